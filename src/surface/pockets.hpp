// Private to the surface stage: the reachability of grid samples while the SES field is built. Samples
// inside the SAS are marked; the outside samples the lattice joins to the grid border are reached, the
// others are numbered pockets, resolved later by the SAS's exposed arcs (probe_centres.hpp).
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

#include "spheremap/molecule/structure.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

// Field values while the field is built: probe-centre samples hold 0 (their squared distance), samples
// inside the SAS +infinity; outside samples not (yet) reached from the border hold kUnreached.
inline constexpr double kUnreached = 1;

// Labels of outside samples (not inside the SAS) while reachability is decided: reached from the grid
// border through the lattice (0), or in pocket p = 1, 2, ... (value p + 1): a 6-connected set of outside
// samples that the lattice does not join to the border. Float holds these integers exactly up to 2^24.
inline constexpr std::int64_t kMaximumPockets = (std::int64_t{1} << 23) - 2;

// The reachability label of a sample value during the build: 0 (reached), p (pocket p), or -1 (inside
// the SAS, or a pocket beyond kMaximumPockets).
template <typename T>
inline std::int64_t label_of(T value) {
  if (value == T(0)) return 0;
  if (!(value < std::numeric_limits<T>::infinity())) return -1;
  return static_cast<std::int64_t>(value) - 1;
}

// A run of samples along axis 0 that are all in pocket `label`: [first, first + length).
struct PocketRun {
  std::int64_t first;
  std::int32_t length;
  std::int32_t label;
};

struct Pockets {
  std::int64_t count = 0;
  std::vector<PocketRun> runs;  // every sample labelled as a pocket, in sample order
};

/// Marks inside-the-SAS samples (within radius + probe of an atom's centre) +infinity; every other
/// sample holds kUnreached. Plane k is written by chunk k % threads only. Precondition: threads >= 1.
template <typename T>
void mark_accessible_surface(Grid3<T>& field, const std::vector<Atom>& atoms, double probe, int threads);

/// Outside samples connected to the grid border through the lattice become 0; every other 6-connected set
/// of outside samples (a pocket as far as the lattice can tell) gets its own label, pockets numbered in
/// the order of their first sample (see kMaximumPockets; beyond that many, pockets are +infinity: never
/// carved). Returns the pockets and where their samples are (so that resolving them later touches only
/// those samples, not the whole grid).
///
/// By runs: the outside samples of each row form runs, found plane by plane in parallel; runs that touch
/// (the same row in adjacent planes, or adjacent rows of a plane, with overlapping spans) are joined by
/// union-find (smaller root wins); each set's labels are then written back plane by plane. The sets and
/// their first samples do not depend on the order of the joins, so neither do the labels.
/// Precondition: `field` as mark_accessible_surface left it; threads >= 1.
template <typename T>
Pockets flood_and_label_pockets(Grid3<T>& field, int threads);

}  // namespace spheremap::detail
