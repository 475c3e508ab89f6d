// The viewer in real browsers: headless Chromium, and Firefox in a window of Xvfb (headless Firefox has no
// WebGL without a GPU), each open a generated index.html from file://, draw both views, name the residue
// under the pointer on either view and mark the point on both, find a residue, and colour values by the same
// rule as the C++ scales. Each test is skipped (visibly) when its browser is absent.
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <string>

#include <nlohmann/json.hpp>

#include "spheremap/render/viewer.hpp"
#include "viewer_test_map.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

constexpr const char* kChromium = "/usr/bin/chromium";
constexpr const char* kFirefox = "/usr/bin/firefox-esr";
constexpr const char* kXvfbRun = "/usr/bin/xvfb-run";

std::string residue_label(const ViewerAtom& a) {
  return a.chain + ":" + a.residue_name + " " + std::to_string(a.residue_number) + a.insertion_code;
}

nlohmann::json hover(const ViewerData& data, const char* view, std::int32_t vertex) {
  const ViewerAtom& a = data.atoms[data.vertex_atoms[vertex]];
  return {{"view", view}, {"vertex", vertex}, {"residue", residue_label(a)}, {"atom", a.atom_name}};
}

// Values at and around the bin edges of two ranges, the ends, out of range, NaN, and categorical halves.
nlohmann::json colour_checks() {
  nlohmann::json checks = nlohmann::json::array();
  const auto add = [&](ScaleKind kind, ValueRange r, double value) {
    checks.push_back({{"scale", std::string(to_string(kind))},
                      {"lo", r.lo},
                      {"hi", r.hi},
                      {"value", value},
                      {"index", colour_index(kind, r, value)}});
  };
  for (const ScaleKind kind : {ScaleKind::sequential, ScaleKind::diverging, ScaleKind::categorical})
    for (const ValueRange r : {ValueRange{-2, 2.5}, ValueRange{0.1, 0.7}, ValueRange{1, 1}}) {
      for (int k = 0; k <= kColourTableSize; k += 5) {
        const double edge = r.lo + (r.hi - r.lo) * k / kColourTableSize;
        for (const double v : {edge, std::nextafter(edge, -1e300), std::nextafter(edge, 1e300)}) add(kind, r, v);
      }
      for (const double v :
           {-1e300, 1e300, -0.5, 0.5, 2.5, 254.5, 255.5, 256.0, 7.0, std::numeric_limits<double>::quiet_NaN()})
        add(kind, r, v);
    }
  return checks;
}

// Writes a test map's index.html into SPHEREMAP_VIEWER_TEST_OUTPUT_DIR/<browser>/ and runs
// viewer_browser_test.mjs on it in that browser; `prefix` goes before the node command (e.g. xvfb-run).
void run_in_browser(const std::string& browser, const std::string& executable, const std::string& prefix) {
  const fs::path out = fs::path(SPHEREMAP_VIEWER_TEST_OUTPUT_DIR) / browser;
  fs::create_directories(out);
  ViewerData data = testing_support::make_viewer_test_map(4, 120);
  data.title = "test map </script> \"quoted\" & 'single' \xc3\x85";  // escaping, seen from the browser
  const std::int32_t apex = testing_support::highest_vertex(data);
  // On the sphere: the vertex nearest a direction in plain view from +z, on another residue than the apex.
  const Vec3 towards{0.35, -0.3, 0.89};
  std::int32_t on_sphere = 0;
  for (std::size_t v = 1; v < data.sphere_positions.size(); ++v)
    if (testing_support::dot3(data.sphere_positions[v], towards) >
        testing_support::dot3(data.sphere_positions[on_sphere], towards))
      on_sphere = static_cast<std::int32_t>(v);
  ASSERT_NE(data.vertex_atoms[on_sphere] / 5, data.vertex_atoms[apex] / 5);
  write_viewer_html(out / "index.html", data);

  const ViewerAtom& searched = data.atoms[data.vertex_atoms[apex]];
  int in_residue = 0;
  for (const std::int32_t a : data.vertex_atoms)
    in_residue += data.atoms[a].chain == searched.chain && data.atoms[a].residue_number == searched.residue_number;
  const nlohmann::json spec{
      {"html", (out / "index.html").string()},
      {"browser", browser},
      {"executable", executable},
      {"nodeModules", SPHEREMAP_VIEWER_NODE_MODULES},
      {"outputDir", out.string()},
      {"title", data.title},
      {"hovers", {hover(data, "surface", apex), hover(data, "sphere", on_sphere)}},
      {"search",
       {{"query", searched.chain + ":" + std::to_string(searched.residue_number)}, {"highlighted", in_residue}}},
      {"colourChecks", colour_checks()}};
  std::ofstream(out / "spec.json") << spec.dump(1);

  const std::string command = prefix + SPHEREMAP_NODE_EXECUTABLE + " " + SPHEREMAP_VIEWER_BROWSER_SCRIPT + " " +
                              (out / "spec.json").string() + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string output;
  char buffer[4096];
  while (std::fgets(buffer, sizeof buffer, pipe) != nullptr) output += buffer;
  const int status = pclose(pipe);
  std::cout << output;
  EXPECT_EQ(status, 0) << output;
}

TEST(ViewerBrowser, DrawsPicksAndSearchesInHeadlessChromium) {
  if (!fs::exists(kChromium))
    GTEST_SKIP() << "no Chromium at " << kChromium << ": the browser test needs Debian's chromium "
                 << "(scripts/install-deps.sh installs it)";
  run_in_browser("chromium", kChromium, "");
}

TEST(ViewerBrowser, DrawsPicksAndSearchesInFirefox) {
  if (!fs::exists(kFirefox) || !fs::exists(kXvfbRun))
    GTEST_SKIP() << "no Firefox at " << kFirefox << " or no " << kXvfbRun << ": the browser test needs Debian's "
                 << "firefox-esr and xvfb (scripts/install-deps.sh installs them)";
  run_in_browser("firefox", kFirefox, std::string(kXvfbRun) + " -a -s '-screen 0 1600x900x24' ");
}

}  // namespace
}  // namespace spheremap
