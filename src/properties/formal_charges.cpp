// The built-in table of formal charges: what the electrostatics uses when neither a PQR nor pdb2pqr gives
// partial charges. Ionizable groups carry the charge they have at pH 7, spread over the atoms that share it
// by resonance (carboxylates, guanidinium); histidine is neutral (its pKa, about 6, is below 7).
#include <algorithm>
#include <cctype>
#include <map>
#include <set>

#include <fmt/format.h>

#include "spheremap/properties/charges.hpp"

namespace spheremap {
namespace {

std::string upper(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::toupper(c); });
  return text;
}

// Standard amino acids, their protonation variants (AMBER, CHARMM names) and common modified residues
// that keep a backbone: they can be chain termini.
const std::set<std::string>& amino_acids() {
  static const std::set<std::string> names = {"ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU", "GLY", "HIS", "ILE",
                                              "LEU", "LYS", "MET", "PHE", "PRO", "SER", "THR", "TRP", "TYR", "VAL",
                                              "HID", "HIE", "HIP", "HSD", "HSE", "HSP", "ASH", "GLH", "LYN", "CYX",
                                              "CYM", "ARN", "TYM", "MSE", "SEC", "PYL", "UNK"};
  return names;
}

// Groups that end a chain without a charged terminus.
const std::set<std::string>& caps() {
  static const std::set<std::string> names = {"ACE", "FOR", "NME", "NH2", "NHE"};
  return names;
}

const std::set<std::string>& nucleotides() {
  static const std::set<std::string> names = {"DA", "DC", "DG", "DT", "DU", "DI", "A",  "C", "G",
                                              "U",  "T",  "I",  "RA", "RC", "RG", "RU", "N", "DN"};
  return names;
}

const std::set<std::string>& waters() {
  static const std::set<std::string> names = {"HOH", "WAT", "H2O", "DOD", "D2O", "SOL", "TIP", "TIP3", "SPC"};
  return names;
}

// Monatomic ions by residue name (PDB chemical component codes).
const std::map<std::string, double>& ions() {
  static const std::map<std::string, double> charges = {
      {"LI", 1}, {"NA", 1}, {"K", 1},  {"RB", 1}, {"CS", 1},  {"AG", 1}, {"CU1", 1}, {"TL", 1},  {"MG", 2},
      {"CA", 2}, {"SR", 2}, {"BA", 2}, {"MN", 2}, {"FE2", 2}, {"CO", 2}, {"NI", 2},  {"CU", 2},  {"ZN", 2},
      {"CD", 2}, {"HG", 2}, {"PB", 2}, {"FE", 3}, {"AL", 3},  {"F", -1}, {"CL", -1}, {"BR", -1}, {"IOD", -1}};
  return charges;
}

// Side-chain charges: residue -> atom -> charge.
const std::map<std::string, std::map<std::string, double>>& side_chains() {
  static const std::map<std::string, std::map<std::string, double>> charges = {{"ASP", {{"OD1", -0.5}, {"OD2", -0.5}}},
                                                                               {"GLU", {{"OE1", -0.5}, {"OE2", -0.5}}},
                                                                               {"LYS", {{"NZ", 1.0}}},
                                                                               {"ARG", {{"NH1", 0.5}, {"NH2", 0.5}}},
                                                                               {"HIP", {{"ND1", 0.5}, {"NE2", 0.5}}},
                                                                               {"HSP", {{"ND1", 0.5}, {"NE2", 0.5}}},
                                                                               {"CYM", {{"SG", -1.0}}},
                                                                               {"TYM", {{"OH", -1.0}}}};
  return charges;
}

bool is_phosphate_oxygen(const std::string& atom) {
  return atom == "OP1" || atom == "OP2" || atom == "O1P" || atom == "O2P";
}

}  // namespace

