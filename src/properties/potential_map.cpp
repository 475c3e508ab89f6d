// Trilinear interpolation of a potential map.
#include "spheremap/properties/potential_map.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {

std::vector<double> interpolate_dx(const DxGrid& grid, const std::vector<Vec3>& points, const std::string& name) {
  // Grid coordinates u of p: p = origin + Σ u_a delta[a]; the inverse of the delta matrix by cofactors.
  const auto& d = grid.delta;
  const double det = dot(d[0], cross(d[1], d[2]));
  const std::array<Vec3, 3> inverse_rows = {(1 / det) * cross(d[1], d[2]), (1 / det) * cross(d[2], d[0]),
                                            (1 / det) * cross(d[0], d[1])};
  std::vector<double> values(points.size());
  std::int64_t outside = 0;
  double farthest = 0;
  Vec3 farthest_point{};
  for (std::size_t p = 0; p < points.size(); ++p) {
    const Vec3 offset = points[p] - grid.origin;
    std::array<double, 3> u{}, fraction{};
    std::array<std::int64_t, 3> base{};
    double excess_squared = 0;
    for (int a = 0; a < 3; ++a) {
      u[a] = dot(inverse_rows[a], offset);
      const double last = static_cast<double>(grid.counts[a] - 1), slack = 1e-9 * last;
      const double excess = u[a] < -slack ? -u[a] : u[a] > last + slack ? u[a] - last : 0.0;
      excess_squared += excess * excess * dot(d[a], d[a]);
      const double clamped = std::clamp(u[a], 0.0, last);
      base[a] = std::min(static_cast<std::int64_t>(clamped), grid.counts[a] - 2);
      fraction[a] = clamped - static_cast<double>(base[a]);
    }
    if (excess_squared > 0) {
      ++outside;
      if (std::sqrt(excess_squared) > farthest) farthest = std::sqrt(excess_squared), farthest_point = points[p];
      continue;
    }
    double value = 0;
    for (int corner = 0; corner < 8; ++corner) {
      double weight = 1;
      std::array<std::int64_t, 3> index{};
      for (int a = 0; a < 3; ++a) {
        const bool up = (corner >> a) & 1;
        index[a] = base[a] + (up ? 1 : 0);
        weight *= up ? fraction[a] : 1 - fraction[a];
      }
      value +=
          weight *
          grid.values[static_cast<std::size_t>((index[0] * grid.counts[1] + index[1]) * grid.counts[2] + index[2])];
    }
    values[p] = value;
  }
  if (outside > 0)
    throw InputError(
        fmt::format("{}: {} of the {} points where the potential is wanted lie outside the map's grid, the "
                    "farthest {:.2f} Å outside, at ({:.3f}, {:.3f}, {:.3f}); the map must cover the "
                    "surface and the offset: compute it on a larger grid (APBS: larger fglen and cglen, "
                    "e.g. the molecule's extent + 20 Å)",
                    name, outside, points.size(), farthest, farthest_point[0], farthest_point[1], farthest_point[2]));
  return values;
}

}  // namespace spheremap
