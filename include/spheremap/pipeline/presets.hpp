// Named sets of options (stage: pipeline): `--preset paper|fast` of the command line, defined here so
// that every front end (the CLI, a future Python module) gets the same settings.
#pragma once

#include <string_view>

#include "spheremap/pipeline/map_job.hpp"

namespace spheremap {

enum class Preset {
  kNone,
  /// The paper's settings for reproduction: probe 1.8 Å, Bondi radii (the default), grid 2.5 Å (3,000-
  /// 8,000 triangles for the paper's proteins with our contouring), the binary inside/outside grid
  /// contoured at 1/2 (every vertex at the midpoint of its edge, as the paper does), the contour mapped
  /// as it is (no simplification).
  kPaper,
  /// A quick look: a 1 Å grid (areas about 1-1.5% below MSMS's), about 2 Å edges on the mapped mesh and
  /// at most 4 equalizing rounds (what that costs and gives: BENCHMARKS.md).
  kFast,
};

inline constexpr double kPaperProbe = 1.8;
inline constexpr double kPaperGrid = 2.5;
inline constexpr double kPaperContourFraction = 0.5;
inline constexpr double kFastGrid = 1.0;
inline constexpr double kFastMeshEdge = 2.0;
inline constexpr int kFastEqualizingRounds = 4;

/// "paper" -> kPaper, "fast" -> kFast, "" -> kNone. Throws InputError for any other name.
Preset parse_preset(std::string_view name);
/// "", "paper", "fast".
const char* to_string(Preset preset);

/// The options a caller set explicitly: a preset leaves them as they are ("explicit options still win").
struct ExplicitOptions {
  bool probe = false;              // surface.probe
  bool grid = false;               // surface.grid
  bool mesh_edge = false;          // simplify.target_edge_length
  bool equalizing_rounds = false;  // map.max_equalizing_rounds
};

/// What the preset is for: a map job, or only a molecular surface (`spheremap surface`, which neither
/// maps nor simplifies unless asked: kFast then sets only the grid).
enum class PresetScope { kMap, kSurface };

/// Sets the options of `preset` in `options`, except those in `given`. kNone changes nothing. Does not
/// throw. A caller that derives other options from these (e.g. simplify.max_error from the edge length)
/// does so after.
void apply_preset(Preset preset, MapJobOptions& options, const ExplicitOptions& given,
                  PresetScope scope = PresetScope::kMap);

}  // namespace spheremap
