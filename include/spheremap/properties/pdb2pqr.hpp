// Debian's pdb2pqr (package `pdb2pqr`, program `pdb2pqr30`), run for the user: hydrogens and partial charges.
#pragma once

#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <string>
#include <vector>

#include "spheremap/molecule/structure.hpp"
#include "spheremap/properties/charges.hpp"

namespace spheremap {

/// Lines telling the user what an external program is doing ("apbs: running for 10 s"); may be null.
using ProgressCallback = std::function<void(const std::string& line)>;

/// AMBER (the default: pdb2pqr 3.5's PARSE has no DNA parameters and drops DNA residues) or PARSE.
enum class ForceField { kAmber, kParse };
std::string to_string(ForceField force_field);  // "AMBER", "PARSE"

inline constexpr const char* kPdb2pqrProgram = "pdb2pqr30";

/// True when pdb2pqr30 is on PATH.
bool pdb2pqr_available();

/// The structure as pdb2pqr is given it: one-character chain names (the PDB column holds one; the original
/// names are kept for the way back), DNA residues with the names pdb2pqr reads (A/C/G/T/U/I without an O2'
/// atom become DA/DC/DG/DT/DU/DI; pdb2pqr reads the old one-letter names as RNA and drops T).
struct Pdb2pqrInput {
  std::vector<Atom> atoms;
  std::map<std::string, std::string> original_chain;  // one-character name -> the structure's name
  std::int64_t dna_residues_renamed = 0;
};

/// Throws InputError (naming `name`, the problem and --charges formal / a PQR as the way out) when the
/// structure cannot be written as PDB: more than 62 chains, residue numbers outside [-999, 9999].
Pdb2pqrInput pdb2pqr_input(const std::vector<Atom>& atoms, const std::string& name);

/// Runs `pdb2pqr30 --ff=FF --keep-chain --whitespace X.pdb X.pqr` in `folder` on `input` (with
/// --apbs-input never: Debian's inputgen breaks under Python 3.11) and reads the PQR back, chain names
/// restored. `name` is the structure's name in messages.
/// Throws InputError naming the Debian package `pdb2pqr` when pdb2pqr30 is not installed, and with
/// pdb2pqr's last lines of output when it fails or writes nothing.
std::vector<Atom> run_pdb2pqr(const Pdb2pqrInput& input, ForceField force_field, const std::filesystem::path& folder,
                              const std::string& name, const ProgressCallback& progress = nullptr);

/// pdb2pqr's charges for the structure's atoms (hydrogens it adds are charges without surface; see
/// match_pqr_charges), run in a temporary folder removed afterwards. Throws as pdb2pqr_input and run_pdb2pqr.
ChargeAssignment pdb2pqr_charges(const std::vector<Atom>& atoms, ForceField force_field, const std::string& name,
                                 const ProgressCallback& progress = nullptr);

}  // namespace spheremap
