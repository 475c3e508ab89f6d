// The presets: paper (reproduction) and fast (a quick look).
#include "spheremap/pipeline/presets.hpp"

#include <fmt/format.h>

#include "spheremap/error.hpp"

namespace spheremap {

Preset parse_preset(std::string_view name) {
  if (name.empty()) return Preset::kNone;
  if (name == "paper") return Preset::kPaper;
  if (name == "fast") return Preset::kFast;
  throw InputError(fmt::format("--preset '{}': expected paper or fast", name));
}

const char* to_string(Preset preset) {
  constexpr const char* kNames[] = {"", "paper", "fast"};  // in the order of the enum
  return kNames[static_cast<int>(preset)];
}

void apply_preset(Preset preset, MapJobOptions& options, const ExplicitOptions& given, PresetScope scope) {
  if (preset == Preset::kPaper) {
    if (!given.probe) options.surface.probe = kPaperProbe;
    if (!given.grid) options.surface.grid = kPaperGrid;
    options.surface.contour_minimum_fraction = kPaperContourFraction;
    if (!given.mesh_edge) options.simplify.target_edge_length = 0;  // the paper maps its contour as it is
  }
  if (preset == Preset::kFast) {
    if (!given.grid) options.surface.grid = kFastGrid;
    if (scope == PresetScope::kMap) {
      if (!given.equalizing_rounds) options.map.max_equalizing_rounds = kFastEqualizingRounds;
      if (!given.mesh_edge) options.simplify.target_edge_length = kFastMeshEdge;
    }
  }
}

}  // namespace spheremap
