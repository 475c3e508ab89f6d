#include "area_change.hpp"

#include <algorithm>
#include <array>

#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {
namespace {

constexpr std::array<std::array<int, 3>, 8> kCellCorner = {
    {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}};
constexpr std::array<std::array<int, 4>, 6> kCellTetrahedra = {
    {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};

// The area of contour_isosurface's triangles in one cell (same tetrahedra, same vertex positions).
template <typename T>
double cell_area(const Grid3<T>& field, std::int64_t i, std::int64_t j, std::int64_t k, double level,
                 double minimum_fraction) {
  std::array<double, 8> value{};
  std::array<Vec3, 8> point{};
  for (int c = 0; c < 8; ++c) {
    const auto a = i + kCellCorner[c][0], b = j + kCellCorner[c][1], d = k + kCellCorner[c][2];
    value[c] = static_cast<double>(field.values[static_cast<std::size_t>(field.index(a, b, d))]);
    point[c] = field.point(a, b, d);
  }
  // A vertex on the edge between corners c1 < c2: c1 is the lower sample, as in contour_isosurface.
  auto vertex = [&](int c1, int c2) {
    const int a = std::min(c1, c2), b = std::max(c1, c2);
    const double t = std::clamp((level - value[a]) / (value[b] - value[a]), minimum_fraction, 1 - minimum_fraction);
    return point[a] + t * (point[b] - point[a]);
  };
  double area = 0;
  for (const auto& tet : kCellTetrahedra) {
    std::array<int, 4> in{}, out{};
    int n_in = 0, n_out = 0;
    for (const int v : tet) (value[v] > level ? in[n_in++] : out[n_out++]) = v;
    if (n_in == 0 || n_out == 0) continue;
    if (n_in == 1) {
      area += triangle_area(vertex(in[0], out[0]), vertex(in[0], out[1]), vertex(in[0], out[2]));
    } else if (n_in == 3) {
      area += triangle_area(vertex(in[0], out[0]), vertex(in[1], out[0]), vertex(in[2], out[0]));
    } else {
      const Vec3 a = vertex(in[0], out[0]), b = vertex(in[0], out[1]), c = vertex(in[1], out[1]),
                 d = vertex(in[1], out[0]);
      area += triangle_area(a, b, c) + triangle_area(a, c, d);
    }
  }
  return area;
}

}  // namespace

template <typename T>
double area_change(Grid3<T>& field, double level, double minimum_fraction, const std::vector<std::int64_t>& samples,
                   T value) {
  const auto [nx, ny, nz] = field.size;
  std::vector<std::int64_t> cells;
  cells.reserve(samples.size() * 8);
  for (const auto s : samples) {
    const std::int64_t i = s % nx, j = (s / nx) % ny, k = s / (nx * ny);
    for (std::int64_t dk = -1; dk <= 0; ++dk)
      for (std::int64_t dj = -1; dj <= 0; ++dj)
        for (std::int64_t di = -1; di <= 0; ++di)
          if (i + di >= 0 && j + dj >= 0 && k + dk >= 0 && i + di + 1 < nx && j + dj + 1 < ny && k + dk + 1 < nz)
            cells.push_back(field.index(i + di, j + dj, k + dk));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  auto area = [&] {
    double sum = 0;
    for (const auto c : cells) sum += cell_area(field, c % nx, (c / nx) % ny, c / (nx * ny), level, minimum_fraction);
    return sum;
  };
  const double before = area();
  std::vector<T> original;
  original.reserve(samples.size());
  for (const auto s : samples)
    original.push_back(field.values[static_cast<std::size_t>(s)]), field.values[static_cast<std::size_t>(s)] = value;
  const double after = area();
  for (std::size_t k = 0; k < samples.size(); ++k) field.values[static_cast<std::size_t>(samples[k])] = original[k];
  return after - before;
}

template double area_change(Grid3<double>&, double, double, const std::vector<std::int64_t>&, double);
template double area_change(Grid3<float>&, double, double, const std::vector<std::int64_t>&, float);

}  // namespace spheremap::detail
