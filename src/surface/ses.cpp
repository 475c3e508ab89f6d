#include "spheremap/surface/ses.hpp"

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "../util/parallel.hpp"
#include "../util/rounding.hpp"
#include "../util/stage_timer.hpp"
#include "field_lowering.hpp"
#include "pockets.hpp"
#include "probe_centres.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/distance_transform.hpp"
#include "spheremap/surface/nearest_atoms.hpp"

namespace spheremap {
namespace {

// The grid of the field (no values yet): the atoms' box with a margin of the largest radius + probe + 3
// steps. Throws InputError without atoms, for a radius that is not positive, or when the field (and
// options.extra_bytes_per_sample) would exceed options.max_grid_bytes.
template <typename T>
Grid3<T> grid_around(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  if (atoms.empty()) throw InputError("no atoms to build a surface from");
  const double h = options.grid, probe = options.probe;
  double largest_radius = 0;
  Vec3 lo = atoms.front().position, hi = lo;
  for (const auto& a : atoms) {
    if (!(a.radius > 0))
      throw InputError(fmt::format("atom {} ({}) has radius {}; radii must be positive", a.serial, a.name, a.radius));
    largest_radius = std::max(largest_radius, a.radius);
    for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], a.position[d]), hi[d] = std::max(hi[d], a.position[d]);
  }
  const double margin = largest_radius + probe + 3 * h;
  Grid3<T> field;
  field.spacing = h;
  for (int d = 0; d < 3; ++d) {
    field.origin[d] = lo[d] - margin;
    field.size[d] = detail::ceil_to_int((hi[d] - lo[d] + 2 * margin) / h) + 1;
  }
  // The field is the only per-sample array (built in place); the surface probe centres (24 bytes each)
  // and the atom lists are small beside it.
  const double samples =
      static_cast<double>(field.size[0]) * static_cast<double>(field.size[1]) * static_cast<double>(field.size[2]);
  const double per_sample = static_cast<double>(sizeof(T)) + options.extra_bytes_per_sample;
  const double bytes = samples * per_sample;
  if (bytes > options.max_grid_bytes) {
    const double fitting = h * std::cbrt(bytes / options.max_grid_bytes) * 1.01;
    throw InputError(
        fmt::format("a {} x {} x {} grid at {} Å would need {:.1f} GB ({:g} bytes per sample; budget {:.1f} GB); use "
                    "--grid {:.2f} or coarser",
                    field.size[0], field.size[1], field.size[2], h, bytes / 1e9, per_sample,
                    options.max_grid_bytes / 1e9, std::ceil(fitting * 100) / 100));
  }
  return field;
}

// Squared distances (grid units²) to g = distance * h - probe. About half the samples are probe centres
// (0): runs of them take their value, -probe, without the square root that bounds this loop
// (sqrt(0) h - probe is exactly -probe).
template <typename T>
void distances_to_field(Grid3<T>& field, double probe, int threads) {
  const double h = field.spacing;
  const std::int64_t plane = field.size[0] * field.size[1];
  constexpr std::int64_t kRun = 16;
  const auto at_centre = static_cast<T>(-probe);
  detail::parallel_chunks(field.size[2], threads, [&](std::int64_t k, int) {
    T* values = field.values.data() + k * plane;
    for (std::int64_t first = 0; first < plane; first += kRun) {
      T* run = values + first;
      const std::int64_t length = std::min(kRun, plane - first);
      bool zeros = true;
      for (std::int64_t s = 0; s < length; ++s) zeros &= run[s] == T(0);
      if (zeros) {
        std::fill_n(run, length, at_centre);
        continue;
      }
      for (std::int64_t s = 0; s < length; ++s)
        run[s] = static_cast<T>(std::sqrt(static_cast<double>(run[s])) * h - probe);
    }
  });
}

template <typename T>
Grid3<T> excluded_field(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  Grid3<T> field = grid_around<T>(atoms, options);
  const double h = options.grid, probe = options.probe;
  const int threads = detail::surface_threads(options.threads);
  detail::StageTimer clock("surface");
  detail::reserve_mapped(field.values, static_cast<std::size_t>(field.count()), threads);
  field.values.assign(static_cast<std::size_t>(field.count()), static_cast<T>(detail::kUnreached));
  // Samples outside the SAS (outside every sphere of radius r + probe) are probe centres; only those a
  // probe reaches from outside count (as for MSMS's outer surface), unless cavities are carved too.
  detail::mark_accessible_surface(field, atoms, probe, threads);
  clock.lap("accessible");
  const detail::Pockets pockets = detail::flood_and_label_pockets(field, threads);
  clock.lap("flood");
  // Which pockets a probe reaches through passages narrower than a step, and more probe centres, on the
  // SAS surface itself (found before the transform, while carving samples are exactly the zeros).
  const std::vector<Vec3> centres =
      detail::surface_probe_centres(field, atoms, probe, pockets, options.carve_cavities, threads, clock);
  clock.lap("sort");
  squared_distance_transform_in_place(field, threads);
  clock.lap("transform");
  // Each surface centre lowers the samples within probe + sqrt(3) steps of it. That makes g exact (for
  // this set of centres) wherever |g| < sqrt(3) steps, which covers both ends of every lattice edge the
  // surface crosses (g changes by at most the edge length along it), so the contour is the same as with
  // an unbounded reach; deeper inside, the grid samples alone give g.
  // Samples within probe/h - sqrt(3) steps of a lattice centre need no lowering: they stay outside and
  // no edge the surface crosses reaches them (a neighbour along a lattice edge, at most sqrt(3) steps
  // away, is within probe/h of that centre, hence not inside). 0.01 of a step keeps rounding away from
  // that bound; zeros cannot be lowered anyway.
  const double free_reach = probe / h - std::sqrt(3.0) - 0.01;
  detail::lower_near_centres(field, centres, probe / h + std::sqrt(3.0) * (1 + 1e-9),
                             free_reach > 0 ? free_reach * free_reach : 0.0, threads, options.use_avx2);
  clock.lap("lower");
  distances_to_field(field, probe, threads);
  clock.lap("root");
  return field;
}

template <typename T>
Mesh contour_with_atoms(const Grid3<T>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  Mesh mesh = contour_isosurface(field, 0.0, options.threads, options.contour_minimum_fraction);
  add_nearest_atoms(mesh, atoms, options);
  return mesh;
}

}  // namespace

Grid3<double> solvent_excluded_field(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return excluded_field<double>(atoms, options);
}

Grid3<float> solvent_excluded_field_float(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return excluded_field<float>(atoms, options);
}

Mesh solvent_excluded_surface(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  Mesh mesh;
  {
    const Grid3<float> field = solvent_excluded_field_float(atoms, options);
    detail::StageTimer clock("surface");
    mesh = contour_isosurface(field, 0.0, options.threads, options.contour_minimum_fraction);
    clock.lap("contour");
  }
  detail::StageTimer clock("surface");
  add_nearest_atoms(mesh, atoms, options);
  clock.lap("provenance");
  return mesh;
}

Mesh surface_from_field(const Grid3<double>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return contour_with_atoms(field, atoms, options);
}

Mesh surface_from_field(const Grid3<float>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return contour_with_atoms(field, atoms, options);
}

}  // namespace spheremap
