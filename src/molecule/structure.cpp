// The translation unit that reads with gemmi (header-only and slow to compile); pdb_writer.cpp writes with it.
#include <gemmi/mmread.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <set>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/text.hpp"
#include "structure_text.hpp"

namespace spheremap {
namespace {

constexpr double kAbsurdCoordinate = 1e5;  // Å; no deposited structure comes close

// The shortest decimal that reads back as `value`: what the file wrote, as a double (gemmi keeps
// B-factors as floats, and 15.23f widened to double is 15.229999542236328).
double decimal_of(float value) {
  std::array<char, 32> text{};
  const auto written = std::to_chars(text.data(), text.data() + text.size(), value);
  double result = value;
  if (written.ec == std::errc{}) std::from_chars(text.data(), written.ptr, result);
  return result;
}

std::string upper(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::toupper(c); });
  return text;
}

std::string lower_extension(const std::filesystem::path& path) {
  std::filesystem::path p = path;
  if (upper(p.extension().string()) == ".GZ") p = p.stem();
  std::string ext = p.extension().string();
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

bool is_water_name(const std::string& residue) {
  static const std::set<std::string> kWater = {"HOH", "WAT", "H2O", "DOD", "D2O", "TIP", "TIP3", "SOL", "SPC"};
  return kWater.count(upper(residue)) > 0;
}

// An atom as read, before filtering.
struct RawAtom {
  Atom atom;
  char altloc = 0;
  double occupancy = 1;
  bool water = false;
  bool hydrogen = false;
  std::string residue_key;  // chain + number + insertion code + name: one residue
};

// Fills what the filters need from the element and residue: for readers without gemmi's residue model.
void classify(RawAtom& raw) {
  raw.hydrogen = raw.atom.element == "H" || raw.atom.element == "D";
  raw.water = is_water_name(raw.atom.residue_name);
  raw.residue_key = fmt::format("{}|{}|{}|{}", raw.atom.chain, raw.atom.residue_number, raw.atom.insertion_code,
                                raw.atom.residue_name);
}

// Names from the file go into JSON, CSV and HTML outputs: valid UTF-8 only (a stray byte becomes U+FFFD;
// an insertion code, one byte, becomes '?').
void make_text_valid(Atom& atom) {
  for (std::string* text : {&atom.name, &atom.element, &atom.residue_name, &atom.chain})
    if (!is_valid_utf8(*text)) *text = valid_utf8(*text);
  const auto code = static_cast<unsigned char>(atom.insertion_code);
  if (code >= 0x7F || (code < 0x20 && code != 0)) atom.insertion_code = '?';
}

// mmCIF files written by other programs (PyMOL's 1bna.cif) may lack the columns gemmi's structure
// reader needs (auth_seq_id); read the _atom_site table directly with gemmi's CIF parser.
std::vector<RawAtom> read_atom_site_table(const std::filesystem::path& path, gemmi::cif::Document& document, int model,
                                          std::int64_t& models_in_file) {
  if (document.blocks.empty()) throw InputError(fmt::format("{}: the mmCIF file has no data block", path.string()));
  auto table = document.blocks.front().find(
      "_atom_site.", {"Cartn_x", "Cartn_y", "Cartn_z", "?group_PDB", "?id", "?type_symbol", "?label_atom_id",
                      "?label_alt_id", "?label_comp_id", "?auth_asym_id", "?label_asym_id", "?auth_seq_id",
                      "?label_seq_id", "?pdbx_PDB_ins_code", "?occupancy", "?pdbx_PDB_model_num", "?B_iso_or_equiv"});
  if (table.length() == 0)
    throw InputError(fmt::format("{}: the file contains no atoms (no _atom_site table)", path.string()));
  std::vector<std::string> model_numbers;
  for (auto row : table) {
    const std::string number = row.has2(15) ? row.str(15) : "1";
    if (std::find(model_numbers.begin(), model_numbers.end(), number) == model_numbers.end())
      model_numbers.push_back(number);
  }
  models_in_file = static_cast<std::int64_t>(model_numbers.size());
  if (model < 1 || model > static_cast<int>(model_numbers.size()))
    throw InputError(fmt::format("{}: --model {} does not exist: the file has {} model(s)", path.string(), model,
                                 model_numbers.size()));
  const std::string& wanted = model_numbers[static_cast<std::size_t>(model - 1)];
  auto text = [&](gemmi::cif::Table::Row& row, int column, const char* fallback) {
    return row.has2(static_cast<std::size_t>(column)) ? row.str(column) : std::string(fallback);
  };
  std::vector<RawAtom> atoms;
  for (auto row : table) {
    if ((row.has2(15) ? row.str(15) : "1") != wanted) continue;
    RawAtom raw;
    raw.atom.position = {gemmi::cif::as_number(row[0]), gemmi::cif::as_number(row[1]), gemmi::cif::as_number(row[2])};
    raw.atom.hetero = text(row, 3, "ATOM") == "HETATM";
    raw.atom.serial = static_cast<std::int32_t>(gemmi::cif::as_number(text(row, 4, "0"), 0));
    raw.atom.element = upper(text(row, 5, "X"));
    raw.atom.name = text(row, 6, "X");
    const std::string altloc = text(row, 7, "");
    raw.altloc = altloc.empty() ? 0 : altloc[0];
    raw.atom.residue_name = text(row, 8, "UNK");
    raw.atom.chain = row.has2(9) ? row.str(9) : text(row, 10, "");
    raw.atom.residue_number =
        static_cast<std::int32_t>(gemmi::cif::as_number(row.has2(11) ? row.str(11) : text(row, 12, "0"), 0));
    const std::string icode = text(row, 13, "");
    raw.atom.insertion_code = icode.empty() ? ' ' : icode[0];
    raw.occupancy = gemmi::cif::as_number(text(row, 14, "1"), 1);
    if (row.has2(16)) raw.atom.b_factor = gemmi::cif::as_number(row.str(16));  // else none, not a zero
    int model_number = model;
    std::from_chars(wanted.data(), wanted.data() + wanted.size(), model_number);
    raw.atom.model = model_number;
    classify(raw);
    atoms.push_back(std::move(raw));
  }
  return atoms;
}

// Whether the line at `at` starts with `record`'s first four letters, in either case: how gemmi's PDB reader
// tells record types apart.
bool starts_record(const std::string& text, std::size_t at, std::string_view record) {
  if (text.size() - at < 4) return false;
  for (std::size_t i = 0; i < 4; ++i)
    if ((static_cast<unsigned char>(text[at + i]) & ~0x20u) != static_cast<unsigned char>(record[i])) return false;
  return true;
}

// `text` as gemmi's PDB reader may safely see it. gemmi 0.5 reads a short or mangled connection record
// (SSBOND, LINK, CISPEP) at fixed columns past its end (a heap over-read found by fuzzing: FUZZING.md,
// finding 4); spheremap uses none of them, so they are renamed to a record gemmi ignores. NUL bytes become
// spaces first: gemmi ends a line at one and starts the next after it, so a record could begin mid-line.
std::string gemmi_safe_pdb_text(const std::string& text) {
  std::string out = text;
  std::replace(out.begin(), out.end(), '\0', ' ');
  for (std::size_t at = 0; at < out.size();) {
    if (starts_record(out, at, "SSBO") || starts_record(out, at, "LINK") || starts_record(out, at, "CISP"))
      std::copy_n("SKIP", 4, out.begin() + static_cast<std::ptrdiff_t>(at));
    const std::size_t end = out.find('\n', at);
    at = end == std::string::npos ? out.size() : end + 1;
  }
  return out;
}

// The structure in `text` (the file's bytes, inflated), as PDB or mmCIF by the file's extension; the
// document too for mmCIF (read_atom_site_table reads it again when gemmi finds no model).
gemmi::Structure parse_with_gemmi(const std::filesystem::path& path, const std::string& text,
                                  std::optional<gemmi::cif::Document>& document) {
  const std::string extension = lower_extension(path);
  if (extension == ".pdb" || extension == ".ent")
    return gemmi::read_pdb_from_memory(text.data(), text.size(), path.string());
  document = gemmi::cif::read_memory(text.data(), text.size(), path.c_str());
  return gemmi::make_structure(*document);
}

std::vector<RawAtom> read_with_gemmi(const std::filesystem::path& path, const std::string& text, int model,
                                     std::int64_t& models_in_file, std::vector<std::string>& warnings) {
  gemmi::Structure structure;
  std::optional<gemmi::cif::Document> document;
  const bool pdb = lower_extension(path) == ".pdb" || lower_extension(path) == ".ent";
  const std::string pdb_text = pdb ? gemmi_safe_pdb_text(text) : std::string();
  const std::string& input = pdb ? pdb_text : text;
  try {
    structure = parse_with_gemmi(path, input, document);
  } catch (const std::exception& first_error) {
    // Old PDB files carry an ID and line numbers in columns 73-80, where the element and charge are now
    // (1hpv.pdb of pymol-data, for one): read them again up to column 72, elements then come from names.
    bool read = false;
    if (pdb) {
      try {
        gemmi::PdbReadOptions up_to_72;
        up_to_72.max_line_length = 72;
        structure = gemmi::read_pdb_from_memory(input.data(), input.size(), path.string(), up_to_72);
        warnings.push_back(fmt::format("columns 73-80 ignored (old-style PDB: {}); elements taken from atom names",
                                       first_error.what()));
        read = true;
      } catch (const std::exception&) {
      }
    }
    if (!read)
      throw InputError(
          fmt::format("{}: cannot read the structure: {}. Check that it is a PDB or mmCIF file and not "
                      "truncated",
                      path.string(), valid_utf8(first_error.what())));
  }
  models_in_file = static_cast<std::int64_t>(structure.models.size());
  if (structure.models.empty() && document) return read_atom_site_table(path, *document, model, models_in_file);
  if (structure.models.empty())
    throw InputError(fmt::format("{}: the file contains no atoms (no model); is it a structure file?", path.string()));
  if (model < 1 || model > static_cast<int>(structure.models.size()))
    throw InputError(fmt::format("{}: --model {} does not exist: the file has {} model(s), numbered 1 to {}",
                                 path.string(), model, structure.models.size(), structure.models.size()));
  const gemmi::Model& chosen = structure.models[static_cast<std::size_t>(model - 1)];
  int model_number = model;
  std::from_chars(chosen.name.data(), chosen.name.data() + chosen.name.size(), model_number);
  std::vector<RawAtom> atoms;
  for (const auto& chain : chosen.chains) {
    for (const auto& residue : chain.residues) {
      const bool water = residue.is_water() || is_water_name(residue.name);
      const std::string key =
          fmt::format("{}|{}|{}|{}", chain.name, residue.seqid.num.value, residue.seqid.icode, residue.name);
      for (const auto& a : residue.atoms) {
        RawAtom raw;
        raw.atom.position = {a.pos.x, a.pos.y, a.pos.z};
        raw.atom.serial = a.serial;
        raw.atom.name = a.name;
        raw.atom.element = upper(a.element.name());
        raw.atom.residue_name = residue.name;
        raw.atom.residue_number = residue.seqid.num.value;
        raw.atom.insertion_code = residue.seqid.icode == '\0' ? ' ' : residue.seqid.icode;
        raw.atom.chain = chain.name;
        raw.atom.model = model_number;
        raw.atom.hetero = residue.het_flag == 'H';
        raw.altloc = a.altloc;
        raw.occupancy = a.occ;
        raw.atom.b_factor = decimal_of(a.b_iso);
        raw.water = water;
        raw.hydrogen = a.is_hydrogen();
        raw.residue_key = key;
        atoms.push_back(std::move(raw));
      }
    }
  }
  return atoms;
}

// PQR (pdb2pqr, APBS): whitespace-separated ATOM/HETATM records whose last five fields are
// x y z charge radius; the chain column is optional.
std::vector<RawAtom> read_pqr(const std::filesystem::path& path, const std::string& text) {
  std::istringstream in(text);
  std::vector<RawAtom> atoms;
  std::string line;
  int line_number = 0;
  while (std::getline(in, line)) {
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    if (line.rfind("ATOM", 0) != 0 && line.rfind("HETATM", 0) != 0) continue;
    std::istringstream stream(line);
    std::vector<std::string> fields;
    for (std::string field; stream >> field;) fields.push_back(field);
    auto fail = [&] {
      return InputError(
          fmt::format("{}:{}: not a PQR atom record (expected 'ATOM serial name residue [chain] number x y "
                      "z charge radius'): {}",
                      path.string(), line_number, molecule_detail::quoted_line(line)));
    };
    if (fields.size() < 10 || fields.size() > 12) throw fail();
    auto number = [&](const std::string& text) {
      double value = 0;
      if (std::from_chars(text.data(), text.data() + text.size(), value).ec != std::errc{}) throw fail();
      return value;
    };
    // Serial and residue numbers: whole numbers of 32 bits (a cast of a larger double is undefined).
    auto whole_number = [&](const std::string& text) {
      const double value = number(text);
      if (!(value >= std::numeric_limits<std::int32_t>::min() && value <= std::numeric_limits<std::int32_t>::max()) ||
          value != std::trunc(value))
        throw fail();
      return static_cast<std::int32_t>(value);
    };
    const auto n = fields.size();
    RawAtom raw;
    raw.atom.position = {number(fields[n - 5]), number(fields[n - 4]), number(fields[n - 3])};
    raw.atom.charge = number(fields[n - 2]);
    raw.atom.radius = number(fields[n - 1]);
    if (!std::isfinite(*raw.atom.charge) || !(raw.atom.radius >= 0 && raw.atom.radius < 10)) throw fail();
    raw.atom.serial = whole_number(fields[1]);
    raw.atom.name = fields[2];
    raw.atom.residue_name = fields[3];
    std::string residue_number = fields[n - 6];
    raw.atom.chain = n - 6 > 4 ? fields[4] : "";
    if (!residue_number.empty() && std::isalpha(static_cast<unsigned char>(residue_number.back()))) {
      raw.atom.insertion_code = residue_number.back();
      residue_number.pop_back();
    }
    raw.atom.residue_number = whole_number(residue_number);
    raw.atom.hetero = fields[0] == "HETATM";
    // PQR has no element column: ions are named after their element (residue FE, atom FE), other atoms
    // start with their element letter after any digits (1HG1 is a hydrogen).
    const std::string name = upper(raw.atom.name);
    if (name == upper(raw.atom.residue_name) && name.size() <= 2) {
      raw.atom.element = name;
    } else {
      const auto first = name.find_first_not_of("0123456789");
      raw.atom.element = first == std::string::npos ? "X" : name.substr(first, 1);
    }
    classify(raw);
    atoms.push_back(std::move(raw));
  }
  return atoms;
}

// The file's atoms of the model asked for, unfiltered. Throws InputError when the file is missing, empty,
// of an unknown format, holds no atoms, or lacks the model.
std::vector<RawAtom> read_raw_atoms(const std::filesystem::path& path, const StructureOptions& options,
                                    StructureReport& report) {
  molecule_detail::StructureText text = molecule_detail::read_structure_text(path);
  const std::string extension = lower_extension(path);
  const bool pqr = extension == ".pqr";
  if (!pqr && extension != ".pdb" && extension != ".ent" && extension != ".cif" && extension != ".mmcif")
    throw InputError(
        fmt::format("{}: unknown structure format '{}'; spheremap reads .pdb, .ent, .cif, .mmcif (also "
                    ".gz) and .pqr",
                    path.string(), extension));
  report.warnings = std::move(text.warnings);
  std::vector<RawAtom> raw;
  if (pqr) {
    raw = read_pqr(path, text.bytes);
    report.models_in_file = 1;
    if (options.model != 1)
      throw InputError(
          fmt::format("{}: --model {} does not exist: PQR files hold one model", path.string(), options.model));
  } else {
    raw = read_with_gemmi(path, text.bytes, options.model, report.models_in_file, report.warnings);
  }
  for (auto& a : raw) make_text_valid(a.atom);
  report.atoms_in_model = static_cast<std::int64_t>(raw.size());
  if (raw.empty()) throw InputError(fmt::format("{}: the file contains no atoms", path.string()));
  return raw;
}

// Throws InputError naming the chains there are when one asked for is not.
void require_chains(const std::vector<RawAtom>& raw, const std::vector<std::string>& chains,
                    const std::filesystem::path& path) {
  if (chains.empty()) return;
  std::set<std::string> present;
  for (const auto& a : raw) present.insert(a.atom.chain);
  for (const auto& wanted : chains)
    if (!present.count(wanted))
      throw InputError(fmt::format("{}: chain '{}' does not exist; the chains are: {}", path.string(), wanted,
                                   fmt::join(present, ", ")));
}

// The most occupied alternate location of each residue (mean occupancy of its atoms; ties: first letter).
std::map<std::string, char> kept_alternate_locations(const std::vector<RawAtom>& raw) {
  std::map<std::string, std::map<char, std::pair<double, int>>> occupancy_by_residue;
  for (const auto& a : raw) {
    if (a.altloc == 0 || a.altloc == ' ') continue;
    auto& entry = occupancy_by_residue[a.residue_key][a.altloc];
    entry.first += a.occupancy;
    entry.second += 1;
  }
  std::map<std::string, char> kept_altloc;
  for (const auto& [key, letters] : occupancy_by_residue) {
    char best = 0;
    double best_mean = -1;
    for (const auto& [letter, sum_count] : letters) {
      const double mean = sum_count.first / sum_count.second;
      if (mean > best_mean) best_mean = mean, best = letter;
    }
    kept_altloc[key] = best;
  }
  return kept_altloc;
}

// Whether the options leave the atom out (counted in the report by why).
bool filtered_out(const RawAtom& a, const StructureOptions& options, bool pqr, std::map<std::string, char>& kept_altloc,
                  StructureReport& report) {
  if (a.altloc != 0 && a.altloc != ' ' && kept_altloc[a.residue_key] != a.altloc) {
    ++report.alternate_locations_removed;
    return true;
  }
  if (!options.chains.empty() &&
      std::find(options.chains.begin(), options.chains.end(), a.atom.chain) == options.chains.end()) {
    ++report.other_chains_removed;
    return true;
  }
  if (a.hydrogen && !options.keep_hydrogens.value_or(pqr)) {
    ++report.hydrogens_removed;
    return true;
  }
  if (a.water && !options.keep_waters) {
    ++report.waters_removed;
    return true;
  }
  if (a.atom.hetero && !a.water && !options.keep_hetero) {
    ++report.hetero_removed;
    return true;
  }
  return false;
}

// Throws InputError when a coordinate is not finite or beyond kAbsurdCoordinate.
void require_real_position(const RawAtom& a, const std::filesystem::path& path) {
  for (double c : a.atom.position) {
    if (!std::isfinite(c) || std::abs(c) > kAbsurdCoordinate)
      throw InputError(
          fmt::format("{}: atom {} ({} {}{}) has the coordinate {}, which is not a real position; fix "
                      "the file",
                      path.string(), a.atom.serial, a.atom.name, a.atom.residue_name, a.atom.residue_number, c));
  }
}

// Radii by element from options.radii or the Bondi table; elements neither lists get kUnknownElementRadius,
// and one warning each naming up to five of their atoms.
class ElementRadii {
 public:
  explicit ElementRadii(const StructureOptions& options) : options_(options) {}

  double radius(const Atom& atom) {
    std::optional<double> radius;
    if (options_.radii) {
      const auto it = options_.radii->find(atom.element);
      if (it != options_.radii->end()) radius = it->second;
    } else {
      radius = bondi_radius(atom.element);
    }
    if (radius) return *radius;
    auto& named = unknown_[atom.element];
    if (named.size() < 5)
      named.push_back(fmt::format("{} {} {}{}", atom.name, atom.residue_name, atom.chain, atom.residue_number));
    else if (named.size() == 5)
      named.push_back("...");
    return kUnknownElementRadius;
  }

  void add_warnings(std::vector<std::string>& warnings) const {
    for (const auto& [element, atoms] : unknown_)
      warnings.push_back(fmt::format("no radius for element '{}' ({}): {} Å used", element, fmt::join(atoms, "; "),
                                     kUnknownElementRadius));
  }

 private:
  const StructureOptions& options_;
  std::map<std::string, std::vector<std::string>> unknown_;  // element -> atom descriptions
};

}  // namespace

