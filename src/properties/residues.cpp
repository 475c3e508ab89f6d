#include "spheremap/properties/residues.hpp"

#include <limits>

#include <fmt/format.h>

namespace spheremap {
namespace {

// Marks every ATOM residue as polymer, and the HETATM residues of a chain that lie between two of them.
void mark_polymer(ResidueIndex& index, const std::vector<bool>& hetero) {
  std::vector<std::int32_t> last_atom_record(index.chains.size(), -1);
  for (std::size_t r = 0; r < index.residues.size(); ++r)
    if (!hetero[r])
      last_atom_record[static_cast<std::size_t>(index.residues[r].chain_index)] = static_cast<std::int32_t>(r);
  std::vector<bool> seen_atom_record(index.chains.size(), false);
  for (std::size_t r = 0; r < index.residues.size(); ++r) {
    Residue& residue = index.residues[r];
    const auto c = static_cast<std::size_t>(residue.chain_index);
    if (!hetero[r]) {
      residue.polymer = true;
      seen_atom_record[c] = true;
    } else {
      residue.polymer = seen_atom_record[c] && static_cast<std::int32_t>(r) < last_atom_record[c];
    }
  }
}

}  // namespace

ResidueIndex index_residues(const std::vector<Atom>& atoms) {
  ResidueIndex index;
  index.residue_of_atom.reserve(atoms.size());
  std::vector<bool> hetero;  // per residue: every atom a HETATM record
  for (std::size_t a = 0; a < atoms.size(); ++a) {
    const Atom& atom = atoms[a];
    if (a == 0 || !same_residue(atom, atoms[a - 1])) {
      Residue residue;
      residue.chain = atom.chain;
      residue.name = atom.residue_name;
      residue.number = atom.residue_number;
      residue.insertion_code = atom.insertion_code;
      std::size_t c = 0;
      while (c < index.chains.size() && index.chains[c] != atom.chain) ++c;
      if (c == index.chains.size()) index.chains.push_back(atom.chain);
      residue.chain_index = static_cast<std::int32_t>(c);
      index.residues.push_back(std::move(residue));
      hetero.push_back(true);
    }
    if (!atom.hetero) hetero.back() = false;
    index.residue_of_atom.push_back(static_cast<std::int32_t>(index.residues.size() - 1));
  }
  mark_polymer(index, hetero);
  return index;
}

std::vector<double> sequence_positions(const ResidueIndex& index) {
  std::vector<std::int64_t> count(index.chains.size(), 0), seen(index.chains.size(), 0);
  for (const Residue& r : index.residues)
    if (r.polymer) ++count[static_cast<std::size_t>(r.chain_index)];
  std::vector<double> positions(index.residues.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t r = 0; r < index.residues.size(); ++r) {
    const Residue& residue = index.residues[r];
    if (!residue.polymer) continue;
    const auto c = static_cast<std::size_t>(residue.chain_index);
    const std::int64_t k = seen[c]++;
    positions[r] = count[c] > 1 ? static_cast<double>(k) / static_cast<double>(count[c] - 1) : 0.0;
  }
  return positions;
}

std::string residue_label(const Residue& residue) {
  std::string label = fmt::format("{}:{}{}", residue.chain, residue.name, residue.number);
  if (residue.insertion_code != ' ') label += residue.insertion_code;
  return label;
}

}  // namespace spheremap
