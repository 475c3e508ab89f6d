#include "spheremap/surface/distance_transform.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "../util/parallel.hpp"

namespace spheremap {
namespace {

constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One line: d[q] = min_p (q - p)² + f[p], by the lower envelope of the parabolas rooted at each p.
// Envelope entry k: parabola v[k], with f[v[k]] + v[k]² in rooted[k], lowest from z[k] on, where z[k]
// (k > 0) is the fraction numerator[k] / denominator[k] (denominator > 0) and z[0] is -infinity.
// Comparisons cross-multiply instead of dividing: the division's latency sat on the loop's critical
// path. The inputs are integers (squared distances), so the products are exact (below 2^53 for lines
// shorter than 2^15) and every comparison decides exactly as the exact fractions do; so did the
// divisions, whose correctly rounded quotients of such fractions never tie unless the fractions do.
// Zeros inside a run of zeros are left out: every sample outside the run is nearer to an end of it,
// and the run's own samples are 0 (which is what the envelope gives them, the transform being exact).
void transform_line(const double* f, double* d, std::int64_t n, std::vector<std::int64_t>& v,
                    std::vector<double>& numerator, std::vector<double>& denominator, std::vector<double>& rooted) {
  v.resize(static_cast<std::size_t>(n));
  numerator.resize(static_cast<std::size_t>(n));
  denominator.resize(static_cast<std::size_t>(n));
  rooted.resize(static_cast<std::size_t>(n));
  std::int64_t k = -1;
  for (std::int64_t q = 0; q < n; ++q) {
    if (f[q] == kInfinity) continue;
    if (f[q] == 0 && q > 0 && q + 1 < n && f[q - 1] == 0 && f[q + 1] == 0) continue;
    const double here = f[q] + static_cast<double>(q * q);
    double num = 0, den = 1;  // where the new parabola meets entry k's
    while (k >= 0) {
      num = here - rooted[k];
      den = 2.0 * static_cast<double>(q - v[k]);
      if (k == 0 || num * denominator[k] > numerator[k] * den) break;
      --k;
    }
    ++k;
    v[k] = q;
    rooted[k] = here;
    numerator[k] = num;
    denominator[k] = den;
  }
  if (k < 0) {
    for (std::int64_t q = 0; q < n; ++q) d[q] = kInfinity;
    return;
  }
  std::int64_t j = 0;
  for (std::int64_t q = 0; q < n; ++q) {
    const auto at = static_cast<double>(q);
    while (j < k && numerator[j + 1] < at * denominator[j + 1]) ++j;
    const double offset = static_cast<double>(q - v[j]);
    d[q] = f[q] == 0 ? 0.0 : offset * offset + f[v[j]];
  }
}

// What a line needs: nothing when it is all zero (every sample is its own nearest) or all infinite; two
// sweeps when it holds only zeros and infinities (as the first axis of a 0/infinity start does); the
// lower envelope otherwise.
enum class LineKind { kTrivial, kBinary, kGeneral };

LineKind kind_of(const double* f, std::int64_t n) {
  bool zero = false, infinite = false;
  for (std::int64_t q = 0; q < n; ++q) {
    zero |= f[q] == 0;
    infinite |= f[q] == kInfinity;
    if (f[q] != 0 && f[q] != kInfinity) return LineKind::kGeneral;
  }
  return zero && infinite ? LineKind::kBinary : LineKind::kTrivial;
}

// A line of zeros and infinities (some of each): (distance to the nearest zero)², exactly as
// transform_line gives it.
void binary_line(const double* f, double* d, std::int64_t n) {
  std::int64_t last = -1;  // the last zero at or before q
  for (std::int64_t q = 0; q < n; ++q) {
    if (f[q] == 0) last = q;
    d[q] = last < 0 ? kInfinity : static_cast<double>((q - last) * (q - last));
  }
  last = -1;  // the first zero at or after q
  for (std::int64_t q = n - 1; q >= 0; --q) {
    if (f[q] == 0) last = q;
    if (last >= 0) d[q] = std::min(d[q], static_cast<double>((last - q) * (last - q)));
  }
}

// Transforms one line from `in` into `out`: returns the range [first, end) of samples that may change
// (out is written there only; first == end when none). Zeros before the first and after the last
// nonzero value stay zero and only the nearest of each run can be anyone's nearest, so the transform
// runs on what lies between them, which in a molecule's grid is often half the line or less.
std::pair<std::int64_t, std::int64_t> transform_any_line(const double* in, double* out, std::int64_t n,
                                                         std::vector<std::int64_t>& v, std::vector<double>& numerator,
                                                         std::vector<double>& denominator,
                                                         std::vector<double>& rooted) {
  std::int64_t first = 0, end = n;
  while (first < n && in[first] == 0) ++first;
  if (first == n) return {0, 0};  // all zero
  while (in[end - 1] == 0) --end;
  first = std::max<std::int64_t>(0, first - 1), end = std::min(n, end + 1);
  const std::int64_t length = end - first;
  switch (kind_of(in + first, length)) {
    case LineKind::kTrivial: return {0, 0};
    case LineKind::kBinary: binary_line(in + first, out + first, length); break;
    case LineKind::kGeneral: transform_line(in + first, out + first, length, v, numerator, denominator, rooted); break;
  }
  return {first, end};
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
    std::vector<double> numerator, denominator, rooted, in, out;
  };
  std::vector<Scratch> scratch(static_cast<std::size_t>(workers));
  const std::int64_t longest = std::max({nx, ny, nz});
  for (auto& s : scratch)
    s.in.resize(static_cast<std::size_t>(longest * kBlock)), s.out.resize(static_cast<std::size_t>(longest));

