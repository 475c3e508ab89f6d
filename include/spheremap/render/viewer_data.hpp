// What the viewer shows of a map: the surface with its atom provenance and the per-vertex values it
// carries, beside its sphere.
#pragma once

#include <string>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/properties/property.hpp"
#include "spheremap/render/viewer.hpp"

namespace spheremap {

/// The viewer's data for `surface` (the mapped mesh) and its map `sphere` (one unit vector per vertex,
/// superposed on the surface). Atoms: one per distinct `atomid` of the surface, in order of first
/// appearance, named by its vertex_chain / vertex_residue_name / vertex_residue_number /
/// vertex_insertion_code / vertex_atom_name attributes (empty when absent); no atoms for a mesh without
/// `atomid`. Properties, in this order: octant (of the sphere point, the order of the octant metrics; always),
/// chain, residue number (the sequence position of the paper's Figure 8), B-factor (Å²) and charge (e,
/// diverging) when the surface carries them; default ranges from the values (colour_scale's data_range).
/// Preconditions: sphere.size() == surface.vertex_count(); the mesh's invariants (mesh.hpp).
/// Throws std::invalid_argument if the sizes differ.
ViewerData viewer_data_for_map(const Mesh& surface, const std::vector<Vec3>& sphere, std::string title);

/// The same with `properties` (e.g. MapJobResult::properties, or the pictures' properties) instead of those
/// read from the surface's attributes, in their order: each with its default range, else its data's range
/// (data_range). Preconditions as above; every property has one value per vertex.
/// Throws std::invalid_argument if the sizes differ.
ViewerData viewer_data_for_map(const Mesh& surface, const std::vector<Vec3>& sphere, std::string title,
                               const std::vector<SurfaceProperty>& properties);

}  // namespace spheremap
