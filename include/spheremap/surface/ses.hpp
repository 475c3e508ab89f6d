// Atoms to a solvent-excluded (Lee & Richards / Connolly) surface on a grid (stage: surface).
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap {

struct SurfaceOptions {
  double probe = 1.4;  // Å, the convention of MSMS, NanoShaper and PyMOL
  double grid = 0.5;   // Å between samples
  /// Refuse fields whose grid would need more memory than this: one value per sample (8 bytes for
  /// solvent_excluded_field, 4 for solvent_excluded_field_float and solvent_excluded_surface); the field
  /// is built in place, with no other per-sample array. The mesh comes on top (see solvent_excluded_surface).
  double max_grid_bytes = 4e9;
  /// Bytes per grid sample that the caller will need beside the field (e.g. 3 for the handle repair:
  /// a state byte and two bytes of distance per sample); counted against max_grid_bytes too.
  double extra_bytes_per_sample = 0;
  /// false: only probe positions reachable from outside the molecule carve (MSMS's outer surface;
  /// enclosed cavities are filled), also through channels narrower than the grid. true: probe positions
  /// in enclosed pockets carve too, so each cavity that holds a probe becomes its own closed component,
  /// facing into the cavity.
  bool carve_cavities = false;
  /// Vertices of the mesh are kept at least this fraction of a step away from grid samples
  /// (contour_isosurface's minimum_fraction): 0.1 makes no sliver triangles but biases the area upwards;
  /// 0 is the plain linear interpolation.
  double contour_minimum_fraction = kContourMinimumFraction;
  /// Threads for the surface stage (0: one per hardware thread). Results do not depend on it.
  int threads = 0;
  /// Let the single-precision field use AVX2 instructions where the processor has them (eight samples
  /// per operation). Results do not depend on it; false is there to test that.
  bool use_avx2 = true;
};

/// Samples g(x) = (distance from x to the nearest valid probe centre) - probe on a grid around the atoms;
/// the SES encloses g > 0. Valid probe centres are the points outside the SAS (every atom's sphere
/// enlarged by the probe) that a probe rolling on the SAS reaches from outside the molecule, as MSMS
/// decides (with carve_cavities also those in enclosed pockets): the grid samples so reached, plus exact
/// points of the SAS surface, which keep re-entrant regions accurate below the grid spacing and let
/// channels narrower than a step through. g is exact (for those centres) wherever |g| < sqrt(3) steps,
/// i.e. at both ends of every lattice edge the surface crosses. Multithreaded (options.threads); the
/// result is the same for any number of threads.
/// Preconditions: options.grid > 0, options.probe >= 0, finite atom positions.
/// Throws InputError if there are no atoms, a radius is not positive, or the grid would exceed
/// options.max_grid_bytes (the message says how much it needs and which spacing fits).
Grid3<double> solvent_excluded_field(const std::vector<Atom>& atoms, const SurfaceOptions& options);

/// The same field in single precision: half the memory. Values differ from solvent_excluded_field by
/// float rounding (about 1e-7 Å), which moves contour vertices by about 1e-5 of a step (at most 1e-4 in
/// the tests) and leaves the classification of samples, hence the mesh's connectivity, the same except
/// for samples within about 1e-7 Å of the surface. Preconditions and throws as solvent_excluded_field.
Grid3<float> solvent_excluded_field_float(const std::vector<Atom>& atoms, const SurfaceOptions& options);

/// The SES as a closed, outward-oriented 2-manifold (possibly several components: detached pieces,
/// and with carve_cavities the cavities), with per-vertex provenance: integer attributes `atomid`
/// (index into `atoms`), `vertex_atom_serial`, `vertex_residue_number`, `vertex_model`; the atom of a
/// vertex is the one whose van der Waals sphere is nearest (smallest |x - centre| - radius, ties to the
/// smallest index). Uses the single-precision field, freed before provenance is added: peak memory is
/// about 4 bytes per grid sample plus 24 bytes per triangle (positions and triangles; the provenance
/// attributes, 8 bytes per triangle, come after the field is freed).
/// Preconditions and throws as solvent_excluded_field.
Mesh solvent_excluded_surface(const std::vector<Atom>& atoms, const SurfaceOptions& options);

/// The contour g = 0 of a field from solvent_excluded_field (possibly repaired: repair/handle_repair.hpp), with the
/// same provenance attributes as solvent_excluded_surface.
/// Preconditions: `field` was built from `atoms` (every sample of its outer layer outside).
/// Throws std::invalid_argument as contour_isosurface does.
Mesh surface_from_field(const Grid3<double>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options);
Mesh surface_from_field(const Grid3<float>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options);

}  // namespace spheremap
