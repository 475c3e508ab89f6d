// Atoms back to a PDB file, for the external programs that read only PDB (pdb2pqr).
#pragma once

#include <filesystem>
#include <vector>

#include "spheremap/molecule/structure.hpp"

namespace spheremap {

/// Writes `atoms` as ATOM/HETATM records of one model (through gemmi), residues grouped as consecutive
/// atoms of the same chain, number, insertion code and name, a TER record after each chain.
/// Preconditions: chain names of at most 2 characters (PDB keeps 1 in column 22, gemmi uses 21-22 for 2),
/// residue numbers in [-999, 9999], names of at most 4 (atoms) and 3 (residues) characters; longer ones are
/// cut by the format. Throws InputError naming the file when it cannot be written.
void write_pdb(const std::vector<Atom>& atoms, const std::filesystem::path& path);

}  // namespace spheremap
