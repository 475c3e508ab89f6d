#include "spheremap/surface/ses.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <unordered_map>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/surface/contour.hpp"

namespace spheremap {
namespace {

// Atoms bucketed in cubic cells, for "which atoms are near this point" queries.
class AtomCells {
 public:
  AtomCells(const std::vector<Atom>& atoms, double cell) : atoms_(atoms), cell_(cell) {
    for (std::int32_t a = 0; a < static_cast<std::int32_t>(atoms.size()); ++a) cells_[key(cell_of(atoms[a].position))].push_back(a);
  }
  // Calls visit(atom index) for every atom in the cells within `reach` of p (a superset of the atoms
  // whose centre is within `reach`).
  template <typename Visit>
  void near(const Vec3& p, double reach, Visit&& visit) const {
    const auto c = cell_of(p);
    const auto span = static_cast<std::int64_t>(std::ceil(reach / cell_));
    for (std::int64_t dz = -span; dz <= span; ++dz)
      for (std::int64_t dy = -span; dy <= span; ++dy)
        for (std::int64_t dx = -span; dx <= span; ++dx) {
          const auto it = cells_.find(key({c[0] + dx, c[1] + dy, c[2] + dz}));
          if (it == cells_.end()) continue;
          for (auto a : it->second) visit(a);
        }
  }

