// The presets of the library (--preset paper|fast): what each sets, and that explicit options win.
#include "spheremap/pipeline/presets.hpp"

#include <gtest/gtest.h>

#include <ostream>

#include "spheremap/error.hpp"

namespace spheremap {
namespace {

// The settings a preset may change, but the contour fraction.
struct Settings {
  double probe, grid, mesh_edge;
  int equalizing_rounds;
  friend bool operator==(const Settings&, const Settings&) = default;
  friend std::ostream& operator<<(std::ostream& out, const Settings& s) {
    return out << "probe " << s.probe << ", grid " << s.grid << ", mesh edge " << s.mesh_edge << ", rounds "
               << s.equalizing_rounds;
  }
};

Settings settings_of(const MapJobOptions& o) {
  return {o.surface.probe, o.surface.grid, o.simplify.target_edge_length, o.map.max_equalizing_rounds};
}

Settings after(Preset preset, MapJobOptions options, const ExplicitOptions& given,
               PresetScope scope = PresetScope::kMap) {
  apply_preset(preset, options, given, scope);
  return settings_of(options);
}

TEST(Presets, ParseByName) {
  EXPECT_EQ(parse_preset(""), Preset::kNone);
  EXPECT_EQ(parse_preset("paper"), Preset::kPaper);
  EXPECT_EQ(parse_preset("fast"), Preset::kFast);
  EXPECT_THROW(parse_preset("Paper"), InputError);
  for (const Preset p : {Preset::kNone, Preset::kPaper, Preset::kFast}) EXPECT_EQ(parse_preset(to_string(p)), p);
}

TEST(Presets, PaperSetsTheSurfaceOfThePaperAndNoSimplification) {
  const int rounds = MapOptions{}.max_equalizing_rounds;
  EXPECT_EQ(after(Preset::kPaper, {}, {}), (Settings{kPaperProbe, kPaperGrid, 0, rounds}));
  MapJobOptions options;
  apply_preset(Preset::kPaper, options, {});
  EXPECT_EQ(options.surface.contour_minimum_fraction, kPaperContourFraction);
}

TEST(Presets, FastSetsGridEdgesAndRoundsOnlyForAMap) {
  const double probe = SurfaceOptions{}.probe;
  EXPECT_EQ(after(Preset::kFast, {}, {}), (Settings{probe, kFastGrid, kFastMeshEdge, kFastEqualizingRounds}));
  MapJobOptions surface;
  surface.simplify.target_edge_length = 0;
  EXPECT_EQ(after(Preset::kFast, surface, {}, PresetScope::kSurface),
            (Settings{probe, kFastGrid, 0, MapOptions{}.max_equalizing_rounds}));
}

TEST(Presets, ExplicitOptionsStillWin) {
  MapJobOptions options;
  options.surface.probe = 1.2;
  options.surface.grid = 0.7;
  options.simplify.target_edge_length = 3;
  options.map.max_equalizing_rounds = 9;
  const ExplicitOptions given{.probe = true, .grid = true, .mesh_edge = true, .equalizing_rounds = true};
  for (const Preset preset : {Preset::kPaper, Preset::kFast})
    EXPECT_EQ(after(preset, options, given), settings_of(options)) << to_string(preset);
  EXPECT_EQ(after(Preset::kNone, options, {}), settings_of(options));
}

}  // namespace
}  // namespace spheremap
