#include "spheremap/surface/contour.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <stdexcept>

#include "../util/parallel.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

// Corners of a cell as offsets (corner c = x + 2y + 4z); the Freudenthal tetrahedra walk from corner 0
// to corner 7 adding one axis at a time, in each of the six axis orders.
constexpr std::array<std::array<int, 3>, 8> kCorner = {
    {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0}, {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}};
constexpr std::array<std::array<int, 4>, 6> kTetrahedra = {
    {{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7}, {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};
// The seven lattice edges leaving a sample upwards: +x, +y, +z, +x+y, +x+z, +y+z, +x+y+z. Every edge of a
// Freudenthal tetrahedron joins a corner to one whose axes include its own, so it is one of these.
constexpr std::array<std::array<int, 3>, 7> kEdgeOffset = {
    {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}, {1, 1, 0}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}};
constexpr std::array<int, 8> kEdgeTypeOfAxes = {-1, 0, 1, 3, 2, 4, 5, 6};  // axis bits (x=1, y=2, z=4) -> type

// Bits set in a byte, by table (std::popcount is a library call without -mpopcnt).
constexpr std::array<std::uint8_t, 256> kBitCount = [] {
  std::array<std::uint8_t, 256> count{};
  for (int b = 0; b < 256; ++b) count[b] = static_cast<std::uint8_t>(std::popcount(static_cast<unsigned>(b)));
  return count;
}();

// An edge of a cell: its lower corner and its type (kEdgeOffset).
struct CellEdge {
  std::uint8_t corner, type;
};
struct CellCase {
  int triangles = 0;
  std::array<std::array<CellEdge, 3>, 12> edges{};
};

// For every pattern of inside corners (bit c: corner c inside), the triangles of the six tetrahedra, in
// tetrahedron order, each turned so that its normal points away from an inside corner (decided on edge
// midpoints of the unit cell, which are never degenerate; the grid is uniform, so this is the
// orientation in space too).
const std::array<CellCase, 256>& cell_cases() {
  static const std::array<CellCase, 256> table = [] {
    std::array<CellCase, 256> cases{};
    auto corner_point = [](int c) { return Vec3{double(kCorner[c][0]), double(kCorner[c][1]), double(kCorner[c][2])}; };
    for (int mask = 0; mask < 256; ++mask) {
      CellCase& cell = cases[mask];
      auto emit = [&](std::array<std::pair<int, int>, 3> edges, int from) {
        Vec3 mid[3];
        for (int e = 0; e < 3; ++e) mid[e] = 0.5 * (corner_point(edges[e].first) + corner_point(edges[e].second));
        const Vec3 normal = cross(mid[1] - mid[0], mid[2] - mid[0]);
        if (dot(normal, mid[0] - corner_point(from)) < 0) std::swap(edges[1], edges[2]);
        auto& out = cell.edges[cell.triangles++];
        for (int e = 0; e < 3; ++e) {
          const int lower = std::min(edges[e].first, edges[e].second),
                    upper = std::max(edges[e].first, edges[e].second);
          out[e] = {static_cast<std::uint8_t>(lower), static_cast<std::uint8_t>(kEdgeTypeOfAxes[upper & ~lower])};
        }
      };
      for (const auto& tet : kTetrahedra) {
        std::array<int, 4> in{}, out{};
        int n_in = 0, n_out = 0;
        for (int v : tet) ((mask >> v) & 1 ? in[n_in++] : out[n_out++]) = v;
        if (n_in == 0 || n_out == 0) continue;
        if (n_in == 1) {
          emit({{{in[0], out[0]}, {in[0], out[1]}, {in[0], out[2]}}}, in[0]);
        } else if (n_in == 3) {
          emit({{{in[0], out[0]}, {in[1], out[0]}, {in[2], out[0]}}}, in[0]);
        } else {
          // A quad on edges (in0,out0) (in0,out1) (in1,out1) (in1,out0), split along one diagonal.
          emit({{{in[0], out[0]}, {in[0], out[1]}, {in[1], out[1]}}}, in[0]);
          emit({{{in[0], out[0]}, {in[1], out[1]}, {in[1], out[0]}}}, in[1]);
        }
      }
    }
    return cases;
  }();
  return table;
}

template <typename T>
class Contour {
 public:
  Contour(const Grid3<T>& field, double level, int threads, double minimum_fraction)
      : field_(field),
        level_(level),
        threshold_(threshold_for(level)),
        minimum_fraction_(minimum_fraction),
        threads_(detail::surface_threads(threads)),
        nx_(field.size[0]),
        ny_(field.size[1]),
        nz_(field.size[2]),
        plane_(nx_ * ny_) {}

  Mesh run() {
    if (nx_ < 2 || ny_ < 2 || nz_ < 2)
      throw std::invalid_argument("contour_isosurface: the grid needs at least 2 samples per axis");
    find_active_rows();
    check_border();
    // Pass 1: vertices (crossing edges) owned by each plane and triangles of each cell layer.
    std::vector<std::int64_t> vertex_start(static_cast<std::size_t>(nz_) + 1, 0),
        triangle_start(static_cast<std::size_t>(nz_) + 1, 0);
    const auto& cases = cell_cases();
    std::vector<std::unique_ptr<Planes>> buffers(static_cast<std::size_t>(threads_));
    auto planes_of = [&](int worker) -> Planes& {
      auto& p = buffers[static_cast<std::size_t>(worker)];
      if (!p) p = std::make_unique<Planes>(plane_);
      return *p;
    };
    detail::parallel_chunks(nz_, threads_, [&](std::int64_t k, int worker) {
      Planes& planes = planes_of(worker);
      signs(k, planes.sign[0]);
      if (k + 1 < nz_) signs(k + 1, planes.sign[1]);
      masks(k, planes.sign[0], planes.sign[1], planes.mask[0]);
      std::int64_t vertices = 0, triangles = 0;
      for (std::int64_t s = 0; s < plane_; ++s) vertices += kBitCount[planes.mask[0][s]];
      if (k + 1 < nz_)
        for_cells(k, planes.sign[0], planes.sign[1], planes.cells,
                  [&](std::int64_t, std::int64_t, int mask) { triangles += cases[mask].triangles; });
      vertex_start[k + 1] = vertices;
      triangle_start[k + 1] = triangles;
    });
    for (std::int64_t k = 0; k < nz_; ++k)
      vertex_start[k + 1] += vertex_start[k], triangle_start[k + 1] += triangle_start[k];
    if (vertex_start[nz_] > std::numeric_limits<std::int32_t>::max())
      throw std::invalid_argument("contour_isosurface: more than 2^31 vertices; use a coarser grid");
    Mesh mesh;
    detail::reserve_mapped(mesh.positions, static_cast<std::size_t>(vertex_start[nz_]), threads_);
    detail::reserve_mapped(mesh.triangles, static_cast<std::size_t>(triangle_start[nz_]), threads_);
    mesh.positions.resize(static_cast<std::size_t>(vertex_start[nz_]));
    mesh.triangles.resize(static_cast<std::size_t>(triangle_start[nz_]));
    // Pass 2: positions and triangles, written at offsets known from pass 1, a slab of planes per chunk.
    constexpr std::int64_t kSlab = 4;
    detail::parallel_chunks((nz_ + kSlab - 1) / kSlab, threads_, [&](std::int64_t chunk, int worker) {
      const std::int64_t k0 = chunk * kSlab, k1 = std::min(nz_, k0 + kSlab);
      Planes& planes = planes_of(worker);
      // planes.*[0]: plane k, [1]: plane k + 1, sign[2]: plane k + 2.
      signs(k0, planes.sign[0]);
      if (k0 + 1 < nz_) signs(k0 + 1, planes.sign[1]);
      masks(k0, planes.sign[0], planes.sign[1], planes.mask[0]);
      firsts(k0, planes.mask[0], vertex_start[k0], planes.first[0]);
      for (std::int64_t k = k0; k < k1; ++k) {
        if (k + 1 < nz_) {
          if (k + 2 < nz_) signs(k + 2, planes.sign[2]);
          masks(k + 1, planes.sign[1], planes.sign[2], planes.mask[1]);
          firsts(k + 1, planes.mask[1], vertex_start[k + 1], planes.first[1]);
        }
        write_positions(k, planes.mask[0], vertex_start[k], mesh.positions);
        if (k + 1 < nz_) {
          std::int64_t next = triangle_start[k];
          for_cells(k, planes.sign[0], planes.sign[1], planes.cells, [&](std::int64_t i, std::int64_t j, int mask) {
            const CellCase& cell = cases[mask];
            for (int t = 0; t < cell.triangles; ++t) {
              Triangle& out = mesh.triangles[static_cast<std::size_t>(next++)];
              for (int e = 0; e < 3; ++e) {
                const CellEdge edge = cell.edges[t][e];
                const int c = edge.corner;
                const std::size_t layer = (c >> 2) & 1;
                const std::int64_t s = (j + ((c >> 1) & 1)) * nx_ + i + (c & 1);
                const unsigned below = planes.mask[layer][s] & ((1u << edge.type) - 1u);
                out[e] = static_cast<std::int32_t>(planes.first[layer][s] + kBitCount[below]);
              }
            }
          });
        }
        std::swap(planes.sign[0], planes.sign[1]);
        std::swap(planes.sign[1], planes.sign[2]);
        std::swap(planes.mask[0], planes.mask[1]);
        std::swap(planes.first[0], planes.first[1]);
      }
    });
    return mesh;
  }

 private:
  struct Planes {
    explicit Planes(std::int64_t n) {
      for (auto& s : sign) s.assign(static_cast<std::size_t>(n), 0);
      for (auto& m : mask) m.assign(static_cast<std::size_t>(n), 0);
      for (auto& f : first) f.assign(static_cast<std::size_t>(n), 0);
    }
    std::array<std::vector<std::uint8_t>, 3> sign;
    std::array<std::vector<std::uint8_t>, 2> mask;
    std::array<std::vector<std::int64_t>, 2> first;
    std::vector<std::uint8_t> cells;  // for_cells' row of cell masks
  };

  bool inside(std::int64_t s) const { return field_.values[static_cast<std::size_t>(s)] > threshold_; }

  // The largest T at most `level`: for x in T, x > threshold exactly when double(x) > level (no T lies
  // between it and level), and the comparison stays in T, which vectorizes.
  static T threshold_for(double level) {
    T t = static_cast<T>(level);
    if (static_cast<double>(t) > level) t = std::nextafter(t, -std::numeric_limits<T>::infinity());
    return t;
  }

  // Rows (j, k) holding an inside sample; everything else is skipped.
  void find_active_rows() {
    row_active_.assign(static_cast<std::size_t>(ny_ * nz_), 0);
    detail::parallel_chunks(nz_, threads_, [&](std::int64_t k, int) {
      for (std::int64_t j = 0; j < ny_; ++j) {
        const std::int64_t start = k * plane_ + j * nx_;
        bool any = false;
        for (std::int64_t i = 0; i < nx_ && !any; ++i) any = inside(start + i);
        row_active_[static_cast<std::size_t>(k * ny_ + j)] = any;
      }
    });
  }
  bool row_active(std::int64_t j, std::int64_t k) const {
    return j < ny_ && k < nz_ && row_active_[static_cast<std::size_t>(k * ny_ + j)];
  }
  // Whether rows j, j + 1 of planes k, k + 1 hold an inside sample (the rows the cells and upward edges
  // of row (j, k) touch).
  bool group_active(std::int64_t j, std::int64_t k) const {
    return row_active(j, k) || row_active(j + 1, k) || row_active(j, k + 1) || row_active(j + 1, k + 1);
  }

  void check_border() const {
    bool bad = false;
    for (std::int64_t k = 0; k < nz_ && !bad; ++k)
      for (std::int64_t j = 0; j < ny_ && !bad; ++j) {
        if (!row_active(j, k)) continue;
        const std::int64_t start = k * plane_ + j * nx_;
        bad = k == 0 || k == nz_ - 1 || j == 0 || j == ny_ - 1 || inside(start) || inside(start + nx_ - 1);
      }
    if (bad)
      throw std::invalid_argument("contour_isosurface: the surface reaches the border of the grid; pad the grid");
  }

  void signs(std::int64_t k, std::vector<std::uint8_t>& out) const {
    for (std::int64_t j = 0; j < ny_; ++j) {
      std::uint8_t* row = out.data() + j * nx_;
      if (!row_active(j, k)) {
        std::memset(row, 0, static_cast<std::size_t>(nx_));
        continue;
      }
      // Locals: writes through a byte pointer could alias the members, which would stop vectorization.
      const T* values = field_.values.data() + k * plane_ + j * nx_;
      const std::int64_t n = nx_;
      const T threshold = threshold_;
      for (std::int64_t i = 0; i < n; ++i) row[i] = values[i] > threshold;
    }
  }

  // Bit e of mask[s]: the edge of type e from sample s of plane k crosses the level. Only rows of active
  // groups are filled (the others are zero); such a row has a row after it and a plane above it (the
  // outer layer holds no inside sample), so only the last sample of the row needs bounds.
  void masks(std::int64_t k, const std::vector<std::uint8_t>& here, const std::vector<std::uint8_t>& above,
             std::vector<std::uint8_t>& out) const {
    for (std::int64_t j = 0; j < ny_; ++j) {
      std::uint8_t* row = out.data() + j * nx_;
      if (!group_active(j, k)) {
        std::memset(row, 0, static_cast<std::size_t>(nx_));
        continue;
      }
      const std::uint8_t *h0 = here.data() + j * nx_, *h1 = h0 + nx_, *a0 = above.data() + j * nx_, *a1 = a0 + nx_;
      const std::int64_t n = nx_;  // a local: `row` could alias the members
      // Edge types (kEdgeOffset): 0 +x, 1 +y, 2 +z, 3 +x+y, 4 +x+z, 5 +y+z, 6 +x+y+z.
      for (std::int64_t i = 0; i + 1 < n; ++i) {
        const std::uint8_t own = h0[i];
        row[i] = static_cast<std::uint8_t>((h0[i + 1] ^ own) | (h1[i] ^ own) << 1 | (a0[i] ^ own) << 2 |
                                           (h1[i + 1] ^ own) << 3 | (a0[i + 1] ^ own) << 4 | (a1[i] ^ own) << 5 |
                                           (a1[i + 1] ^ own) << 6);
      }
      const std::int64_t i = n - 1;
      const std::uint8_t own = h0[i];
      row[i] = static_cast<std::uint8_t>((h1[i] ^ own) << 1 | (a0[i] ^ own) << 2 | (a1[i] ^ own) << 5);
    }
  }

  // first[s]: the index of the first vertex of sample s of plane k (vertices are numbered by sample,
  // then by edge type).
  void firsts(std::int64_t k, const std::vector<std::uint8_t>& mask, std::int64_t start,
              std::vector<std::int64_t>& out) const {
    std::int64_t next = start;
    for (std::int64_t j = 0; j < ny_; ++j) {
      if (!group_active(j, k)) continue;  // no crossing edge in this row: never looked up
      for (std::int64_t i = 0; i < nx_; ++i) {
        const auto s = j * nx_ + i;
        out[s] = next;
        next += kBitCount[mask[s]];
      }
    }
  }

  void write_positions(std::int64_t k, const std::vector<std::uint8_t>& mask, std::int64_t start,
                       std::vector<Vec3>& positions) const {
    std::int64_t next = start;
    for (std::int64_t j = 0; j < ny_; ++j) {
      if (!group_active(j, k)) continue;
      for (std::int64_t i = 0; i < nx_; ++i) {
        unsigned bits = mask[j * nx_ + i];
        while (bits) {
          const int e = std::countr_zero(bits);
          bits &= bits - 1;
          const auto& o = kEdgeOffset[e];
          const std::int64_t a = field_.index(i, j, k), b = field_.index(i + o[0], j + o[1], k + o[2]);
          const double fa = field_.values[static_cast<std::size_t>(a)], fb = field_.values[static_cast<std::size_t>(b)];
          const double t = std::clamp((level_ - fa) / (fb - fa), minimum_fraction_, 1 - minimum_fraction_);
          const Vec3 pa = field_.point(i, j, k), pb = field_.point(i + o[0], j + o[1], k + o[2]);
          positions[static_cast<std::size_t>(next++)] = pa + t * (pb - pa);
        }
      }
    }
  }

  // visit(i, j, mask) for every cell of layer k (between planes k and k + 1) with corners on both sides.
  // The masks of a row of cells go to `cells` (nx - 1 of them, padded with zeros to a multiple of 8) in
  // one vectorized pass; runs of 8 cells all outside (0) or all inside (255), most of them, are then
  // passed over a word at a time.
  template <typename Visit>
  void for_cells(std::int64_t k, const std::vector<std::uint8_t>& here, const std::vector<std::uint8_t>& above,
                 std::vector<std::uint8_t>& cells, Visit&& visit) const {
    const std::int64_t n = nx_ - 1, words = (n + 7) / 8;  // locals: `cells` could alias the members
    cells.resize(static_cast<std::size_t>(words * 8));
    std::uint8_t* out = cells.data();
    for (std::int64_t i = n; i < words * 8; ++i) out[i] = 0;
    for (std::int64_t j = 0; j + 1 < ny_; ++j) {
      if (!group_active(j, k)) continue;
      const std::uint8_t *h0 = here.data() + j * nx_, *h1 = h0 + nx_, *a0 = above.data() + j * nx_, *a1 = a0 + nx_;
      for (std::int64_t i = 0; i < n; ++i)
        out[i] = static_cast<std::uint8_t>(h0[i] | h0[i + 1] << 1 | h1[i] << 2 | h1[i + 1] << 3 | a0[i] << 4 |
                                           a0[i + 1] << 5 | a1[i] << 6 | a1[i + 1] << 7);
      for (std::int64_t w = 0; w < words; ++w) {
        std::uint64_t word;
        std::memcpy(&word, out + 8 * w, sizeof word);
        if (word == 0 || word == ~std::uint64_t{0}) continue;
        for (std::int64_t i = 8 * w; i < 8 * w + 8; ++i)
          if (out[i] != 0 && out[i] != 255) visit(i, j, static_cast<int>(out[i]));
      }
    }
  }

  const Grid3<T>& field_;
  double level_;
  T threshold_;
  double minimum_fraction_;
  int threads_;
  std::int64_t nx_, ny_, nz_, plane_;
  std::vector<std::uint8_t> row_active_;
};

double checked_fraction(double minimum_fraction) {
  if (!(minimum_fraction >= 0 && minimum_fraction <= 0.5))
    throw std::invalid_argument("contour_isosurface: the minimum fraction must be in [0, 0.5]");
  return minimum_fraction;
}

}  // namespace

Mesh contour_isosurface(const Grid3<double>& field, double level, int threads, double minimum_fraction) {
  return Contour<double>(field, level, threads, checked_fraction(minimum_fraction)).run();
}
Mesh contour_isosurface(const Grid3<float>& field, double level, int threads, double minimum_fraction) {
  return Contour<float>(field, level, threads, checked_fraction(minimum_fraction)).run();
}

}  // namespace spheremap
