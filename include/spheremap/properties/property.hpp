// A surface property: one value per vertex of the mapped mesh, with what a picture or a table needs to
// show it (name, unit, colour scale). The registry that fills them, and every output that shows them
// (PLY, residues.csv, pictures, viewer), share this one type.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace spheremap {

/// How a property's values are coloured.
enum class ScaleKind : std::uint8_t {
  sequential,   // ordered values (B-factor, hydrophobicity, curvature): viridis
  diverging,    // signed values around 0 (electrostatics): red (low) - white - blue (high)
  categorical,  // whole numbers naming classes (chain, octant): one distinct colour per class
  spectrum,     // ordered values shown as the colours of the spectrum, blue (low) to red (high): the paper's
                // sequence-position colouring (Figure 8)
};

/// "sequential", "diverging", "categorical" or "spectrum". Never throws.
std::string_view to_string(ScaleKind kind);

/// The values a continuous colour scale spans: lo gets the first colour, hi the last; values outside saturate.
struct ValueRange {
  double lo = 0;
  double hi = 1;
};

/// What a property is, independent of any one surface.
struct PropertyInfo {
  std::string name;  // e.g. "electrostatics"; PLY property `vertex_<name>`, glTF attribute `_<NAME>`
  std::string unit;  // e.g. "kT/e"; empty for dimensionless values
  ScaleKind scale = ScaleKind::sequential;
  /// The colour range a picture uses unless the user gives one (e.g. -2..2 kT/e for electrostatics, as in
  /// the paper); none: the data's own range.
  std::optional<ValueRange> default_range;
  /// Categorical scales: the name of class k (e.g. chain "A"), where the classes have names.
  std::vector<std::string> categories;
};

/// A property on one surface: values[v] for vertex v of the mapped mesh; NaN where it has no value (never
/// a made-up zero). `source` says where the values came from (e.g. "coulomb, pdb2pqr AMBER charges").
struct SurfaceProperty {
  PropertyInfo info;
  std::string source;
  std::vector<double> values;
};

}  // namespace spheremap
