// The bucket grid of a sphere map and the point location in it (see sphere_locator.hpp).
#include "spheremap/render/sphere_locator.hpp"

#include "../util/parallel.hpp"
#include "spheremap/topology/connectivity.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

namespace spheremap {
namespace {

constexpr double kPi = std::numbers::pi;
// Bounding caps are widened by this much (radians): a cap computed with rounding must still hold its
// triangle's edges.
constexpr double kCapMargin = 1e-9;

Vec3 normalized(const Vec3& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

double distance2(const Vec3& a, const Vec3& b) {
  const Vec3 d{a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  return d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
}

double colatitude(const Vec3& u) { return std::acos(std::clamp(u[2], -1.0, 1.0)); }

double azimuth(const Vec3& u) {
  const double phi = std::atan2(u[1], u[0]);
  return phi < 0 ? phi + 2 * kPi : phi;
}

// The cells a triangle's cap meets, row by row: [first, last] columns (last may exceed the row's columns:
// the range wraps around longitude 2π).
struct CapCells {
  int row_first = 0, row_last = 0;
  double phi_lo = 0, phi_hi = 2 * kPi;  // the whole row when phi_hi - phi_lo >= 2π
};

CapCells cap_cells(const SphereLocator& l, const Triangle& t) {
  const Vec3& a = l.vertices[t[0]];
  const Vec3& b = l.vertices[t[1]];
  const Vec3& c = l.vertices[t[2]];
  const Vec3 sum{a[0] + b[0] + c[0], a[1] + b[1] + c[1], a[2] + b[2] + c[2]};
  CapCells cells{0, l.rows - 1, 0, 2 * kPi};
  // A cap wider than a hemisphere is not convex: such a triangle goes into every cell.
  if (std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]) < 1e-3) return cells;
  const Vec3 centre = normalized(sum);
  // The angle to the farthest corner, from the longest chord (one asin instead of three atan2).
  const double chord2 = std::max({distance2(centre, a), distance2(centre, b), distance2(centre, c)});
  const double radius = 2 * std::asin(std::min(1.0, std::sqrt(chord2) / 2)) + kCapMargin;
  if (radius >= kPi / 2) return cells;
  const double theta = colatitude(centre);
  const double row_height = kPi / l.rows;
  cells.row_first = std::clamp(static_cast<int>(std::floor((theta - radius) / row_height)), 0, l.rows - 1);
  cells.row_last = std::clamp(static_cast<int>(std::floor((theta + radius) / row_height)), 0, l.rows - 1);
  if (theta - radius <= 0 || theta + radius >= kPi) return cells;  // the cap holds a pole: every longitude
  const double half_width = std::asin(std::min(1.0, std::sin(radius) / std::sin(theta))) + kCapMargin;
  const double phi = azimuth(centre);
  cells.phi_lo = phi - half_width;
  cells.phi_hi = phi + half_width;
  return cells;
}

// Calls add(cell) for every cell of `cells`, each once.
template <typename Add>
void for_each_cell(const SphereLocator& l, const CapCells& cells, Add&& add) {
  for (int row = cells.row_first; row <= cells.row_last; ++row) {
    const int columns = l.row_columns[row];
    const int first_cell = l.row_first_cell[row];
    if (cells.phi_hi - cells.phi_lo >= 2 * kPi) {
      for (int column = 0; column < columns; ++column) add(first_cell + column);
      continue;
    }
    const double width = 2 * kPi / columns;
    const int lo = static_cast<int>(std::floor(cells.phi_lo / width));
    const int hi = static_cast<int>(std::floor(cells.phi_hi / width));
    const int count = std::min(hi - lo + 1, columns);
    for (int k = 0; k < count; ++k) add(first_cell + (((lo + k) % columns) + columns) % columns);
  }
}

void lay_out_grid(SphereLocator& l) {
  // About one cell per two triangles: 4 rows² / π cells in all.
  const double cells = std::max(1.0, static_cast<double>(l.triangles.size()) / 2);
  l.rows = std::clamp(static_cast<int>(std::ceil(std::sqrt(kPi * cells / 4))), 1, 4096);
  l.row_columns.resize(l.rows);
  l.row_first_cell.assign(l.rows + 1, 0);
  for (int row = 0; row < l.rows; ++row) {
    const double mid = (row + 0.5) * kPi / l.rows;
    l.row_columns[row] = std::max(1, static_cast<int>(std::lround(2 * l.rows * std::sin(mid))));
    l.row_first_cell[row + 1] = l.row_first_cell[row] + l.row_columns[row];
  }
}

}  // namespace

SphereLocator make_sphere_locator(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles,
                                  int threads) {
  SphereLocator l;
  l.vertices.reserve(vertices.size());
  for (const Vec3& v : vertices) l.vertices.push_back(normalized(v));
  const auto n = static_cast<std::int64_t>(vertices.size());
  for (const Triangle& t : triangles)
    for (const std::int32_t v : t)
      if (v < 0 || v >= n) throw std::invalid_argument("make_sphere_locator: a triangle index is out of range");
  l.triangles = triangles;
  lay_out_grid(l);
  const int cells = l.row_first_cell[l.rows];
  // Each triangle's cap and edge normals on their own (in parallel; each depends on its triangle only), then the
  // buckets in triangle order.
  std::vector<CapCells> caps(triangles.size());
  l.edge_normals.resize(triangles.size());
  detail::parallel_ranges(static_cast<std::int64_t>(triangles.size()), 8192, detail::surface_threads(threads),
                          [&](std::int64_t first, std::int64_t last) {
                            for (auto t = static_cast<std::size_t>(first); t < static_cast<std::size_t>(last); ++t) {
                              caps[t] = cap_cells(l, triangles[t]);
                              const Vec3& a = l.vertices[triangles[t][0]];
                              const Vec3& b = l.vertices[triangles[t][1]];
                              const Vec3& c = l.vertices[triangles[t][2]];
                              const Vec3 n0 = cross(b, c), n1 = cross(c, a), n2 = cross(a, b);
                              l.edge_normals[t] = {n0[0], n0[1], n0[2], n1[0], n1[1], n1[2], n2[0], n2[1], n2[2]};
                            }
                          });
  l.opposite = opposite_half_edges(l.vertices.size(), triangles, detail::surface_threads(threads));
  // Bands of rows side by side: each band's cells are its own, and each band takes the triangles in index order,
  // so every cell lists its triangles in index order whatever the number of bands.
  const int bands = std::min(l.rows, detail::surface_threads(threads));
  const auto in_band = [&](int band, const CapCells& cap, auto&& add) {
    CapCells clipped = cap;
    clipped.row_first = std::max(cap.row_first, band * l.rows / bands);
    clipped.row_last = std::min(cap.row_last, (band + 1) * l.rows / bands - 1);
    if (clipped.row_first <= clipped.row_last) for_each_cell(l, clipped, add);
  };
  std::vector<std::int32_t> counts(static_cast<std::size_t>(cells) + 1, 0);
  detail::parallel_chunks(bands, bands, [&](std::int64_t band, int) {
    for (const CapCells& cap : caps) in_band(static_cast<int>(band), cap, [&](int cell) { ++counts[cell + 1]; });
  });
  for (int cell = 0; cell < cells; ++cell) counts[cell + 1] += counts[cell];
  l.cell_first = counts;
  l.cell_triangles.resize(static_cast<std::size_t>(counts[cells]));
  detail::parallel_chunks(bands, bands, [&](std::int64_t band, int) {
    for (std::size_t t = 0; t < caps.size(); ++t)
      in_band(static_cast<int>(band), caps[t],
              [&](int cell) { l.cell_triangles[counts[cell]++] = static_cast<std::int32_t>(t); });
  });
  return l;
}

namespace {

// A weight below this (of unit vectors: |weights| < 6) makes its triangle's score negative (not a denormal that
// rounds to -0 when divided by the weights' sum).
constexpr double kOutside = -1e-300;
// How far inside a hinted triangle (its smallest weight over their sum) a point must be to take it unsearched.
constexpr double kHintMargin = 1e-6;
// Triangles tried from the hint before the cell search.
constexpr int kHintSteps = 4;

// The first candidate of `cell`, in index order, that contains `direction`, else the one it is least outside
// (weights clamped).
SphereHit locate_in_cell(const SphereLocator& l, const Vec3& d, int cell) {
  // Most candidates are rejected by their first or second weight: a first pass looks for the containing one only
  // (the same test as below), and the least-outside search runs when none contains the point.
  for (std::int32_t k = l.cell_first[cell]; k < l.cell_first[cell + 1]; ++k) {
    const std::int32_t t = l.cell_triangles[k];
    const std::array<double, 9>& n = l.edge_normals[t];
    const double w0 = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    if (w0 < kOutside) continue;
    const double w1 = d[0] * n[3] + d[1] * n[4] + d[2] * n[5];
    if (w1 < kOutside) continue;
    const double w2 = d[0] * n[6] + d[1] * n[7] + d[2] * n[8];
    if (w2 < kOutside) continue;
    const double total = w0 + w1 + w2;
    if (!(total > 0)) continue;
    if (std::min({w0, w1, w2}) / total >= 0) return {t, {w0 / total, w1 / total, w2 / total}};
  }
  SphereHit best;
  double best_score = -std::numeric_limits<double>::infinity();
  for (std::int32_t k = l.cell_first[cell]; k < l.cell_first[cell + 1]; ++k) {
    const std::int32_t t = l.cell_triangles[k];
    const std::array<double, 9>& n = l.edge_normals[t];
    const std::array<double, 3> w{d[0] * n[0] + d[1] * n[1] + d[2] * n[2], d[0] * n[3] + d[1] * n[4] + d[2] * n[5],
                                  d[0] * n[6] + d[1] * n[7] + d[2] * n[8]};
    const double total = w[0] + w[1] + w[2];
    if (!(total > 0)) continue;  // the point is behind the triangle's plane
    const double score = std::min({w[0], w[1], w[2]}) / total;
    if (score >= 0) return {t, {w[0] / total, w[1] / total, w[2] / total}};
    if (score > best_score) best_score = score, best = {t, w};
  }
  if (best.triangle < 0) return best;
  for (double& w : best.weights) w = std::max(w, 0.0);
  const double total = best.weights[0] + best.weights[1] + best.weights[2];
  for (double& w : best.weights) w /= total;
  return best;
}

int cell_of(const SphereLocator& l, double theta, double phi) {
  const int row = std::clamp(static_cast<int>(theta / kPi * l.rows), 0, l.rows - 1);
  const int columns = l.row_columns[row];
  const int column = std::clamp(static_cast<int>(phi / (2 * kPi) * columns), 0, columns - 1);
  return l.row_first_cell[row] + column;
}

}  // namespace

SphereHit locate_on_sphere(const SphereLocator& l, const Vec3& direction) {
  return locate_in_cell(l, direction, cell_of(l, colatitude(normalized(direction)), azimuth(direction)));
}

SphereHit locate_on_sphere(const SphereLocator& l, const Vec3& direction, double theta, double phi) {
  phi = std::fmod(phi, 2 * kPi);
  if (phi < 0) phi += 2 * kPi;
  return locate_in_cell(l, direction, cell_of(l, theta, phi));
}

SphereHit locate_on_sphere(const SphereLocator& l, const Vec3& direction, double theta, double phi, std::int32_t hint) {
  // Neighbouring pixels lie in the same triangle or one or two edges away: a short walk finds most of them.
  for (int step = 0; step < kHintSteps && hint >= 0; ++step) {
    // The weights as locate_in_cell computes them, so that the hit is the same to the bit.
    const Vec3& d = direction;
    const std::array<double, 9>& n = l.edge_normals[static_cast<std::size_t>(hint)];
    const double w0 = d[0] * n[0] + d[1] * n[1] + d[2] * n[2];
    const double w1 = d[0] * n[3] + d[1] * n[4] + d[2] * n[5];
    const double w2 = d[0] * n[6] + d[1] * n[7] + d[2] * n[8];
    const double total = w0 + w1 + w2;
    if (!(total > 0)) break;
    // Well inside (rounding moves a weight by about 1e-16 of the sum): no other triangle of a one-to-one map has it.
    if (std::min({w0, w1, w2}) >= kHintMargin * total) return {hint, {w0 / total, w1 / total, w2 / total}};
    const int across = w0 <= w1 ? (w0 <= w2 ? 0 : 2) : (w1 <= w2 ? 1 : 2);
    // Edge `across` of the triangle, (corner across + 1, corner across + 2), is its half-edge across + 1.
    const std::int32_t half_edge = l.opposite[3 * static_cast<std::size_t>(hint) + (across + 1) % 3];
    hint = half_edge < 0 ? -1 : half_edge / 3;
  }
  return locate_on_sphere(l, direction, theta, phi);
}

}  // namespace spheremap
