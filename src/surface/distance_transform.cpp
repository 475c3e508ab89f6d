#include <algorithm>
#include <cmath>
#include <limits>

#include "parallel.hpp"
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

// A line needs no work when it is all zero (every sample is its own nearest) or all infinite.
bool trivial_line(const double* f, std::int64_t n) {
  const double first = f[0];
  if (first != 0 && first != kInfinity) return false;
  for (std::int64_t q = 1; q < n; ++q)
    if (f[q] != first) return false;
  return true;
}

// Lines of one axis are gathered in blocks of this many neighbouring lines (contiguous in memory along
// axis 0), which keeps the strided passes cache-friendly.
constexpr std::int64_t kBlock = 16;

}  // namespace

template <typename T>
void squared_distance_transform_in_place(Grid3<T>& grid, int threads) {
  const auto [nx, ny, nz] = grid.size;
  if (nx <= 0 || ny <= 0 || nz <= 0) return;
  const int workers = detail::surface_threads(threads);
  T* values = grid.values.data();
  const std::int64_t plane = nx * ny;
  struct Scratch {
    std::vector<std::int64_t> v;
    std::vector<double> z, in, out;
  };
  std::vector<Scratch> scratch(static_cast<std::size_t>(workers));
  const std::int64_t longest = std::max({nx, ny, nz});
  for (auto& s : scratch) s.in.resize(static_cast<std::size_t>(longest * kBlock)), s.out.resize(static_cast<std::size_t>(longest));

  // Axis 0: contiguous rows, one chunk per plane k.
  detail::parallel_chunks(nz, workers, [&](std::int64_t k, int worker) {
    auto& s = scratch[static_cast<std::size_t>(worker)];
    for (std::int64_t j = 0; j < ny; ++j) {
      T* row = values + k * plane + j * nx;
      for (std::int64_t q = 0; q < nx; ++q) s.in[q] = static_cast<double>(row[q]);
      if (trivial_line(s.in.data(), nx)) continue;
      transform_line(s.in.data(), s.out.data(), nx, s.v, s.z);
      for (std::int64_t q = 0; q < nx; ++q) row[q] = static_cast<T>(s.out[q]);
    }
  });
  // Axis 1 (stride nx) and axis 2 (stride nx * ny): kBlock neighbouring lines at a time.
  auto pass = [&](std::int64_t n, std::int64_t stride, std::int64_t outer_count, auto&& start_of) {
    const std::int64_t blocks_per_outer = (nx + kBlock - 1) / kBlock;
    detail::parallel_chunks(outer_count, workers, [&](std::int64_t outer, int worker) {
      auto& s = scratch[static_cast<std::size_t>(worker)];
      for (std::int64_t b = 0; b < blocks_per_outer; ++b) {
        const std::int64_t i0 = b * kBlock, width = std::min(kBlock, nx - i0);
        T* base = values + start_of(outer) + i0;
        for (std::int64_t q = 0; q < n; ++q)
          for (std::int64_t w = 0; w < width; ++w) s.in[w * n + q] = static_cast<double>(base[q * stride + w]);
        for (std::int64_t w = 0; w < width; ++w) {
          const double* line = s.in.data() + w * n;
          if (trivial_line(line, n)) continue;
          transform_line(line, s.out.data(), n, s.v, s.z);
          for (std::int64_t q = 0; q < n; ++q) base[q * stride + w] = static_cast<T>(s.out[q]);
        }
      }
    });
  };
  pass(ny, nx, nz, [&](std::int64_t k) { return k * plane; });
  pass(nz, plane, ny, [&](std::int64_t j) { return j * nx; });
}

template void squared_distance_transform_in_place<double>(Grid3<double>&, int);
template void squared_distance_transform_in_place<float>(Grid3<float>&, int);

Grid3<double> squared_distance_transform(const Grid3<std::uint8_t>& is_target, int threads) {
  Grid3<double> out;
  out.size = is_target.size;
  out.origin = is_target.origin;
  out.spacing = is_target.spacing;
  out.values.resize(is_target.values.size());
  for (std::size_t s = 0; s < out.values.size(); ++s) out.values[s] = is_target.values[s] ? 0.0 : kInfinity;
  squared_distance_transform_in_place(out, threads);
  return out;
}

}  // namespace spheremap