 private:
  std::array<std::int64_t, 3> cell_of(const Vec3& p) const {
    return {static_cast<std::int64_t>(std::floor(p[0] / cell_)), static_cast<std::int64_t>(std::floor(p[1] / cell_)),
            static_cast<std::int64_t>(std::floor(p[2] / cell_))};
  }
  static std::uint64_t key(const std::array<std::int64_t, 3>& c) {
    return (static_cast<std::uint64_t>(c[0] & 0x1FFFFF) << 42) | (static_cast<std::uint64_t>(c[1] & 0x1FFFFF) << 21) |
           static_cast<std::uint64_t>(c[2] & 0x1FFFFF);
  }
  const std::vector<Atom>& atoms_;
  double cell_;
  std::unordered_map<std::uint64_t, std::vector<std::int32_t>> cells_;
};

}  // namespace

Grid3<double> solvent_excluded_field(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  if (atoms.empty()) throw InputError("no atoms to build a surface from");
  const double h = options.grid, probe = options.probe;
  double largest_radius = 0;
  Vec3 lo = atoms.front().position, hi = lo;
  for (const auto& a : atoms) {
    if (!(a.radius > 0)) throw InputError(fmt::format("atom {} ({}) has radius {}; radii must be positive", a.serial, a.name, a.radius));
    largest_radius = std::max(largest_radius, a.radius);
    for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], a.position[d]), hi[d] = std::max(hi[d], a.position[d]);
  }
  const double margin = largest_radius + probe + 3 * h;
  Grid3<double> field;
  field.spacing = h;
  for (int d = 0; d < 3; ++d) {
    field.origin[d] = lo[d] - margin;
    field.size[d] = static_cast<std::int64_t>(std::ceil((hi[d] - lo[d] + 2 * margin) / h)) + 1;
  }
  const double samples = static_cast<double>(field.size[0]) * static_cast<double>(field.size[1]) * static_cast<double>(field.size[2]);
  const double bytes = samples * (sizeof(double) + 1);
  if (bytes > options.max_grid_bytes) {
    const double fitting = h * std::cbrt(bytes / options.max_grid_bytes) * 1.01;
    throw InputError(fmt::format("a {} x {} x {} grid at {} Å would need {:.1f} GB (budget {:.1f} GB); use --grid {:.2f} or coarser",
                                 field.size[0], field.size[1], field.size[2], h, bytes / 1e9, options.max_grid_bytes / 1e9,
                                 std::ceil(fitting * 100) / 100));
  }
  const auto [nx, ny, nz] = field.size;

  // Samples outside the SAS (outside every sphere of radius r + probe) are probe centres.
  Grid3<std::uint8_t> outside;
  outside.size = field.size;
  outside.origin = field.origin;
  outside.spacing = h;
  outside.values.assign(static_cast<std::size_t>(outside.count()), 1);
  for (const auto& a : atoms) {
    const double reach = a.radius + probe;
    const auto first = [&](int d) { return std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((a.position[d] - reach - field.origin[d]) / h))); };
    const auto last = [&](int d) { return std::min<std::int64_t>(field.size[d] - 1, static_cast<std::int64_t>(std::floor((a.position[d] + reach - field.origin[d]) / h))); };
    for (std::int64_t k = first(2); k <= last(2); ++k)
      for (std::int64_t j = first(1); j <= last(1); ++j)
        for (std::int64_t i = first(0); i <= last(0); ++i)
          if (squared_distance(field.point(i, j, k), a.position) < reach * reach) outside.values[outside.index(i, j, k)] = 0;
  }
  // Only probe positions connected to the outside count (as for MSMS's outer surface): flood the outside
  // samples from the grid border; enclosed pockets are left unmarked and end up filled.
  {
    std::vector<std::int64_t> queue;
    for (std::int64_t s = 0; s < outside.count(); ++s) {
      const std::int64_t i = s % nx, j = (s / nx) % ny, k = s / (nx * ny);
      if ((i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1) && outside.values[s] == 1) {
        outside.values[s] = 2;
        queue.push_back(s);
      }
    }
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const auto s = queue[head];
      const std::int64_t i = s % nx, j = (s / nx) % ny, k = s / (nx * ny);
      const std::int64_t neighbours[6] = {i > 0 ? s - 1 : -1, i + 1 < nx ? s + 1 : -1, j > 0 ? s - nx : -1,
                                          j + 1 < ny ? s + nx : -1, k > 0 ? s - nx * ny : -1, k + 1 < nz ? s + nx * ny : -1};
      for (auto t : neighbours)
        if (t >= 0 && outside.values[t] == 1) outside.values[t] = 2, queue.push_back(t);
    }
    for (auto& v : outside.values) v = v == 2 ? 1 : 0;
  }
  Grid3<double> squared = squared_distance_transform(outside);
  for (auto& d : squared.values) d *= h * h;

  // More probe centres, on the SAS surface itself: in crevices narrower than a grid step no sample is
  // outside the SAS, yet a probe fits. Every sample just inside an enlarged sphere projects radially onto
  // it; the projection is a probe centre when no other enlarged sphere covers it. Each centre lowers the
  // distance of the inside samples within probe + 2 steps of it.
  const AtomCells cells(atoms, largest_radius + probe);
  const auto window = static_cast<std::int64_t>(std::ceil((probe + 2 * h) / h));
  auto add_probe_centre = [&](const Vec3& centre) {
    const auto ci = static_cast<std::int64_t>(std::llround((centre[0] - field.origin[0]) / h));
    const auto cj = static_cast<std::int64_t>(std::llround((centre[1] - field.origin[1]) / h));
    const auto ck = static_cast<std::int64_t>(std::llround((centre[2] - field.origin[2]) / h));
    // A centre on the SAS surface counts when a connected outside sample is next to it.
    bool connected = false;
    for (std::int64_t c = std::max<std::int64_t>(0, ck - 1); c <= std::min(nz - 1, ck + 1) && !connected; ++c)
      for (std::int64_t b = std::max<std::int64_t>(0, cj - 1); b <= std::min(ny - 1, cj + 1) && !connected; ++b)
        for (std::int64_t a = std::max<std::int64_t>(0, ci - 1); a <= std::min(nx - 1, ci + 1) && !connected; ++a)
          connected = outside.values[outside.index(a, b, c)] != 0;
    if (!connected) return;
    for (std::int64_t c = std::max<std::int64_t>(0, ck - window); c <= std::min(nz - 1, ck + window); ++c)
      for (std::int64_t b = std::max<std::int64_t>(0, cj - window); b <= std::min(ny - 1, cj + window); ++b)
        for (std::int64_t a = std::max<std::int64_t>(0, ci - window); a <= std::min(nx - 1, ci + window); ++a) {
          const auto t = squared.index(a, b, c);
          if (outside.values[t]) continue;
          const double d = squared_distance(field.point(a, b, c), centre);
          if (d < squared.values[t]) squared.values[t] = d;
        }
  };
  for (std::int32_t index = 0; index < static_cast<std::int32_t>(atoms.size()); ++index) {
    const auto& atom = atoms[index];
    const double reach = atom.radius + probe;
    const auto first = [&](int d) { return std::max<std::int64_t>(0, static_cast<std::int64_t>(std::ceil((atom.position[d] - reach - field.origin[d]) / h))); };
    const auto last = [&](int d) { return std::min<std::int64_t>(field.size[d] - 1, static_cast<std::int64_t>(std::floor((atom.position[d] + reach - field.origin[d]) / h))); };
    for (std::int64_t k = first(2); k <= last(2); ++k)
      for (std::int64_t j = first(1); j <= last(1); ++j)
        for (std::int64_t i = first(0); i <= last(0); ++i) {
          const Vec3 x = field.point(i, j, k);
          const double distance = norm(x - atom.position);
          if (distance >= reach || distance < reach - h || distance == 0) continue;
          const Vec3 centre = atom.position + (reach / distance) * (x - atom.position);
          bool covered = false;
          cells.near(centre, largest_radius + probe, [&](std::int32_t other) {
            if (covered || other == index) return;
            const double other_reach = atoms[other].radius + probe;
            covered = squared_distance(centre, atoms[other].position) < other_reach * other_reach;
          });
          if (!covered) add_probe_centre(centre);
        }
  }
  // Probe centres touching two atoms lie on the circle where their enlarged spheres meet: these shape the
  // re-entrant (concave) parts of the surface, so the circles are sampled every half grid step.
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(atoms.size()); ++i) {
    const double reach_i = atoms[i].radius + probe;
    cells.near(atoms[i].position, 2 * (largest_radius + probe), [&](std::int32_t j) {
      if (j <= i) return;
      const double reach_j = atoms[j].radius + probe;
      const Vec3 axis = atoms[j].position - atoms[i].position;
      const double d = norm(axis);
      if (d >= reach_i + reach_j || d <= std::abs(reach_i - reach_j) || d == 0) return;
      const double along = (d * d + reach_i * reach_i - reach_j * reach_j) / (2 * d);
      const double circle_radius = std::sqrt(std::max(0.0, reach_i * reach_i - along * along));
      const Vec3 unit = (1 / d) * axis;
      const Vec3 centre = atoms[i].position + along * unit;
      const Vec3 helper = std::abs(unit[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
      const Vec3 u = normalized(cross(unit, helper));
      const Vec3 v = cross(unit, u);
      const auto steps = std::max<std::int64_t>(8, static_cast<std::int64_t>(std::ceil(2 * std::numbers::pi * circle_radius / (0.5 * h))));
      for (std::int64_t step = 0; step < steps; ++step) {
        const double angle = 2 * std::numbers::pi * static_cast<double>(step) / static_cast<double>(steps);
        const Vec3 point = centre + circle_radius * (std::cos(angle) * u + std::sin(angle) * v);
        bool covered = false;
        cells.near(point, largest_radius + probe, [&](std::int32_t other) {
          if (covered || other == i || other == j) return;
          const double other_reach = atoms[other].radius + probe;
          covered = squared_distance(point, atoms[other].position) < other_reach * other_reach;
        });
        if (!covered) add_probe_centre(point);
      }
    });
  }
  field.values.resize(squared.values.size());
  for (std::size_t s = 0; s < field.values.size(); ++s) field.values[s] = std::sqrt(squared.values[s]) - probe;
  return field;
}

Mesh solvent_excluded_surface(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return surface_from_field(solvent_excluded_field(atoms, options), atoms, options);
}

Mesh surface_from_field(const Grid3<double>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  Mesh mesh = contour_isosurface(field, 0.0);
  double largest_radius = 0;
  for (const auto& a : atoms) largest_radius = std::max(largest_radius, a.radius);
  const AtomCells cells(atoms, largest_radius + options.probe);
  auto& atom_index = mesh.integer_attributes["atomid"];
  auto& serial = mesh.integer_attributes["vertex_atom_serial"];
  auto& residue = mesh.integer_attributes["vertex_residue_number"];
  auto& model = mesh.integer_attributes["vertex_model"];
  for (const auto& p : mesh.positions) {
    // A surface point is within probe + grid of its nearest atom's sphere.
    double best = std::numeric_limits<double>::infinity();
    std::int32_t chosen = 0;
    cells.near(p, largest_radius + options.probe + 2 * options.grid, [&](std::int32_t index) {
      const double gap = norm(p - atoms[index].position) - atoms[index].radius;
      if (gap < best || (gap == best && index < chosen)) best = gap, chosen = index;
    });
    atom_index.push_back(chosen);
    serial.push_back(atoms[chosen].serial);
    residue.push_back(atoms[chosen].residue_number);
    model.push_back(atoms[chosen].model);
  }
  return mesh;
}

}  // namespace spheremap
