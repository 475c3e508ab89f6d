#include "pockets.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "../util/parallel.hpp"
#include "../util/rounding.hpp"
#include "../util/union_find.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {

template <typename T>
void mark_accessible_surface(Grid3<T>& field, const std::vector<Atom>& atoms, double probe, int threads) {
  const double h = field.spacing;
  const T inside = std::numeric_limits<T>::infinity();
  // Plane k belongs to chunk k % threads: every sample is written by one thread only.
  parallel_chunks(threads, threads, [&](std::int64_t chunk, int) {
    for (const auto& a : atoms) {
      const double reach = a.radius + probe, reach2 = reach * reach;
      const auto first = [&](int d) {
        return std::max<std::int64_t>(0, ceil_to_int((a.position[d] - reach - field.origin[d]) / h));
      };
      const auto last = [&](int d) {
        return std::min<std::int64_t>(field.size[d] - 1, floor_to_int((a.position[d] + reach - field.origin[d]) / h));
      };
      const std::int64_t i_first = first(0), i_last = last(0);
      std::int64_t k = first(2);
      k += ((chunk - k) % threads + threads) % threads;
      for (; k <= last(2); k += threads)
        for (std::int64_t j = first(1); j <= last(1); ++j) {
          const Vec3 row = field.point(0, j, k);
          const double dy = row[1] - a.position[1], dz = row[2] - a.position[2], rest = reach2 - (dy * dy + dz * dz);
          if (rest < -1e-9 * reach2) continue;
          const double half = std::sqrt(std::max(0.0, rest));
          const std::int64_t i0 = std::max(i_first, ceil_to_int((a.position[0] - half - field.origin[0]) / h) - 1);
          const std::int64_t i1 = std::min(i_last, floor_to_int((a.position[0] + half - field.origin[0]) / h) + 1);
          T* values = field.values.data() + field.index(0, j, k);
          // The test is monotone in |x - centre| even as rounded, so the samples that pass form an
          // interval: found from both ends of the estimate, then filled.
          auto inside_sphere = [&](std::int64_t i) {
            return squared_distance(field.point(i, j, k), a.position) < reach2;
          };
          std::int64_t lo = i0, hi = i1;
          while (lo <= i1 && !inside_sphere(lo)) ++lo;
          if (lo > i1) continue;
          while (!inside_sphere(hi)) --hi;
          std::fill(values + lo, values + hi + 1, inside);
        }
    }
  });
}

