// Private to the topology stage: a switch of simplify_surface (simplify.cpp) that tests turn off to
// compare against the plain algorithm.
#pragma once

namespace spheremap::detail {

/// Whether the flip passes skip an edge whose angle test failed while neither triangle on it has changed
/// since (positions never move, so it would fail again). Off, every edge is tested on every pass: the
/// result must be the same, only slower.
inline bool& simplify_skips_known_unflippable_edges() {
  static bool skip = true;
  return skip;
}

}  // namespace spheremap::detail
