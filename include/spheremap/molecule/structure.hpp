// From a structure file to atoms with radii (stage: molecule).
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/molecule/radii.hpp"

namespace spheremap {

struct Atom {
  Vec3 position{};
  double radius = 0;  // Å
  /// Partial charge (e), from the charge column of PQR files; absent for PDB and mmCIF files.
  std::optional<double> charge;
  /// Isotropic B-factor (Å²), from PDB and mmCIF files (the column tools also use to carry any per-atom
  /// value: conservation, hydrophobicity, ...); absent for PQR files, which have no such column. The
  /// decimal the file wrote (gemmi keeps it as a float; its shortest decimal is taken back).
  std::optional<double> b_factor;
  std::int32_t serial = 0;
  std::string name;          // atom name, e.g. "CA"
  std::string element;       // upper case, e.g. "C", "FE"
  std::string residue_name;  // e.g. "LYS", "HOH"
  std::int32_t residue_number = 0;
  char insertion_code = ' ';
  std::string chain;
  std::int32_t model = 1;  // model number as written in the file
  bool hetero = false;     // HETATM record
};

/// Whether two atoms belong to one residue: same chain, residue number, insertion code and name. Never throws.
inline bool same_residue(const Atom& a, const Atom& b) {
  return a.chain == b.chain && a.residue_number == b.residue_number && a.insertion_code == b.insertion_code &&
         a.residue_name == b.residue_name;
}

struct StructureOptions {
  /// Which model to read: 1 = the first in the file (the default), N = the N-th.
  int model = 1;
  /// Chains to keep (by name); empty = all.
  std::vector<std::string> chains;
  /// Hydrogens: unset, PDB and mmCIF files lose them and PQR files keep them (a PQR's hydrogens carry
  /// charge; those of radius 0 make no surface); true or false applies to every format.
  std::optional<bool> keep_hydrogens;
  bool keep_waters = false;
  bool keep_hetero = true;  // ligands, ions and other HETATM groups that are not water
  /// Element -> radius (Å) replacing the Bondi table, e.g. from load_radius_table. Ignored for PQR files,
  /// whose radius column is used.
  std::optional<std::map<std::string, double>> radii;
  /// Every warning about the file (StructureReport::warnings: a truncated last line, unknown elements,
  /// ignored columns, ...) is an error instead.
  bool strict = false;
};

struct StructureReport {
  std::int64_t models_in_file = 0;
  std::int64_t atoms_in_model = 0;
  std::int64_t hydrogens_removed = 0;
  std::int64_t waters_removed = 0;
  std::int64_t hetero_removed = 0;
  std::int64_t other_chains_removed = 0;
  std::int64_t alternate_locations_removed = 0;  // atoms of the less occupied alternate conformations
  /// About the file (valid UTF-8): signs of truncation (a last line without its line break, a last atom
  /// record shorter than the others), unknown elements and the radius used, ignored columns.
  std::vector<std::string> warnings;
};

struct Molecule {
  std::vector<Atom> atoms;
  StructureReport report;
};

/// Reads PDB, mmCIF (both optionally .gz) through gemmi (B-factors too), or PQR (radius and charge columns), chosen by
/// extension (.pdb .ent .cif .mmcif .pqr, with an optional .gz). Keeps, by default, the first model,
/// the most occupied alternate location of each residue (ties: the first letter), no hydrogens (but a
/// PQR's, whose atoms of radius 0 count for charge and make no surface), no waters, all other HETATM groups and all
/// chains; radii from Bondi (1964) per element unless options.radii or the PQR file say otherwise; unknown elements get
/// kUnknownElementRadius and a warning naming them. A .gz file is inflated whole and must be complete (CRC and length
/// checked). Signs of a truncated file (a last line without its line break, a last atom record shorter than the others)
/// are warnings in the report; options.strict makes every warning an error. Text read from the file (names, chains,
/// elements) is made valid UTF-8 (valid_utf8).
/// Throws InputError naming the file, the problem and the fix when the file is missing, a folder,
/// unreadable, empty, not a structure, a truncated or corrupt .gz, a .gz that inflates past 1 GiB or past
/// 100 times its size beyond 64 MiB (a gzip bomb; stopped as it inflates), has a non-finite or absurd coordinate
/// (beyond ±1e5 Å) or a non-finite PQR charge, has fewer than two atoms after filtering, or the model /
/// chains asked for do not exist; with options.strict, when there is a warning.
Molecule read_structure(const std::filesystem::path& path, const StructureOptions& options = {});

}  // namespace spheremap
