#include <algorithm>
#include <cmath>
#include <limits>

#include "spheremap/surface/grid.hpp"

namespace spheremap {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One line: d[q] = min_p (q - p)² + f[p], by the lower envelope of the parabolas rooted at each p.
void transform_line(const double* f, double* d, std::int64_t n, std::vector<std::int64_t>& v, std::vector<double>& z) {
  v.resize(static_cast<std::size_t>(n));
  z.resize(static_cast<std::size_t>(n) + 1);
  std::int64_t k = -1;
  for (std::int64_t q = 0; q < n; ++q) {
    if (f[q] == kInfinity) continue;
    while (k >= 0) {
      const auto p = v[k];
      const double s = ((f[q] + static_cast<double>(q * q)) - (f[p] + static_cast<double>(p * p))) / (2.0 * static_cast<double>(q - p));
      if (s <= z[k]) {
        --k;
      } else {
        break;
      }
    }
    ++k;
    v[k] = q;
    z[k] = k == 0 ? -kInfinity : ((f[q] + static_cast<double>(q * q)) - (f[v[k - 1]] + static_cast<double>(v[k - 1] * v[k - 1]))) /
                                     (2.0 * static_cast<double>(q - v[k - 1]));
    z[k + 1] = kInfinity;
  }
  if (k < 0) {
    for (std::int64_t q = 0; q < n; ++q) d[q] = kInfinity;
    return;
  }
  std::int64_t j = 0;
  for (std::int64_t q = 0; q < n; ++q) {
    while (z[j + 1] < static_cast<double>(q)) ++j;
    const double offset = static_cast<double>(q - v[j]);
    d[q] = offset * offset + f[v[j]];
  }
}

}  // namespace

Grid3<double> squared_distance_transform(const Grid3<std::uint8_t>& is_target) {
  Grid3<double> out;
  out.size = is_target.size;
  out.origin = is_target.origin;
  out.spacing = is_target.spacing;
  out.values.resize(is_target.values.size());
  for (std::size_t s = 0; s < out.values.size(); ++s) out.values[s] = is_target.values[s] ? 0.0 : kInfinity;
  const auto [nx, ny, nz] = is_target.size;
  std::vector<std::int64_t> v;
  std::vector<double> z;
  const std::int64_t longest = std::max({nx, ny, nz});
  std::vector<double> line_in(static_cast<std::size_t>(longest)), line_out(static_cast<std::size_t>(longest));
  // Pass along each axis in turn; the result after all three is the exact 3D squared distance.
  for (int axis = 0; axis < 3; ++axis) {
    const std::int64_t n = is_target.size[axis];
    const std::int64_t stride = axis == 0 ? 1 : axis == 1 ? nx : nx * ny;
    const std::int64_t lines = out.count() / n;
    for (std::int64_t line = 0; line < lines; ++line) {
      // The first sample of the line: enumerate the two other axes.
      std::int64_t start;
      if (axis == 0) start = line * nx;
      else if (axis == 1) start = (line % nx) + (line / nx) * nx * ny;
      else start = line;
      for (std::int64_t q = 0; q < n; ++q) line_in[q] = out.values[start + q * stride];
      transform_line(line_in.data(), line_out.data(), n, v, z);
      for (std::int64_t q = 0; q < n; ++q) out.values[start + q * stride] = line_out[q];
    }
  }
  return out;
}

}  // namespace spheremap