template <typename T>
Pockets flood_and_label_pockets(Grid3<T>& field, int threads) {
  const auto [nx, ny, nz] = field.size;
  const T unreached = static_cast<T>(kUnreached);
  const std::int64_t plane = nx * ny;
  struct Run {
    std::int32_t i0, i1;  // [i0, i1] along axis 0
  };
  // plane_runs[k]: the runs of plane k, row by row, each row's in increasing i; row_start[k * (ny + 1) + j]:
  // index of row j's first run in plane k.
  std::vector<std::vector<Run>> plane_runs(static_cast<std::size_t>(nz));
  std::vector<std::int64_t> row_start(static_cast<std::size_t>(nz * (ny + 1)));
  parallel_chunks(nz, threads, [&](std::int64_t k, int) {
    auto& runs = plane_runs[static_cast<std::size_t>(k)];
    std::int64_t* starts = row_start.data() + k * (ny + 1);
    for (std::int64_t j = 0; j < ny; ++j) {
      starts[j] = static_cast<std::int64_t>(runs.size());
      const T* values = field.values.data() + k * plane + j * nx;
      for (std::int64_t i = 0; i < nx;) {
        if (values[i] != unreached) {
          ++i;
          continue;
        }
        const std::int64_t i0 = i;
        while (i < nx && values[i] == unreached) ++i;
        runs.push_back({static_cast<std::int32_t>(i0), static_cast<std::int32_t>(i - 1)});
      }
    }
    starts[ny] = static_cast<std::int64_t>(runs.size());
  });
  std::vector<std::int64_t> plane_first(static_cast<std::size_t>(nz) + 1, 0);  // global index of each plane's first run
  for (std::int64_t k = 0; k < nz; ++k)
    plane_first[static_cast<std::size_t>(k) + 1] =
        plane_first[static_cast<std::size_t>(k)] +
        static_cast<std::int64_t>(plane_runs[static_cast<std::size_t>(k)].size());
  const std::int64_t total = plane_first.back();
  if (total == 0) return {};
  UnionFind<std::int64_t> sets(static_cast<std::size_t>(total));
  // Joins the runs of row (j, k) with those of row (j', k') they overlap (both lists increasing in i).
  auto join_rows = [&](std::int64_t k, std::int64_t j, std::int64_t k2, std::int64_t j2) {
    const auto& a = plane_runs[static_cast<std::size_t>(k)];
    const auto& b = plane_runs[static_cast<std::size_t>(k2)];
    std::int64_t x = row_start[static_cast<std::size_t>(k * (ny + 1) + j)],
                 x_end = row_start[static_cast<std::size_t>(k * (ny + 1) + j + 1)];
    std::int64_t y = row_start[static_cast<std::size_t>(k2 * (ny + 1) + j2)],
                 y_end = row_start[static_cast<std::size_t>(k2 * (ny + 1) + j2 + 1)];
    while (x < x_end && y < y_end) {
      const Run& r = a[static_cast<std::size_t>(x)];
      const Run& q = b[static_cast<std::size_t>(y)];
      if (r.i0 <= q.i1 && q.i0 <= r.i1)
        sets.join(plane_first[static_cast<std::size_t>(k)] + x, plane_first[static_cast<std::size_t>(k2)] + y);
      if (r.i1 < q.i1)
        ++x;
      else
        ++y;
    }
  };
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j) {
      if (j > 0) join_rows(k, j, k, j - 1);
      if (k > 0) join_rows(k, j, k - 1, j);
    }
  // Per set (at its root): whether it reaches the border, and its first sample.
  std::vector<std::uint8_t> border(static_cast<std::size_t>(total), 0);
  std::vector<std::int64_t> first_sample(static_cast<std::size_t>(total), std::numeric_limits<std::int64_t>::max());
  std::vector<std::int64_t> root_of(static_cast<std::size_t>(total));
  for (std::int64_t k = 0; k < nz; ++k) {
    const auto& runs = plane_runs[static_cast<std::size_t>(k)];
    for (std::int64_t j = 0; j < ny; ++j)
      for (auto x = row_start[static_cast<std::size_t>(k * (ny + 1) + j)];
           x < row_start[static_cast<std::size_t>(k * (ny + 1) + j + 1)]; ++x) {
        const Run& r = runs[static_cast<std::size_t>(x)];
        const std::int64_t run = plane_first[static_cast<std::size_t>(k)] + x, root = sets.find(run);
        root_of[static_cast<std::size_t>(run)] = root;
        border[static_cast<std::size_t>(root)] |=
            k == 0 || k == nz - 1 || j == 0 || j == ny - 1 || r.i0 == 0 || r.i1 == nx - 1;
        first_sample[static_cast<std::size_t>(root)] =
            std::min(first_sample[static_cast<std::size_t>(root)], k * plane + j * nx + r.i0);
      }
  }
  // Pockets numbered by first sample.
  std::vector<std::pair<std::int64_t, std::int64_t>> pocket_roots;  // first sample, root
  for (std::int64_t run = 0; run < total; ++run)
    if (root_of[static_cast<std::size_t>(run)] == run && !border[static_cast<std::size_t>(run)])
      pocket_roots.push_back({first_sample[static_cast<std::size_t>(run)], run});
  std::sort(pocket_roots.begin(), pocket_roots.end());
  std::vector<T> value_of_root(static_cast<std::size_t>(total), T(0));
  for (std::size_t p = 0; p < pocket_roots.size(); ++p)
    value_of_root[static_cast<std::size_t>(pocket_roots[p].second)] =
        static_cast<std::int64_t>(p) < kMaximumPockets ? static_cast<T>(p + 2) : std::numeric_limits<T>::infinity();
  std::vector<std::vector<PocketRun>> plane_pockets(static_cast<std::size_t>(nz));
  parallel_chunks(nz, threads, [&](std::int64_t k, int) {
    const auto& runs = plane_runs[static_cast<std::size_t>(k)];
    for (std::int64_t j = 0; j < ny; ++j) {
      T* values = field.values.data() + k * plane + j * nx;
      for (auto x = row_start[static_cast<std::size_t>(k * (ny + 1) + j)];
           x < row_start[static_cast<std::size_t>(k * (ny + 1) + j + 1)]; ++x) {
        const Run& r = runs[static_cast<std::size_t>(x)];
        const T value = value_of_root[static_cast<std::size_t>(
            root_of[static_cast<std::size_t>(plane_first[static_cast<std::size_t>(k)] + x)])];
        std::fill(values + r.i0, values + r.i1 + 1, value);
        if (const std::int64_t label = label_of(value); label > 0)
          plane_pockets[static_cast<std::size_t>(k)].push_back(
              {k * plane + j * nx + r.i0, r.i1 - r.i0 + 1, static_cast<std::int32_t>(label)});
      }
    }
  });
  Pockets pockets;
  pockets.count = std::min<std::int64_t>(static_cast<std::int64_t>(pocket_roots.size()), kMaximumPockets);
  for (auto& part : plane_pockets) pockets.runs.insert(pockets.runs.end(), part.begin(), part.end());
  return pockets;
}

template void mark_accessible_surface<double>(Grid3<double>&, const std::vector<Atom>&, double, int);
template void mark_accessible_surface<float>(Grid3<float>&, const std::vector<Atom>&, double, int);
template Pockets flood_and_label_pockets<double>(Grid3<double>&, int);
template Pockets flood_and_label_pockets<float>(Grid3<float>&, int);

}  // namespace spheremap::detail
