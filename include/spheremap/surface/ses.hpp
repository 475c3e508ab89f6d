// Atoms to a solvent-excluded (Lee & Richards / Connolly) surface on a grid (stage: surface).
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap {

struct SurfaceOptions {
  double probe = 1.4;     // Å, the convention of MSMS, NanoShaper and PyMOL
  double grid = 0.5;      // Å between samples
  double max_grid_bytes = 4e9;  // refuse grids that would need more memory than this
};

/// Samples g(x) = (distance from x to the nearest valid probe centre) - probe, where valid probe centres
/// are the points outside every atom's sphere enlarged by the probe (outside the SAS) that a probe can
/// reach from outside the molecule. The SES encloses g > 0. Probe centres are the grid samples outside
/// the SAS connected to the grid border (flood fill; exact Euclidean distance transform), plus exact
/// points of the SAS surface next to them: radial projections of samples just inside each enlarged
/// sphere and samples of the circles where two enlarged spheres meet, which keep re-entrant regions
/// accurate below the grid spacing. Enclosed cavities are filled (not carved) for now; channels narrower
/// than the grid spacing are not passed by the flood fill.
/// Throws InputError if there are no atoms, a radius is not positive, or the grid would exceed
/// options.max_grid_bytes (the message says how much it needs and which spacing fits).
Grid3<double> solvent_excluded_field(const std::vector<Atom>& atoms, const SurfaceOptions& options);

/// The SES as a closed, outward-oriented 2-manifold (possibly several components: detached pieces),
/// with per-vertex provenance: integer attributes `atomid` (index into `atoms`),
/// `vertex_atom_serial`, `vertex_residue_number`, `vertex_model`; the atom of a vertex is the one whose
/// van der Waals sphere is nearest (smallest |x - centre| - radius).
Mesh solvent_excluded_surface(const std::vector<Atom>& atoms, const SurfaceOptions& options);

/// The contour g = 0 of a field from solvent_excluded_field (possibly repaired by cut_handles), with the
/// same provenance attributes as solvent_excluded_surface.
Mesh surface_from_field(const Grid3<double>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options);

}  // namespace spheremap
