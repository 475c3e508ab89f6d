// Charges of a structure's atoms, for the built-in electrostatics: from a PQR file, from pdb2pqr run for
// the user, or from a table of formal charges.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/molecule/structure.hpp"
#include "spheremap/properties/coulomb.hpp"

namespace spheremap {

/// The charges of a structure, as the potential needs them and as the report names them.
struct ChargeAssignment {
  /// Every charge the potential sums: the structure's atoms with their charge, then the atoms a PQR adds
  /// to residues of the structure (the hydrogens pdb2pqr builds, a missing OXT or side chain). Those added
  /// atoms carry charge but make no surface: they are not in the structure's atom list.
  PointCharges points;
  std::vector<double> atom_charges;   // per atom of the structure (e), in its order; 0 for an unmatched one
  std::vector<bool> atom_matched;     // per atom of the structure: the source gave its charge
  std::string source;                 // "formal", "pdb2pqr (AMBER)", "PQR file.pqr"
  std::int64_t atoms_charged = 0;     // structure atoms that got a charge from the source (even 0.0)
  std::int64_t atoms_unmatched = 0;   // structure atoms the source has no charge for (charge 0, or formal)
  std::int64_t added_atoms = 0;       // PQR atoms of the structure's residues that it lacks (in `points`)
  std::int64_t added_hydrogens = 0;   // of which hydrogens
  std::int64_t pqr_atoms_unused = 0;  // PQR atoms of residues the structure does not have (ignored)
  double net_charge = 0;              // Σ of `points` (e)
  std::vector<std::string> warnings;
};

/// The charge of one atom in the built-in formal table, given its place in its chain. Documented in
/// docs (and formal_charges.cpp): ASP OD1/OD2 and GLU OE1/OE2 -1/2 each; LYS NZ +1; ARG NH1/NH2 +1/2 each;
/// HIS neutral (HIP/HSP: ND1/NE2 +1/2 each); CYM SG -1; N of a chain's first amino acid +1 and O/OXT of its
/// last -1/2 each (-1 on O without OXT), unless capped (ACE, NME, ...); nucleic-acid phosphates OP1/OP2
/// (O1P/O2P) -1/2 each; monatomic ions by residue name (NA +1, MG +2, CL -1, ...); every other atom 0.
struct TerminusFlags {
  bool n_terminus = false;  // the atom's residue is the first amino acid of its chain
  bool c_terminus = false;  // ... the last one
  bool has_oxt = false;     // the residue has an OXT atom
};
double formal_charge(const std::string& residue_name, const std::string& atom_name, const TerminusFlags& where);

/// True when the residue name is in the formal table (a standard or protonation-variant amino acid, a
/// nucleotide, water or a known ion); the atoms of other residues (ligands, modified residues) get 0.
bool formal_table_knows(const std::string& residue_name);

/// Charges of every atom from the formal table (chain termini found per chain, in file order, among the
/// residues the table knows as amino acids). Warns with the names of residues the table does not know.
/// Never throws (but std::bad_alloc).
ChargeAssignment formal_charges(const std::vector<Atom>& atoms);

/// Matches a PQR's atoms to the structure's by chain, residue number, insertion code and atom name (names
/// compared with '*' read as '\'', O1P/O2P as OP1/OP2 and C5M as C7, as old files and pdb2pqr differ). Structure atoms
/// without a match get 0 and are counted; PQR atoms of the structure's residues that match no structure
/// atom (hydrogens, rebuilt atoms) are added as charges; PQR atoms of other residues are counted, unused.
/// `source` names the source in the result. Throws std::invalid_argument if a PQR atom has no charge.
ChargeAssignment match_pqr_charges(const std::vector<Atom>& atoms, const std::vector<Atom>& pqr_atoms,
                                   const std::string& source);

/// Gives the structure atoms the source left without a charge (atom_matched false) their formal charge
/// (ions, and residues a force field lacks), updating points, net charge and warnings.
void fill_unmatched_with_formal(ChargeAssignment& charges, const std::vector<Atom>& atoms);

/// Reads a PQR file, hydrogens, waters and HETATM groups included, and matches it (match_pqr_charges).
/// Throws InputError as read_structure does for an unreadable or malformed file, and when no atom of the
/// PQR matches an atom of the structure (a PQR of another structure, or other chain names).
ChargeAssignment read_pqr_charges(const std::vector<Atom>& atoms, const std::filesystem::path& pqr);

}  // namespace spheremap
