// Test helper: OpenDX maps written as APBS writes them, for the reader's and the interpolation's tests.
#pragma once

#include <unistd.h>

#include <array>
#include <filesystem>
#include <fstream>
#include <string>

#include <fmt/format.h>

#include "spheremap/mesh.hpp"

namespace spheremap::testing_support {

inline std::filesystem::path temporary(const std::string& name) {
  return std::filesystem::temp_directory_path() / fmt::format("spheremap-dx-{}-{}", ::getpid(), name);
}

// A map in APBS's layout (3 values a line, z fastest) of f at the grid points.
template <typename F>
std::string dx_text(std::array<int, 3> n, const Vec3& origin, const std::array<Vec3, 3>& delta, F f) {
  std::string text = "# Data from APBS 3.4.1\n# \n# POTENTIAL (kT/e)\n# \n";
  text += fmt::format("object 1 class gridpositions counts {} {} {}\n", n[0], n[1], n[2]);
  text += fmt::format("origin {:e} {:e} {:e}\n", origin[0], origin[1], origin[2]);
  for (const auto& d : delta) text += fmt::format("delta {:e} {:e} {:e}\n", d[0], d[1], d[2]);
  text += fmt::format("object 2 class gridconnections counts {} {} {}\n", n[0], n[1], n[2]);
  text += fmt::format("object 3 class array type double rank 0 items {} data follows\n", n[0] * n[1] * n[2]);
  int column = 0;
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k) {
        Vec3 p = origin;
        for (int a = 0; a < 3; ++a) p[a] += i * delta[0][a] + j * delta[1][a] + k * delta[2][a];
        text += fmt::format("{}{}", fmt::format("{:.17g}", f(p)), ++column % 3 == 0 ? "\n" : " ");
      }
  if (column % 3 != 0) text += "\n";
  text +=
      "attribute \"dep\" string \"positions\"\nobject \"regular positions regular connections\" class field\n"
      "component \"positions\" value 1\ncomponent \"connections\" value 2\ncomponent \"data\" value 3\n";
  return text;
}

inline std::filesystem::path write_dx(const std::string& name, const std::string& text) {
  const auto path = temporary(name);
  std::ofstream(path) << text;
  return path;
}

inline double linear(const Vec3& p) { return 0.75 * p[0] - 1.25 * p[1] + 2.5 * p[2] - 3; }

}  // namespace spheremap::testing_support
