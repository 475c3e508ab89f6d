// Private to the sphere stage: the optimization of a certified map for MapOptions::objective.
#pragma once

#include "../util/stage_timer.hpp"
#include "finish.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/sphere/map.hpp"

namespace spheremap::detail {

/// Optimizes `finished` (a map of `mesh`, superposed) for options.objective with `north` and `south`
/// fixed, in the frame before the superposition, then superposes and certifies the result again; it
/// replaces `finished` only if it is certified. Does nothing for kPaper; an uncertified `finished` is
/// left as it is. Fills `report`; laps "objective" on `timer`.
/// Preconditions: `finished` is of `mesh`, `input` built on `mesh`; north and south are vertices of `mesh`.
void optimize_for_objective(const Mesh& mesh, InputStars& input, std::int32_t north, std::int32_t south,
                            const MapOptions& options, Finished& finished, ObjectiveReport& report, StageTimer& timer);

}  // namespace spheremap::detail
