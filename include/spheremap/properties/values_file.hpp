// --values FILE: any per-atom or per-residue values (conservation, pLDDT, interface labels, docking
// scores, ...) from a CSV or TSV table, as surface properties (stage: properties).
#pragma once

#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "spheremap/molecule/structure.hpp"

namespace spheremap {

/// One data row of a values file.
struct ValuesRow {
  std::int64_t line = 0;
  std::string chain;
  std::int32_t residue_number = 0;
  char insertion_code = ' ';
  std::string atom_name;       // empty: the row is for every atom of the residue
  std::vector<double> values;  // one per value column; NaN for an empty, NA or NaN cell
};

/// A values file as read. The dialect (docs/properties.md): a header line, then one row per residue or atom;
/// tab-separated when the header holds a tab, else comma-separated; RFC 4180 quoting; blank lines and lines
/// starting with '#' skipped; UTF-8. Columns, named by the header (any case, any order): `chain`,
/// `residue_number` (or `resnum`, `resi`, `residue`), optionally `insertion_code` (`icode`) and `atom_name`
/// (`atom`, `name`); every other column holds values and becomes a property named by its header in lower case
/// (letters, digits and '_', starting with a letter).
struct ValuesTable {
  std::filesystem::path file;
  std::vector<std::string> columns;  // the property names, in file order
  std::vector<ValuesRow> rows;
};

/// Reads and checks a values file. Throws InputError naming the file, the line and the problem for: a missing
/// file, no header, a missing chain or residue-number column, no value column, a column name that is not a
/// valid property name or is one twice, a row with another number of fields than the header, a residue number
/// that is not an integer, a value that is not a number (empty, NA and NaN mean no value), an insertion code
/// of more than one character, or two rows for the same residue or atom.
ValuesTable read_values_file(const std::filesystem::path& file);

/// One value column matched to a structure's atoms.
struct AtomValues {
  std::string name;                             // the property name (the column's)
  std::vector<double> per_atom;                 // per atom of the structure; NaN where no row gives a value
  std::int64_t rows = 0;                        // data rows of the file
  std::int64_t rows_unmatched = 0;              // rows naming a residue or atom the structure does not have
  std::int64_t atoms_without_value = 0;         // atoms of the structure no row gives a (non-NaN) value
  std::vector<std::string> unmatched_examples;  // up to 5 unmatched rows: "line 12: A:145"
};

/// Gives each atom the value of the row of its atom, else of the row of its residue (an atom row is more
/// specific). Throws InputError naming the file and line for a chain the structure does not have (listing
/// the chains it has).
std::vector<AtomValues> match_values(const ValuesTable& table, const std::vector<Atom>& atoms);

}  // namespace spheremap
