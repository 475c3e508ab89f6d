// A structure's residues and chains, from its atoms (stage: properties): what per-residue properties,
// the sequence position and residues.csv are computed over.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "spheremap/molecule/structure.hpp"

namespace spheremap {

/// One residue: a run of consecutive atoms with the same chain, number, insertion code and name.
struct Residue {
  std::string chain, name;
  std::int32_t number = 0;
  char insertion_code = ' ';
  std::int32_t chain_index = 0;  // index into ResidueIndex::chains
  /// Part of its chain's polymer: an ATOM record, or a HETATM residue (MSE, SEP, ...) that has ATOM
  /// residues of its chain both before and after it. Ligands, ions and waters are not.
  bool polymer = false;
};

struct ResidueIndex {
  std::vector<Residue> residues;              // in file order
  std::vector<std::int32_t> residue_of_atom;  // per atom
  std::vector<std::string> chains;            // chain names in order of first appearance
};

/// Groups the atoms into residues and chains. Never throws (but std::bad_alloc).
ResidueIndex index_residues(const std::vector<Atom>& atoms);

/// Position along the chain of every residue: the k-th of the n polymer residues of its chain (in file order)
/// gets k / (n - 1), from 0 at the N-terminus (5' end) to 1 at the C-terminus (3' end), 0 when n is 1; NaN for
/// a residue outside the polymer. Never throws (but std::bad_alloc).
std::vector<double> sequence_positions(const ResidueIndex& index);

/// "A:LYS45" or "A:LYS45B" (with an insertion code). Never throws (but std::bad_alloc).
std::string residue_label(const Residue& residue);

}  // namespace spheremap
