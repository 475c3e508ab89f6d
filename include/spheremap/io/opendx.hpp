// OpenDX potential maps as APBS writes them (`write pot dx`).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// A scalar field on a regular grid: the value of grid point (i, j, k) is at origin + i delta[0] +
/// j delta[1] + k delta[2], stored at values[(i * counts[1] + j) * counts[2] + k] (z fastest, as OpenDX).
struct DxGrid {
  std::array<std::int64_t, 3> counts{};
  Vec3 origin{};
  std::array<Vec3, 3> delta{};
  std::vector<double> values;
};

/// Reads an OpenDX file of APBS's layout: '#' comments, `object 1 class gridpositions counts nx ny nz`,
/// `origin x y z`, three `delta` lines, optionally `object 2 class gridconnections counts nx ny nz`, then
/// `object 3 class array type double rank 0 items N data follows` and N numbers (any number per line);
/// what follows the data (attribute, field objects) is not read.
/// Throws InputError naming the file, the line and the problem (a missing or malformed header line,
/// counts below 2 or N != nx ny nz, a singular delta matrix, a value that is not a finite number, fewer
/// values than N, or more before the next keyword).
DxGrid read_dx(const std::filesystem::path& path);

}  // namespace spheremap
