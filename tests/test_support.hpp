// Checks shared by several test files.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <utility>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap::testing_support {

/// The structure files of `pdb`/paper77 and `pdb`/misc (../shared/data/pdb), sorted by path.
inline std::vector<std::filesystem::path> shared_structure_files(const std::filesystem::path& pdb) {
  std::vector<std::filesystem::path> files;
  for (const char* set : {"paper77", "misc"})
    for (const auto& entry : std::filesystem::directory_iterator(pdb / set)) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

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
