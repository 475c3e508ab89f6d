#include "spheremap/properties/pdb2pqr.hpp"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "../util/subprocess.hpp"
#include "spheremap/error.hpp"
#include "spheremap/molecule/pdb_writer.hpp"

namespace spheremap {
namespace {

std::string trimmed_upper(const std::string& text) {
  std::string out;
  for (const char c : text)
    if (c != ' ') out.push_back(static_cast<char>(std::toupper(static_cast<unsigned char>(c))));
  return out;
}

// One-character chain names: the structure's own when they all are, else A-Z, a-z, 0-9 in order of appearance.
std::map<std::string, std::string> chain_letters(const std::vector<Atom>& atoms, const std::string& name) {
  std::vector<std::string> chains;
  for (const Atom& a : atoms)
    if (std::find(chains.begin(), chains.end(), a.chain) == chains.end()) chains.push_back(a.chain);
  std::map<std::string, std::string> letters;  // structure's name -> letter
  if (std::all_of(chains.begin(), chains.end(), [](const std::string& c) { return c.size() == 1 && c != " "; })) {
    for (const auto& c : chains) letters[c] = c;
    return letters;
  }
  static const std::string kLetters = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789";
  if (chains.size() > kLetters.size())
    throw InputError(
        fmt::format("{}: {} chains, but pdb2pqr reads PDB files, whose chain column holds one character "
                    "(at most {} chains); use --charges formal, or give a PQR with --charges FILE",
                    name, chains.size(), kLetters.size()));
  for (std::size_t i = 0; i < chains.size(); ++i) letters[chains[i]] = kLetters.substr(i, 1);
  return letters;
}

}  // namespace

std::string to_string(ForceField force_field) { return force_field == ForceField::kParse ? "PARSE" : "AMBER"; }

bool pdb2pqr_available() { return detail::find_executable(kPdb2pqrProgram).has_value(); }

Pdb2pqrInput pdb2pqr_input(const std::vector<Atom>& atoms, const std::string& name) {
  Pdb2pqrInput input;
  input.atoms = atoms;
  const auto letters = chain_letters(atoms, name);
  for (const auto& [chain, letter] : letters) input.original_chain[letter] = chain;
  static const std::set<std::string> kOneLetterBases = {"A", "C", "G", "T", "U", "I"};
  for (std::size_t first = 0; first < input.atoms.size();) {
    std::size_t last = first;
    bool has_o2 = false;
    while (last < input.atoms.size() && same_residue(input.atoms[first], input.atoms[last])) {
      const std::string atom = trimmed_upper(input.atoms[last].name);
      has_o2 = has_o2 || atom == "O2'" || atom == "O2*";
      ++last;
    }
    const Atom& head = input.atoms[first];
    if (head.residue_number < -999 || head.residue_number > 9999)
      throw InputError(
          fmt::format("{}: residue {} {}{} has a number PDB files cannot hold (-999 to 9999), and pdb2pqr "
                      "reads PDB files; use --charges formal, or give a PQR with --charges FILE",
                      name, head.residue_name, head.chain, head.residue_number));
    const std::string residue = trimmed_upper(head.residue_name);
    const bool dna = kOneLetterBases.count(residue) && !has_o2;
    if (dna) ++input.dna_residues_renamed;
    for (std::size_t i = first; i < last; ++i) {
      if (dna) input.atoms[i].residue_name = "D" + residue;
      input.atoms[i].chain = letters.at(input.atoms[i].chain);
    }
    first = last;
  }
  return input;
}

std::vector<Atom> run_pdb2pqr(const Pdb2pqrInput& input, ForceField force_field, const std::filesystem::path& folder,
                              const std::string& name, const ProgressCallback& progress) {
  const auto program = detail::find_executable(kPdb2pqrProgram);
  if (!program)
    throw InputError(
        fmt::format("{}: pdb2pqr30 is not installed (it is on no folder of PATH); install Debian's package "
                    "pdb2pqr (apt-get install pdb2pqr), or use --charges formal",
                    name));
  write_pdb(input.atoms, folder / "structure.pdb");
  if (progress)
    progress(fmt::format("pdb2pqr30: adding hydrogens and {} charges to {} atoms", to_string(force_field),
                         input.atoms.size()));
  const auto run = detail::run_program({program->string(), "--ff=" + to_string(force_field), "--keep-chain",
                                        "--whitespace", "structure.pdb", "structure.pqr"},
                                       folder, folder / "pdb2pqr.log", [&](double seconds) {
                                         if (progress)
                                           progress(fmt::format("pdb2pqr30: running for {:.0f} s", seconds));
                                       });
  const auto pqr = folder / "structure.pqr";
  if (run.exit_code != 0 || !std::filesystem::exists(pqr) || std::filesystem::is_empty(pqr))
    throw InputError(
        fmt::format("{}: pdb2pqr30 --ff={} failed on this structure (exit status {}); its last lines:\n{}"
                    "Use --charges formal, or prepare a PQR yourself and give it with --charges FILE",
                    name, to_string(force_field), run.exit_code, run.log_tail));
  if (progress) progress(fmt::format("pdb2pqr30: done in {:.1f} s", run.seconds));
  StructureOptions everything;
  everything.keep_hydrogens = true;
  everything.keep_waters = true;
  everything.keep_hetero = true;
  std::vector<Atom> atoms = read_structure(pqr, everything).atoms;
  for (Atom& a : atoms) {
    const auto original = input.original_chain.find(a.chain);
    if (original != input.original_chain.end()) a.chain = original->second;
  }
  return atoms;
}

ChargeAssignment pdb2pqr_charges(const std::vector<Atom>& atoms, ForceField force_field, const std::string& name,
                                 const ProgressCallback& progress) {
  const Pdb2pqrInput input = pdb2pqr_input(atoms, name);
  const detail::TemporaryFolder folder("spheremap-pdb2pqr");
  const std::vector<Atom> charged = run_pdb2pqr(input, force_field, folder.path(), name, progress);
  ChargeAssignment result = match_pqr_charges(atoms, charged, fmt::format("pdb2pqr ({})", to_string(force_field)));
  fill_unmatched_with_formal(result, atoms);  // ions, and what the force field lacks
  if (input.dna_residues_renamed > 0)
    result.warnings.push_back(fmt::format("{} DNA residues named A/C/G/T/U/I given to pdb2pqr as DA/DC/DG/DT/DU/DI",
                                          input.dna_residues_renamed));
  return result;
}

}  // namespace spheremap
