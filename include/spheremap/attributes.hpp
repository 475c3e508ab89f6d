// The names of the per-vertex attributes spheremap writes (PLY vertex properties): every producer and
// consumer spells them through these constants, so a name is changed in one place.
#pragma once

namespace spheremap::attributes {

// Atom provenance of a molecular surface's vertices (add_nearest_atoms, add_atom_provenance).
inline constexpr const char* kAtomId = "atomid";                  // integer: index into the atoms (the Mol* convention)
inline constexpr const char* kAtomSerial = "vertex_atom_serial";  // integer
inline constexpr const char* kResidueNumber = "vertex_residue_number";  // integer
inline constexpr const char* kModel = "vertex_model";                   // integer
inline constexpr const char* kAtomName = "vertex_atom_name";            // text
inline constexpr const char* kElement = "vertex_element";               // text
inline constexpr const char* kResidueName = "vertex_residue_name";      // text
inline constexpr const char* kInsertionCode = "vertex_insertion_code";  // text, empty when blank
inline constexpr const char* kChain = "vertex_chain";                   // text
inline constexpr const char* kBFactor = "vertex_b_factor";              // real: PDB and mmCIF files
inline constexpr const char* kCharge = "vertex_charge";                 // real: PQR files

// The map's outputs (write_map_outputs).
inline constexpr const char* kTheta = "theta";               // real: polar angle from the north pole, in [0, π]
inline constexpr const char* kPhi = "phi";                   // real: azimuth, in [0, 2π)
inline constexpr const char* kInputVertex = "input_vertex";  // integer: the vertex's index in the input file
inline constexpr const char* kNormalX = "nx";  // float: the surface's unit vertex normal (on both PLY files)
inline constexpr const char* kNormalY = "ny";
inline constexpr const char* kNormalZ = "nz";
inline constexpr const char* kRed = "red";  // uchar: the colour of the --color property (both PLY files)
inline constexpr const char* kGreen = "green";
inline constexpr const char* kBlue = "blue";
// Surface properties (properties/registry.hpp): float `vertex_<name>`, e.g. vertex_electrostatics.
inline constexpr const char* kPropertyPrefix = "vertex_";

}  // namespace spheremap::attributes
