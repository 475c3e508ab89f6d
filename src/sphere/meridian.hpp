// Private to the sphere stage: the boundary meridian, the cut from the north ring to the south ring
// along which φ jumps from 2π to 0.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/topology/connectivity.hpp"

namespace spheremap::detail {

struct Meridian {
  std::vector<std::int32_t> path;  // from a north-ring vertex to a south-ring vertex
  bool by_descent = true;          // false: the shortest-path fallback
  bool kept = false;               // the `kept` path was reused
};

/// The boundary meridian for harmonic z (z = +Z on the north ring, -Z on the south ring). In order of
/// preference: `kept` (the path of an earlier round) if z strictly decreases along it; a steepest descent
/// in the strict total order (z, index) from a north-ring vertex (those whose first step is lowest first),
/// so that ties cannot stall or loop and no edge joins two non-consecutive path vertices; and when every
/// descent stalls at an interior minimum (possible only with weights that can be negative, cotangent),
/// a breadth-first shortest path from ring to ring, which has no chord either (a chord would shorten it).
/// Neither pole, and no north-ring vertex but the first, is on the path.
/// Preconditions: z.size() == rings.vertex_count(); north and south are vertices at least 4 edges apart,
/// so their rings are disjoint and not adjacent. Throws std::logic_error if no path joins the rings
/// (the mesh is then not connected, against prepare_mesh's guarantee).
Meridian boundary_meridian(const VertexRings& rings, const std::vector<double>& z, std::int32_t north,
                           std::int32_t south, const std::vector<std::int32_t>* kept = nullptr);

}  // namespace spheremap::detail
