#include "outside_depth.hpp"

#include <algorithm>
#include <cstddef>
#include <limits>

#include "../util/parallel.hpp"

namespace spheremap::detail {
namespace {

// One line of a squared distance transform: d[q] = min(cap, min_p (q - p)² + f[p]) (Felzenszwalb &
// Huttenlocher's lower envelope of parabolas). Samples at the cap cannot lower any result below it, so
// they are left out of the envelope: far from the solid most lines have few others.
void envelope_line(const double* f, double* d, std::int64_t n, double cap, std::vector<std::int64_t>& v,
                   std::vector<double>& z) {
  v.resize(static_cast<std::size_t>(n));
  z.resize(static_cast<std::size_t>(n) + 1);
  auto meet = [&](std::int64_t p, std::int64_t q) {  // where the parabolas rooted at p < q cross
    return ((f[q] + static_cast<double>(q * q)) - (f[p] + static_cast<double>(p * p))) /
           (2.0 * static_cast<double>(q - p));
  };
  std::int64_t k = -1;
  for (std::int64_t q = 0; q < n; ++q) {
    if (f[q] >= cap) continue;
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -std::numeric_limits<double>::infinity();
      z[1] = std::numeric_limits<double>::infinity();
      continue;
    }
    double s = meet(v[k], q);
    while (s <= z[k]) s = meet(v[--k], q);  // ends at k = 0 at the latest: z[0] = -infinity
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  if (k < 0) {
    std::fill(d, d + n, cap);
    return;
  }
  std::int64_t j = 0;
  for (std::int64_t q = 0; q < n; ++q) {
    while (z[j + 1] < static_cast<double>(q)) ++j;
    const double offset = static_cast<double>(q - v[j]);
    d[q] = std::min(cap, offset * offset + f[v[j]]);
  }
}

std::uint16_t capped(double d) { return static_cast<std::uint16_t>(std::min(d, static_cast<double>(kDepthCap))); }

// Along x: the distance to the nearest inside sample of the row.
template <typename T>
void rows_along_x(const Grid3<T>& field, double level, int threads, std::vector<std::uint16_t>& depth) {
  const std::int64_t nx = field.size[0], ny = field.size[1], nz = field.size[2];
  parallel_chunks(nz, threads, [&](std::int64_t k, int) {
    for (std::int64_t j = 0; j < ny; ++j) {
      const std::int64_t row = nx * (j + ny * k);
      const T* values = field.values.data() + row;
      std::uint16_t* out = depth.data() + row;
      constexpr std::int64_t kFar = std::int64_t{1} << 20;
      std::int64_t last = -kFar;
      for (std::int64_t i = 0; i < nx; ++i) {
        if (static_cast<double>(values[i]) > level) last = i;
        const double gap = static_cast<double>(i - last);
        out[i] = capped(gap * gap);
      }
      std::int64_t next = nx + kFar;
      for (std::int64_t i = nx - 1; i >= 0; --i) {
        if (static_cast<double>(values[i]) > level) next = i;
        const double gap = static_cast<double>(next - i);
        out[i] = std::min(out[i], capped(gap * gap));
      }
    }
  });
}

// One pass of the transform along another axis: `planes` chunks (at plane_stride), each of `lines` lines
// (at line_stride) of `length` samples (at `stride`), gathered kBlock lines at a time (neighbours along x)
// for cache-friendly strides. Capping every pass at kDepthCap keeps every value below the cap exact (a
// capped input only ever yields results at or above the cap).
void lines_along(std::vector<std::uint16_t>& depth, int threads, std::int64_t length, std::int64_t stride,
                 std::int64_t planes, std::int64_t plane_stride, std::int64_t lines, std::int64_t line_stride) {
  constexpr std::int64_t kBlock = 16;
  std::vector<std::vector<double>> in(static_cast<std::size_t>(surface_threads(threads))), out(in.size());
  std::vector<std::vector<std::int64_t>> vs(in.size());
  std::vector<std::vector<double>> zs(in.size());
  parallel_chunks(planes, threads, [&](std::int64_t plane, int worker) {
    auto& f = in[static_cast<std::size_t>(worker)];
    auto& d = out[static_cast<std::size_t>(worker)];
    f.resize(static_cast<std::size_t>(kBlock * length));
    d.resize(f.size());
    for (std::int64_t first = 0; first < lines; first += kBlock) {
      const std::int64_t count = std::min(kBlock, lines - first);
      const std::int64_t base = plane * plane_stride + first * line_stride;
      for (std::int64_t q = 0; q < length; ++q)
        for (std::int64_t b = 0; b < count; ++b)
          f[static_cast<std::size_t>(b * length + q)] =
              depth[static_cast<std::size_t>(base + b * line_stride + q * stride)];
      for (std::int64_t b = 0; b < count; ++b) {
        const double* line = f.data() + b * length;
        // A line that is all zero or all at the cap needs no work.
        bool trivial = line[0] == 0 || line[0] == kDepthCap;
        for (std::int64_t q = 1; q < length && trivial; ++q) trivial = line[q] == line[0];
        if (trivial) {
          std::copy(line, line + length, d.data() + b * length);
          continue;
        }
        envelope_line(line, d.data() + b * length, length, kDepthCap, vs[static_cast<std::size_t>(worker)],
                      zs[static_cast<std::size_t>(worker)]);
      }
      for (std::int64_t q = 0; q < length; ++q)
        for (std::int64_t b = 0; b < count; ++b)
          depth[static_cast<std::size_t>(base + b * line_stride + q * stride)] =
              capped(d[static_cast<std::size_t>(b * length + q)]);
    }
  });
}

}  // namespace

template <typename T>
std::vector<std::uint16_t> outside_depth(const Grid3<T>& field, double level, int threads) {
  const std::int64_t nx = field.size[0], ny = field.size[1], nz = field.size[2];
  std::vector<std::uint16_t> depth(static_cast<std::size_t>(field.count()));
  rows_along_x(field, level, threads, depth);
  lines_along(depth, threads, ny, nx, nz, nx * ny, nx, 1);  // along y: planes k, lines i
  lines_along(depth, threads, nz, nx * ny, ny, nx, nx, 1);  // along z: planes j, lines i
  return depth;
}

template std::vector<std::uint16_t> outside_depth(const Grid3<double>&, double, int);
template std::vector<std::uint16_t> outside_depth(const Grid3<float>&, double, int);

}  // namespace spheremap::detail