bool formal_table_knows(const std::string& residue_name) {
  const std::string residue = upper(residue_name);
  return amino_acids().count(residue) || caps().count(residue) || nucleotides().count(residue) ||
         waters().count(residue) || ions().count(residue);
}

double formal_charge(const std::string& residue_name, const std::string& atom_name, const TerminusFlags& where) {
  const std::string residue = upper(residue_name), atom = upper(atom_name);
  if (const auto ion = ions().find(residue); ion != ions().end()) return ion->second;
  if (nucleotides().count(residue)) return is_phosphate_oxygen(atom) ? -0.5 : 0.0;
  if (!amino_acids().count(residue)) return 0;
  double charge = 0;
  if (const auto side = side_chains().find(residue); side != side_chains().end())
    if (const auto a = side->second.find(atom); a != side->second.end()) charge += a->second;
  if (where.n_terminus && atom == "N") charge += 1;
  if (where.c_terminus && atom == "OXT") charge -= 0.5;
  if (where.c_terminus && atom == "O") charge -= where.has_oxt ? 0.5 : 1.0;
  return charge;
}

ChargeAssignment formal_charges(const std::vector<Atom>& atoms) {
  // Residues as runs of atoms; per chain, the first and last residue that is an amino acid or a cap.
  struct Residue {
    std::size_t first = 0, last = 0;  // atoms [first, last)
    bool has_oxt = false;
  };
  std::vector<Residue> residues;
  for (std::size_t i = 0; i < atoms.size(); ++i) {
    if (residues.empty() || !same_residue(atoms[residues.back().first], atoms[i])) residues.push_back({i, i, false});
    residues.back().last = i + 1;
    if (upper(atoms[i].name) == "OXT") residues.back().has_oxt = true;
  }
  std::map<std::string, std::pair<std::size_t, std::size_t>> chain_ends;  // chain -> first, last residue
  for (std::size_t r = 0; r < residues.size(); ++r) {
    const std::string name = upper(atoms[residues[r].first].residue_name);
    if (!amino_acids().count(name) && !caps().count(name)) continue;
    const std::string& chain = atoms[residues[r].first].chain;
    const auto found = chain_ends.find(chain);
    if (found == chain_ends.end())
      chain_ends[chain] = {r, r};
    else
      found->second.second = r;
  }
  ChargeAssignment result;
  result.source = "formal";
  result.atom_charges.assign(atoms.size(), 0.0);
  result.atom_matched.assign(atoms.size(), false);
  std::map<std::string, std::int64_t> unknown;  // residue name -> atoms
  for (std::size_t r = 0; r < residues.size(); ++r) {
    const Atom& head = atoms[residues[r].first];
    const auto ends = chain_ends.find(head.chain);
    const bool in_chain = ends != chain_ends.end() && amino_acids().count(upper(head.residue_name));
    const TerminusFlags where{in_chain && ends->second.first == r, in_chain && ends->second.second == r,
                              residues[r].has_oxt};
    const bool known = formal_table_knows(head.residue_name);
    for (std::size_t i = residues[r].first; i < residues[r].last; ++i) {
      result.atom_charges[i] = formal_charge(atoms[i].residue_name, atoms[i].name, where);
      result.atom_matched[i] = known;
      if (known)
        ++result.atoms_charged;
      else
        ++result.atoms_unmatched, ++unknown[head.residue_name];
    }
  }
  for (std::size_t i = 0; i < atoms.size(); ++i) {
    result.points.positions.push_back(atoms[i].position);
    result.points.charges.push_back(result.atom_charges[i]);
    result.net_charge += result.atom_charges[i];
  }
  if (!unknown.empty()) {
    std::vector<std::string> names;
    for (const auto& [name, count] : unknown) names.push_back(fmt::format("{} ({} atoms)", name, count));
    result.warnings.push_back(
        fmt::format("no formal charge for the residues {}: their atoms count as neutral", fmt::join(names, ", ")));
  }
  return result;
}

}  // namespace spheremap