  // Zeros stay zero and other values stay nonzero (with f >= 0 a sample's new value is at least the
  // smaller of its old value and 1), so where the nonzero samples lie is known from the start. The first
  // pass records it per block of kBlock neighbouring lines: the range of rows j (per plane k) and of
  // planes k (per row j) holding a nonzero sample. The later passes gather only that range, widened by one sample: the
  // zeros beyond it are nearer to that zero than to anything on the far side, which is what transform_any_line does
  // with them anyway (it reads the whole line only to find them). A block without a nonzero sample is skipped. The
  // result is the same to the last bit.
  const std::int64_t blocks_per_row = (nx + kBlock - 1) / kBlock;
  struct Extent {
    std::int32_t first = std::numeric_limits<std::int32_t>::max(), last = -1;
    void add(std::int64_t at) {
      first = std::min(first, static_cast<std::int32_t>(at));
      last = std::max(last, static_cast<std::int32_t>(at));
    }
    void add(const Extent& other) { first = std::min(first, other.first), last = std::max(last, other.last); }
  };
  std::vector<Extent> rows_of_block(static_cast<std::size_t>(nz * blocks_per_row));  // [k][block]: rows j
  std::vector<std::vector<Extent>> planes_of_block(
      static_cast<std::size_t>(workers));  // per worker, [j][block]: planes k
  for (auto& p : planes_of_block) p.resize(static_cast<std::size_t>(ny * blocks_per_row));

  // Axis 0: contiguous rows, one chunk per plane k.
  detail::parallel_chunks(nz, workers, [&](std::int64_t k, int worker) {
    auto& s = scratch[static_cast<std::size_t>(worker)];
    Extent* rows = rows_of_block.data() + k * blocks_per_row;
    auto& planes = planes_of_block[static_cast<std::size_t>(worker)];
    for (std::int64_t j = 0; j < ny; ++j) {
      T* row = values + k * plane + j * nx;
      for (std::int64_t q = 0; q < nx; ++q) s.in[q] = static_cast<double>(row[q]);
      std::int64_t first = 0, last = nx - 1;
      while (first < nx && s.in[first] == 0) ++first;
      if (first == nx) continue;  // all zero: nothing to do here or along the other axes
      while (s.in[last] == 0) --last;
      for (std::int64_t b = first / kBlock; b <= last / kBlock; ++b)
        rows[b].add(j), planes[static_cast<std::size_t>(j * blocks_per_row + b)].add(k);
      const auto [from, end] =
          transform_any_line(s.in.data(), s.out.data(), nx, s.v, s.numerator, s.denominator, s.rooted);
      for (std::int64_t q = from; q < end; ++q) row[q] = static_cast<T>(s.out[q]);
    }
  });
  std::vector<Extent> planes_of(static_cast<std::size_t>(ny * blocks_per_row));
  for (const auto& p : planes_of_block)
    for (std::size_t e = 0; e < planes_of.size(); ++e) planes_of[e].add(p[e]);
  // Axis 1 (stride nx) and axis 2 (stride nx * ny): kBlock neighbouring lines at a time, over the range
  // extent(outer, block) of the line.
  auto pass = [&](std::int64_t n, std::int64_t stride, std::int64_t outer_count, auto&& start_of, auto&& extent) {
    detail::parallel_chunks(outer_count, workers, [&](std::int64_t outer, int worker) {
      auto& s = scratch[static_cast<std::size_t>(worker)];
      for (std::int64_t b = 0; b < blocks_per_row; ++b) {
        const Extent& nonzero = extent(outer, b);
        if (nonzero.last < 0) continue;
        const std::int64_t lo = std::max<std::int64_t>(0, nonzero.first - 1),
                           length = std::min<std::int64_t>(n - 1, nonzero.last + 1) - lo + 1;
        const std::int64_t i0 = b * kBlock, width = std::min(kBlock, nx - i0);
        T* base = values + start_of(outer) + lo * stride + i0;
        for (std::int64_t q = 0; q < length; ++q)
          for (std::int64_t w = 0; w < width; ++w) s.in[w * length + q] = static_cast<double>(base[q * stride + w]);
        for (std::int64_t w = 0; w < width; ++w) {
          const auto [first, end] = transform_any_line(s.in.data() + w * length, s.out.data(), length, s.v, s.numerator,
                                                       s.denominator, s.rooted);
          for (std::int64_t q = first; q < end; ++q) base[q * stride + w] = static_cast<T>(s.out[q]);
        }
      }
    });
  };
  pass(
      ny, nx, nz, [&](std::int64_t k) { return k * plane; },
      [&](std::int64_t k, std::int64_t b) -> const Extent& {
        return rows_of_block[static_cast<std::size_t>(k * blocks_per_row + b)];
      });
  pass(
      nz, plane, ny, [&](std::int64_t j) { return j * nx; },
      [&](std::int64_t j, std::int64_t b) -> const Extent& {
        return planes_of[static_cast<std::size_t>(j * blocks_per_row + b)];
      });
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
