// The atom each surface vertex came from: its nearest van der Waals sphere (stage: surface).
#pragma once

#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/surface/ses.hpp"

namespace spheremap {

/// Sets the integer attributes `atomid` (index into `atoms`), `vertex_atom_serial`,
/// `vertex_residue_number` and `vertex_model` on every vertex of `mesh` (replacing any of those names):
/// the atom whose van der Waals sphere is nearest (smallest |x - centre| - radius, ties to the smallest
/// index). Multithreaded (options.threads; the only option read); the result does not depend on it.
/// Preconditions: radii positive; positions finite.
/// Throws InputError if the mesh has vertices and `atoms` is empty.
void add_nearest_atoms(Mesh& mesh, const std::vector<Atom>& atoms, const SurfaceOptions& options);

}  // namespace spheremap
