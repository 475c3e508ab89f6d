// What the handle repair changes: closures, each a cut or a fill (glossary: handle_repair.hpp).
#pragma once

#include <cstdint>
#include <vector>

namespace spheremap {

/// Which way a closure moves its samples across the level.
enum class ClosureKind {
  kCut,   ///< inside samples made outside: a handle cut through
  kFill,  ///< outside samples made inside: a tunnel spanned
};

/// "cut" or "fill": the text of report.json's `changes[].kind`.
const char* to_string(ClosureKind kind);

/// A set of grid samples moved across the level to remove handles: half a grid step past it, below for a
/// cut and above for a fill, as if the surface ran along their voxels' faces.
struct Closure {
  ClosureKind kind = ClosureKind::kCut;
  std::vector<std::int64_t> samples;    // grid indices, ascending
  std::vector<double> original_values;  // the field at `samples` before (for undo); empty from close_all_handles
  /// Handles removed: the change of the solid's Euler characteristic (repair_handles); for the global
  /// closure of repair_outer_genus the outer genus before; 0 from close_all_handles.
  int handles_removed = 0;
  /// Change of the contour's area (all components) that this closure made, on the field as it was when it
  /// was applied (closures are applied in order): the closures' areas add up to the contour's change.
  double area_change = 0;
};

}  // namespace spheremap
