// Helpers and checks shared by several test files: files, a fresh folder per test, the command line.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/surface/grid.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap::testing_support {

/// An n x n x n grid of `function` at its sample points (spacing, origin as given).
Grid3<double> sample(std::int64_t n, double spacing, const Vec3& origin, auto&& function) {
  Grid3<double> grid;
  grid.size = {n, n, n};
  grid.spacing = spacing;
  grid.origin = origin;
  grid.values.resize(static_cast<std::size_t>(grid.count()));
  for (std::int64_t k = 0; k < n; ++k)
    for (std::int64_t j = 0; j < n; ++j)
      for (std::int64_t i = 0; i < n; ++i) grid.values[grid.index(i, j, k)] = function(grid.point(i, j, k));
  return grid;
}

/// The volume a closed mesh encloses: positive when it is oriented outward.
inline double signed_volume(const Mesh& mesh) {
  double six_volume = 0;
  for (const auto& [a, b, c] : mesh.triangles)
    six_volume += dot(mesh.positions[a], cross(mesh.positions[b], mesh.positions[c]));
  return six_volume / 6;
}

/// Every triangle of `mesh` positively oriented on the sphere `sphere` (exact predicate) and the solid
/// angles summing to 4π: a valid map, checked independently of the certificate's bookkeeping.
inline void expect_valid_on_sphere(const Mesh& mesh, const std::vector<Vec3>& sphere, const std::string& what) {
  std::int64_t negative = 0;
  double solid_angle = 0;
  for (const auto& t : mesh.triangles) {
    negative += orientation_sign(sphere[t[0]], sphere[t[1]], sphere[t[2]]) <= 0;
    solid_angle += signed_solid_angle(sphere[t[0]], sphere[t[1]], sphere[t[2]]);
  }
  EXPECT_EQ(negative, 0) << what;
  EXPECT_NEAR(solid_angle, 4 * std::numbers::pi, 1e-8) << what;
}

/// The bytes of a file ("" if it cannot be read).
inline std::string slurp(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

/// Writes `bytes` to `path`, creating its folder if missing.
inline void write_text(const std::filesystem::path& path, const std::string& bytes) {
  if (path.has_parent_path()) std::filesystem::create_directories(path.parent_path());
  std::ofstream(path, std::ios::binary) << bytes;
}

/// A fixture with a fresh, empty folder of its own (`folder_`, named after the test and the process, so
/// that tests running at once never share one), removed after the test.
class FolderTest : public testing::Test {
 protected:
  void SetUp() override {
    const auto* test = testing::UnitTest::GetInstance()->current_test_info();
    folder_ = std::filesystem::temp_directory_path() / (std::string("spheremap-") + test->test_suite_name() + "-" +
                                                        std::to_string(::getpid()) + "-" + test->name());
    std::filesystem::remove_all(folder_);
    std::filesystem::create_directories(folder_);
  }
  void TearDown() override { std::filesystem::remove_all(folder_); }

  /// Writes `bytes` to folder_/name; returns that path.
  std::filesystem::path write(const std::string& name, const std::string& bytes) const {
    write_text(folder_ / name, bytes);
    return folder_ / name;
  }

  std::filesystem::path folder_;
};

#ifdef SPHEREMAP_CLI_PATH
/// What the command printed (stdout and stderr) and its exit code.
struct CliRun {
  int exit_code;
  std::string output;
};

/// Runs the spheremap command with `arguments` (passed through the shell: quote what needs it).
inline CliRun run_cli(const std::string& arguments) {
  const std::string command = std::string(SPHEREMAP_CLI_PATH) + " " + arguments + " 2>&1";
  FILE* pipe = popen(command.c_str(), "r");
  std::string output;
  char buffer[4096];
  while (std::size_t got = std::fread(buffer, 1, sizeof buffer, pipe)) output.append(buffer, got);
  const int status = pclose(pipe);
  return {WEXITSTATUS(status), output};
}
#endif

#ifdef SPHEREMAP_SHARED_DATA_DIR
/// A fixture over the 88 structure files of ../shared/data/pdb (paper77 and misc) in `files_`, sorted by
/// path; the test is skipped, saying so, when the shared data is absent.
class SharedStructuresTest : public testing::Test {
 protected:
  void SetUp() override {
    const std::filesystem::path pdb = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb";
    if (!std::filesystem::exists(pdb)) GTEST_SKIP() << "shared data not found: " << pdb << " (skipped on purpose)";
    for (const char* set : {"paper77", "misc"})
      for (const auto& entry : std::filesystem::directory_iterator(pdb / set)) files_.push_back(entry.path());
    std::sort(files_.begin(), files_.end());
    ASSERT_EQ(files_.size(), 88u);
  }
  std::vector<std::filesystem::path> files_;
};
#endif

/// Every directed edge once and its reverse once (closed, consistently oriented), and every vertex's
/// triangles one fan (build_vertex_rings throws otherwise).
inline void expect_closed_oriented_manifold(const Mesh& mesh) {
  std::map<std::pair<std::int32_t, std::int32_t>, int> directed;
  for (const auto& t : mesh.triangles)
    for (int s = 0; s < 3; ++s) ++directed[{t[s], t[(s + 1) % 3]}];
  for (const auto& [edge, count] : directed) {
    ASSERT_EQ(count, 1);
    ASSERT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
  EXPECT_NO_THROW(build_vertex_rings(static_cast<std::int32_t>(mesh.vertex_count()), mesh.triangles));
}

}  // namespace spheremap::testing_support
