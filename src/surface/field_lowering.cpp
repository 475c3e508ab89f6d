#include "field_lowering.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "../util/parallel.hpp"
#include "../util/rounding.hpp"

namespace spheremap::detail {
namespace {

// Runs of this many samples along axis 0 (segment i / kSegment of row (j, k)) tell lower_near_centres
// which rows it may skip.
constexpr std::int64_t kSegment = 8;

// values[m] = min(values[m], across + (m + start)²) for m in [0, length): one row of a ball.
template <typename T>
inline void lower_row(T* values, std::int32_t length, T across, T start) {
  for (std::int32_t m = 0; m < length; ++m) {
    const T dx = static_cast<T>(m) + start;
    const T value = across + dx * dx;
    values[m] = value < values[m] ? value : values[m];
  }
}

// The same for a row whose `padded` samples (a multiple of 4, at most length + 3) may all be read and
// written: whole vectors with the samples past `length` masked out, rather than a vector loop with a
// tail for every row (rows are short: 5 to 19 samples), which cost more in loop control and branch
// misses than in arithmetic. The values are those of lower_row to the last bit.
#if defined(__GNUC__)
using Floats = float __attribute__((vector_size(16)));
using Ints = std::int32_t __attribute__((vector_size(16)));

// Vectors [0, vectors) of a padded row (FloatVector: 4 or 8 floats, IntVector the same lanes of int32),
// unrolled; always inlined, so that in a function compiled for AVX2 it uses AVX2's 256-bit operations.
template <typename FloatVector, typename IntVector, int vectors>
[[gnu::always_inline]] inline void lower_vectors(float* values, FloatVector m, FloatVector end, FloatVector a,
                                                 FloatVector s) {
  constexpr int kLanes = sizeof(FloatVector) / sizeof(float);
  const FloatVector step = FloatVector{} + static_cast<float>(kLanes);
  for (int q = 0; q < vectors; ++q, m += step) {
    FloatVector old;
    std::memcpy(&old, values + kLanes * q, sizeof old);
    const FloatVector dx = m + s;
    const FloatVector value = a + dx * dx;
    const IntVector take = (value < old) & (m < end);
    const FloatVector out = reinterpret_cast<FloatVector>((reinterpret_cast<IntVector>(value) & take) |
                                                          (reinterpret_cast<IntVector>(old) & ~take));
    std::memcpy(values + kLanes * q, &out, sizeof out);
  }
}
#endif

inline void lower_row_padded(float* values, std::int32_t padded, std::int32_t length, float across, float start) {
#if defined(__GNUC__)
  const Floats m = {0, 1, 2, 3};
  const auto last = static_cast<float>(length);
  const Floats end = {last, last, last, last}, a = {across, across, across, across}, s = {start, start, start, start};
  switch (padded / 4) {
    case 1: return lower_vectors<Floats, Ints, 1>(values, m, end, a, s);
    case 2: return lower_vectors<Floats, Ints, 2>(values, m, end, a, s);
    case 3: return lower_vectors<Floats, Ints, 3>(values, m, end, a, s);
    case 4: return lower_vectors<Floats, Ints, 4>(values, m, end, a, s);
    case 5: return lower_vectors<Floats, Ints, 5>(values, m, end, a, s);
    default: break;
  }
  (void)padded;
#endif
  lower_row(values, length, across, start);
}
inline void lower_row_padded(double* values, std::int32_t, std::int32_t length, double across, double start) {
  lower_row(values, length, across, start);
}

// The same eight lanes at a time, for a row whose `padded` samples (a multiple of 8, at most length + 7)
// may all be read and written; inlined into a function compiled for AVX2 (lower_interior_avx2) this is
// one 256-bit operation per eight samples. The values are those of lower_row to the last bit.
#if defined(__GNUC__) && defined(__x86_64__)
#define SPHEREMAP_LOWER_AVX2 1
using Floats8 = float __attribute__((vector_size(32)));
using Ints8 = std::int32_t __attribute__((vector_size(32)));

[[gnu::always_inline]] inline void lower_row_padded8(float* values, std::int32_t padded, std::int32_t length,
                                                     float across, float start) {
  const Floats8 m = {0, 1, 2, 3, 4, 5, 6, 7};
  const auto last = static_cast<float>(length);
  const Floats8 end = {last, last, last, last, last, last, last, last};
  const Floats8 a = {across, across, across, across, across, across, across, across};
  const Floats8 s = {start, start, start, start, start, start, start, start};
  switch (padded / 8) {
    case 1: return lower_vectors<Floats8, Ints8, 1>(values, m, end, a, s);
    case 2: return lower_vectors<Floats8, Ints8, 2>(values, m, end, a, s);
    case 3: return lower_vectors<Floats8, Ints8, 3>(values, m, end, a, s);
    default: break;
  }
  lower_row(values, length, across, start);
}
#endif

// A row of the ball that lower_near_centres lowers around a centre's nearest sample.
struct BallRow {
  double dj, first;                            // dj; the offset of the row's first sample along axis 0 (-half)
  std::int64_t offset, segment_row;            // of the first sample in the field; of the row's segments
  std::int32_t half, padded, padded8, length;  // padded: to a multiple of 4; padded8: of 8
};

// Whether segment flags [i0 / kSegment, i1 / kSegment] of a row hold an open one. A row of at most
// 2 kSegment + 1 samples spans at most three segments (its first, its last and the one between); `wide`
// rows are checked segment by segment.
[[gnu::always_inline]] inline bool any_open(const std::uint8_t* flags, std::int64_t i0, std::int64_t i1, bool wide) {
  const auto g0 = static_cast<std::uint64_t>(i0) / kSegment, g1 = static_cast<std::uint64_t>(i1) / kSegment;
  std::uint8_t any = flags[g0] | flags[g1] | flags[(g0 + g1) / 2];
  if (wide)
    for (auto g = g0 + 1; g < g1; ++g) any |= flags[g];
  return any != 0;
}

// One centre away from the grid's border: its ball's rows in planes dk, dk + step, ... up to extent.
template <typename T>
struct InteriorBall {
  T* centre_sample;                     // the centre's nearest sample
  const std::uint8_t* centre_segments;  // the flags of its row
  std::int64_t ci;                      // its index along axis 0
  double fx, fy, fz;                    // centre - nearest sample (grid units)
  const BallRow* rows;
  const std::size_t* plane_rows;
  std::int64_t extent;
  bool wide;
};

template <int kLanes>
[[gnu::always_inline]] inline void lower_interior(const InteriorBall<float>& ball, std::int64_t dk, std::int64_t step) {
  for (; dk <= ball.extent; dk += step) {
    const double z = static_cast<double>(dk) - ball.fz, z2 = z * z;
    const BallRow* end = ball.rows + ball.plane_rows[static_cast<std::size_t>(dk + ball.extent + 1)];
    for (const BallRow* row = ball.rows + ball.plane_rows[static_cast<std::size_t>(dk + ball.extent)]; row != end;
         ++row) {
      if (!any_open(ball.centre_segments + row->segment_row, ball.ci - row->half, ball.ci + row->half, ball.wide))
        continue;
      const double y = row->dj - ball.fy;
      const auto across = static_cast<float>(z2 + y * y), start = static_cast<float>(row->first - ball.fx);
#if defined(SPHEREMAP_LOWER_AVX2)
      if constexpr (kLanes == 8) {
        lower_row_padded8(ball.centre_sample + row->offset, row->padded8, row->length, across, start);
        continue;
      }
#endif
      lower_row_padded(ball.centre_sample + row->offset, row->padded, row->length, across, start);
    }
  }
}

void lower_interior_four_lanes(const InteriorBall<float>& ball, std::int64_t dk, std::int64_t step) {
  lower_interior<4>(ball, dk, step);
}
#if defined(SPHEREMAP_LOWER_AVX2)
[[gnu::target("avx2")]] void lower_interior_avx2(const InteriorBall<float>& ball, std::int64_t dk, std::int64_t step) {
  lower_interior<8>(ball, dk, step);
}
#endif

// The rows of the ball around a centre's nearest sample, plane by plane (dk ascending, then dj), as
// offsets from that sample: every sample within `reach` of the nearest sample.
struct Ball {
  std::vector<BallRow> rows;
  std::vector<std::size_t> plane_rows;  // rows of plane dk: [plane_rows[dk + extent], plane_rows[dk + extent + 1])
  std::int64_t extent = 0;
  bool wide = false;  // some row spans more than 2 kSegment + 1 samples
};

template <typename T>
Ball ball_rows(const Grid3<T>& field, double reach, std::int64_t segments) {
  const auto [nx, ny, nz] = field.size;
  const std::int64_t plane = nx * ny;
  Ball ball;
  const auto extent = ball.extent = static_cast<std::int64_t>(std::ceil(reach));
  for (std::int64_t dk = -extent; dk <= extent; ++dk) {
    ball.plane_rows.push_back(ball.rows.size());
    for (std::int64_t dj = -extent; dj <= extent; ++dj) {
      const double rest = reach * reach - static_cast<double>(dk * dk + dj * dj);
      if (rest < 0) continue;
      const auto half = static_cast<std::int32_t>(std::floor(std::sqrt(rest)));
      ball.rows.push_back({static_cast<double>(dj), static_cast<double>(-half), dk * plane + dj * nx - half,
                           (dk * ny + dj) * segments, half, (2 * half + 1 + 3) / 4 * 4, (2 * half + 1 + 7) / 8 * 8,
                           2 * half + 1});
    }
  }
  ball.plane_rows.push_back(ball.rows.size());
  for (const BallRow& row : ball.rows) ball.wide = ball.wide || row.length > 2 * kSegment + 1;
  return ball;
}

// open[segment]: some sample of the segment is above `settled`. Sample by sample into bytes (a loop that
// vectorizes), then a segment's 8 bytes read as one word.
template <typename T>
std::vector<std::uint8_t> open_segments(const Grid3<T>& field, double settled, std::int64_t segments, int threads) {
  const auto [nx, ny, nz] = field.size;
  const std::int64_t plane = nx * ny;
  std::vector<std::uint8_t> open(static_cast<std::size_t>(segments * ny * nz));
  const T limit = static_cast<T>(settled);
  static_assert(kSegment == sizeof(std::uint64_t));
  std::vector<std::vector<std::uint8_t>> above(
      static_cast<std::size_t>(threads), std::vector<std::uint8_t>(static_cast<std::size_t>(segments * kSegment), 0));
  parallel_chunks(nz, threads, [&](std::int64_t k, int worker) {
    std::uint8_t* over = above[static_cast<std::size_t>(worker)].data();
    for (std::int64_t j = 0; j < ny; ++j) {
      const T* values = field.values.data() + k * plane + j * nx;
      std::uint8_t* flags = open.data() + (k * ny + j) * segments;
      for (std::int64_t i = 0; i < nx; ++i) over[i] = values[i] > limit;
      for (std::int64_t g = 0; g < segments; ++g) {
        std::uint64_t word;
        std::memcpy(&word, over + g * kSegment, sizeof word);
        flags[g] = word != 0;
      }
    }
  });
  return open;
}

// The ball of a centre away from the border in a double field: rows dk, dk + step, ... of its planes.
void lower_interior_double(const InteriorBall<double>& ball, std::int64_t dk, std::int64_t step) {
  for (; dk <= ball.extent; dk += step) {
    const double z = static_cast<double>(dk) - ball.fz, z2 = z * z;
    const BallRow* end = ball.rows + ball.plane_rows[static_cast<std::size_t>(dk + ball.extent + 1)];
    for (const BallRow* row = ball.rows + ball.plane_rows[static_cast<std::size_t>(dk + ball.extent)]; row != end;
         ++row) {
      if (!any_open(ball.centre_segments + row->segment_row, ball.ci - row->half, ball.ci + row->half, ball.wide))
        continue;
      const double y = row->dj - ball.fy;
      lower_row_padded(ball.centre_sample + row->offset, row->padded, row->length, z2 + y * y, row->first - ball.fx);
    }
  }
}

// The ball of a centre near the border: each row clipped to the grid.
template <typename T>
void lower_at_border(Grid3<T>& field, const Ball& ball, const std::vector<std::uint8_t>& open, std::int64_t segments,
                     std::int64_t ci, std::int64_t cj, std::int64_t ck, double fx, double fy, double fz,
                     std::int64_t dk, std::int64_t step) {
  const auto [nx, ny, nz] = field.size;
  const std::int64_t plane = nx * ny, extent = ball.extent;
  for (; dk <= extent; dk += step) {
    const std::int64_t k = ck + dk;
    if (k < 0 || k >= nz) continue;
    const double z = static_cast<double>(dk) - fz, z2 = z * z;
    for (auto r = ball.plane_rows[static_cast<std::size_t>(dk + extent)];
         r < ball.plane_rows[static_cast<std::size_t>(dk + extent + 1)]; ++r) {
      const BallRow& row = ball.rows[r];
      const std::int64_t j = cj + static_cast<std::int64_t>(row.dj);
      if (j < 0 || j >= ny) continue;
      const std::int64_t i0 = std::max<std::int64_t>(ci - row.half, 0),
                         i1 = std::min<std::int64_t>(ci + row.half, nx - 1);
      if (i0 > i1 || !any_open(open.data() + (k * ny + j) * segments, i0, i1, ball.wide)) continue;
      const double y = row.dj - fy;
      lower_row(field.values.data() + k * plane + j * nx + i0, static_cast<std::int32_t>(i1 - i0 + 1),
                static_cast<T>(z2 + y * y), static_cast<T>(static_cast<double>(i0 - ci) - fx));
    }
  }
}

}  // namespace

template <typename T>
void lower_near_centres(Grid3<T>& field, const std::vector<Vec3>& centres, double radius, double settled, int threads,
                        bool use_avx2) {
  const auto [nx, ny, nz] = field.size;
  const std::int64_t plane = nx * ny, segments = (nx + kSegment - 1) / kSegment;
  const Ball ball = ball_rows(field, radius + std::sqrt(3.0) / 2 + 1e-9, segments);
  const std::int64_t extent = ball.extent;
  const std::vector<std::uint8_t> open = open_segments(field, settled, segments, threads);
  // Interior balls of a float field go eight lanes at a time where the processor has AVX2.
  auto lower_interior_rows = lower_interior_four_lanes;
#if defined(SPHEREMAP_LOWER_AVX2)
  if (use_avx2 && __builtin_cpu_supports("avx2")) lower_interior_rows = lower_interior_avx2;
#else
  (void)use_avx2;
#endif
  parallel_chunks(threads, threads, [&](std::int64_t chunk, int) {
    for (const auto& c : centres) {
      const std::int64_t ci = round_to_int(c[0]), cj = round_to_int(c[1]), ck = round_to_int(c[2]);
      const double fx = c[0] - static_cast<double>(ci), fy = c[1] - static_cast<double>(cj),
                   fz = c[2] - static_cast<double>(ck);
      std::int64_t dk = -extent;
      dk += (((chunk - (ck + dk)) % threads) + threads) % threads;
      // Away from the border (the padded rows included), no row needs clipping.
      if (ci - extent >= 0 && cj - extent >= 0 && ck - extent >= 0 && ci + extent + 7 < nx && cj + extent < ny &&
          ck + extent < nz) {
        const InteriorBall<T> interior{field.values.data() + ck * plane + cj * nx + ci,
                                       open.data() + (ck * ny + cj) * segments,
                                       ci,
                                       fx,
                                       fy,
                                       fz,
                                       ball.rows.data(),
                                       ball.plane_rows.data(),
                                       extent,
                                       ball.wide};
        if constexpr (std::is_same_v<T, float>) {
          lower_interior_rows(interior, dk, threads);
        } else {
          lower_interior_double(interior, dk, threads);
        }
        continue;
      }
      lower_at_border(field, ball, open, segments, ci, cj, ck, fx, fy, fz, dk, threads);
    }
  });
}

template void lower_near_centres<double>(Grid3<double>&, const std::vector<Vec3>&, double, double, int, bool);
template void lower_near_centres<float>(Grid3<float>&, const std::vector<Vec3>&, double, double, int, bool);

}  // namespace spheremap::detail
