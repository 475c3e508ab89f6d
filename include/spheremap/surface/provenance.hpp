// Which atom each surface vertex came from, as per-vertex attributes (stage: surface).
#pragma once

#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/molecule/structure.hpp"

namespace spheremap {

/// From the integer attribute `atomid` (index into `atoms`, the Mol* convention), sets the full provenance
/// of every vertex: integer `vertex_atom_serial`, `vertex_residue_number`, `vertex_model`; text
/// `vertex_atom_name`, `vertex_element`, `vertex_residue_name`, `vertex_insertion_code` (empty when
/// blank) and `vertex_chain`; real `vertex_b_factor` when every atom has a B-factor (PDB, mmCIF) and
/// `vertex_charge` when every atom has a charge (PQR), each removed otherwise. Existing attributes of
/// those names are replaced.
/// Throws std::invalid_argument if `atomid` is missing or an index is out of range.
void add_atom_provenance(Mesh& mesh, const std::vector<Atom>& atoms);

}  // namespace spheremap
