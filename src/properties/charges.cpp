// Charges from a PQR file, matched to the structure's atoms.
#include <algorithm>
#include <cctype>
#include <map>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/properties/charges.hpp"

namespace spheremap {
namespace {

// Atom names as pdb2pqr and old PDB files (format 2) write them differently: O5* / O5', O1P / OP1, and
// thymine's methyl C5M / C7.
std::string canonical_atom_name(const std::string& name) {
  std::string n;
  for (const char c : name)
    n.push_back(c == '*' ? '\'' : static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  if (n == "O1P") return "OP1";
  if (n == "O2P") return "OP2";
  if (n == "O3P") return "OP3";
  if (n == "C5M") return "C7";
  return n;
}

std::string residue_key(const Atom& a, bool with_chain) {
  return fmt::format("{}|{}|{}", with_chain ? a.chain : "", a.residue_number, a.insertion_code);
}

bool is_hydrogen(const Atom& a) { return a.element == "H" || a.element == "D"; }

}  // namespace

ChargeAssignment match_pqr_charges(const std::vector<Atom>& atoms, const std::vector<Atom>& pqr_atoms,
                                   const std::string& source) {
  for (const Atom& a : pqr_atoms)
    if (!a.charge) throw std::invalid_argument("match_pqr_charges: a PQR atom has no charge");
  // A PQR without chain identifiers (pdb2pqr without --keep-chain) still matches a one-chain structure.
  std::set<std::string> chains;
  for (const Atom& a : atoms) chains.insert(a.chain);
  const bool pqr_has_chains =
      std::any_of(pqr_atoms.begin(), pqr_atoms.end(), [](const Atom& a) { return !a.chain.empty(); });
  const bool with_chain = pqr_has_chains || chains.size() > 1;

  std::map<std::string, std::size_t> by_key;  // residue key + atom name -> PQR atom (the first of duplicates)
  for (std::size_t i = 0; i < pqr_atoms.size(); ++i)
    by_key.emplace(residue_key(pqr_atoms[i], with_chain) + "|" + canonical_atom_name(pqr_atoms[i].name), i);
  std::set<std::string> residues;
  for (const Atom& a : atoms) residues.insert(residue_key(a, with_chain));

  ChargeAssignment result;
  result.source = source;
  result.atom_charges.assign(atoms.size(), 0.0);
  result.atom_matched.assign(atoms.size(), false);
  std::vector<bool> used(pqr_atoms.size(), false);
  for (std::size_t i = 0; i < atoms.size(); ++i) {
    const auto found = by_key.find(residue_key(atoms[i], with_chain) + "|" + canonical_atom_name(atoms[i].name));
    if (found == by_key.end() || used[found->second]) {
      ++result.atoms_unmatched;
    } else {
      used[found->second] = true;
      result.atom_matched[i] = true;
      result.atom_charges[i] = *pqr_atoms[found->second].charge;
      ++result.atoms_charged;
    }
    result.points.positions.push_back(atoms[i].position);
    result.points.charges.push_back(result.atom_charges[i]);
  }
  for (std::size_t i = 0; i < pqr_atoms.size(); ++i) {
    if (used[i]) continue;
    if (!residues.count(residue_key(pqr_atoms[i], with_chain))) {
      ++result.pqr_atoms_unused;
      continue;
    }
    ++result.added_atoms;
    if (is_hydrogen(pqr_atoms[i])) ++result.added_hydrogens;
    result.points.positions.push_back(pqr_atoms[i].position);
    result.points.charges.push_back(*pqr_atoms[i].charge);
  }
  for (const double q : result.points.charges) result.net_charge += q;
  if (result.atoms_unmatched > 0) {
    std::set<std::string> names;
    for (std::size_t i = 0; i < atoms.size(); ++i)
      if (!result.atom_matched[i]) names.insert(atoms[i].residue_name);
    result.warnings.push_back(
        fmt::format("{} of {} atoms (of the residues {}) have no charge in {} and count as neutral",
                    result.atoms_unmatched, atoms.size(), fmt::join(names, ", "), source));
  }
  if (result.pqr_atoms_unused > 0)
    result.warnings.push_back(
        fmt::format("{} atoms of {} belong to residues the structure does not have and were "
                    "ignored",
                    result.pqr_atoms_unused, source));
  return result;
}

void fill_unmatched_with_formal(ChargeAssignment& charges, const std::vector<Atom>& atoms) {
  if (charges.atoms_unmatched == 0) return;
  const ChargeAssignment formal = formal_charges(atoms);
  double added = 0;
  std::set<std::string> residues;
  for (std::size_t i = 0; i < atoms.size(); ++i) {
    if (charges.atom_matched[i] || formal.atom_charges[i] == 0) continue;
    charges.atom_charges[i] = charges.points.charges[i] = formal.atom_charges[i];
    added += formal.atom_charges[i];
    residues.insert(atoms[i].residue_name);
  }
  charges.net_charge = 0;
  for (const double q : charges.points.charges) charges.net_charge += q;
  if (!residues.empty())
    charges.warnings.push_back(
        fmt::format("of the atoms without a charge in {}, those of {} took their formal charge "
                    "instead ({:+g} e in all)",
                    charges.source, fmt::join(residues, ", "), added));
}

ChargeAssignment read_pqr_charges(const std::vector<Atom>& atoms, const std::filesystem::path& pqr) {
  StructureOptions everything;
  everything.keep_hydrogens = true;
  everything.keep_waters = true;
  everything.keep_hetero = true;
  const Molecule charged = read_structure(pqr, everything);
  ChargeAssignment result = match_pqr_charges(atoms, charged.atoms, fmt::format("PQR {}", pqr.filename().string()));
  if (result.atoms_charged == 0)
    throw InputError(
        fmt::format("{}: no atom of the PQR file matches an atom of the structure by chain, residue "
                    "number, insertion code and atom name; give the PQR of this structure, written with "
                    "its chain identifiers (pdb2pqr30 --keep-chain)",
                    pqr.string()));
  return result;
}

}  // namespace spheremap