Molecule read_structure(const std::filesystem::path& path, const StructureOptions& options) {
  Molecule molecule;
  StructureReport& report = molecule.report;
  std::vector<RawAtom> raw = read_raw_atoms(path, options, report);
  const bool pqr = lower_extension(path) == ".pqr";  // PQR files give each atom's radius
  require_chains(raw, options.chains, path);
  auto kept_altloc = kept_alternate_locations(raw);
  ElementRadii radii(options);
  for (auto& a : raw) {
    if (filtered_out(a, options, pqr, kept_altloc, report)) continue;
    require_real_position(a, path);
    if (!pqr) a.atom.radius = radii.radius(a.atom);
    molecule.atoms.push_back(std::move(a.atom));
  }
  radii.add_warnings(report.warnings);
  for (auto& warning : report.warnings) warning = valid_utf8(warning);  // some quote the file
  if (options.strict && !report.warnings.empty())
    throw InputError(fmt::format("{}: --strict: {}. Fix the file, or leave out --strict to map it with {}",
                                 path.string(), fmt::join(report.warnings, "; "),
                                 report.warnings.size() == 1 ? "this warning" : "these warnings"));
  if (molecule.atoms.size() < 2)
    throw InputError(
        fmt::format("{}: {} atom(s) left after filtering (hydrogens, waters{}); a molecular surface needs "
                    "at least two. Check --chains and --model, or keep more atoms (--keep-waters, "
                    "--keep-hydrogens{})",
                    path.string(), molecule.atoms.size(), options.keep_hetero ? "" : ", HETATM groups",
                    options.keep_hetero ? "" : ", without --no-hetero"));
  return molecule;
}

}  // namespace spheremap
