// Reading a values file (read_values_file) and giving its values to atoms (match_values).
#include "spheremap/properties/values_file.hpp"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <tuple>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/io/csv.hpp"

namespace spheremap {
namespace {

std::string trimmed(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r");
  if (first == std::string::npos) return {};
  return text.substr(first, text.find_last_not_of(" \t\r") - first + 1);
}

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

bool is_property_name(const std::string& name) {
  if (name.empty() || !std::islower(static_cast<unsigned char>(name.front()))) return false;
  return std::all_of(name.begin(), name.end(),
                     [](unsigned char c) { return std::islower(c) || std::isdigit(c) || c == '_'; });
}

// Where each kind of column is (-1: absent).
struct Layout {
  int chain = -1, residue = -1, insertion = -1, atom = -1;
  std::vector<int> value_columns;
};

Layout read_header(const DelimitedRecord& header, ValuesTable& table, const std::string& name) {
  Layout layout;
  std::set<std::string> seen;
  for (std::size_t k = 0; k < header.fields.size(); ++k) {
    const std::string column = lower(trimmed(header.fields[k]));
    const int index = static_cast<int>(k);
    int* key = nullptr;
    if (column == "chain")
      key = &layout.chain;
    else if (column == "residue_number" || column == "resnum" || column == "resi" || column == "residue")
      key = &layout.residue;
    else if (column == "insertion_code" || column == "icode")
      key = &layout.insertion;
    else if (column == "atom_name" || column == "atom" || column == "name")
      key = &layout.atom;
    if (!seen.insert(column).second)
      throw InputError(fmt::format("{}:{}: the header names column '{}' twice", name, header.line, column));
    if (key != nullptr) {
      *key = index;
      continue;
    }
    if (!is_property_name(column))
      throw InputError(
          fmt::format("{}:{}: column '{}' cannot name a property: use letters, digits and '_', starting "
                      "with a letter",
                      name, header.line, header.fields[k]));
    layout.value_columns.push_back(index);
    table.columns.push_back(column);
  }
  if (layout.chain < 0 || layout.residue < 0)
    throw InputError(
        fmt::format("{}:{}: the header needs a 'chain' and a 'residue_number' column (then optionally "
                    "'insertion_code' and 'atom_name', then value columns); it has: {}",
                    name, header.line, fmt::join(header.fields, ", ")));
  if (layout.value_columns.empty())
    throw InputError(
        fmt::format("{}:{}: no value column: add at least one column of numbers, named by the property "
                    "it holds (e.g. conservation)",
                    name, header.line));
  return layout;
}

double value_of(const std::string& cell, const std::string& name, std::int64_t line, const std::string& column) {
  const std::string text = trimmed(cell);
  const std::string low = lower(text);
  if (text.empty() || low == "na" || low == "nan") return std::numeric_limits<double>::quiet_NaN();
  double value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc{} || end != text.data() + text.size() || !std::isfinite(value))
    throw InputError(
        fmt::format("{}:{}: column '{}': '{}' is not a number (leave the cell empty, or write NA, for no "
                    "value)",
                    name, line, column, text));
  return value;
}

ValuesRow read_row(const DelimitedRecord& record, const Layout& layout, const ValuesTable& table,
                   const std::string& name) {
  ValuesRow row;
  row.line = record.line;
  row.chain = trimmed(record.fields[static_cast<std::size_t>(layout.chain)]);
  std::string number = trimmed(record.fields[static_cast<std::size_t>(layout.residue)]);
  std::string insertion =
      layout.insertion >= 0 ? trimmed(record.fields[static_cast<std::size_t>(layout.insertion)]) : "";
  // "45A": residue 45, insertion code A, when no insertion code is given apart.
  if (insertion.empty() && !number.empty() && std::isalpha(static_cast<unsigned char>(number.back()))) {
    insertion = number.substr(number.size() - 1);
    number.pop_back();
  }
  const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), row.residue_number);
  if (number.empty() || error != std::errc{} || end != number.data() + number.size())
    throw InputError(fmt::format("{}:{}: residue number '{}' is not an integer", name, record.line, number));
  if (insertion.size() > 1)
    throw InputError(
        fmt::format("{}:{}: insertion code '{}' has more than one character", name, record.line, insertion));
  row.insertion_code = insertion.empty() ? ' ' : insertion.front();
  if (layout.atom >= 0) row.atom_name = trimmed(record.fields[static_cast<std::size_t>(layout.atom)]);
  for (std::size_t c = 0; c < layout.value_columns.size(); ++c)
    row.values.push_back(value_of(record.fields[static_cast<std::size_t>(layout.value_columns[c])], name, record.line,
                                  table.columns[c]));
  return row;
}

using RowKey = std::tuple<std::string, std::int32_t, char, std::string>;  // chain, number, insertion, atom

std::string key_text(const std::string& chain, std::int32_t number, char insertion, const std::string& atom = "") {
  std::string text = fmt::format("{}:{}", chain, number);
  if (insertion != ' ') text += insertion;
  if (!atom.empty()) text += "@" + atom;
  return text;
}

}  // namespace

ValuesTable read_values_file(const std::filesystem::path& file) {
  const std::string name = file.string();
  std::ifstream in(file, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open the values file; check the path", name));
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  // The header decides the delimiter: the first line that is neither blank nor a comment.
  std::istringstream lines(text);
  char delimiter = ',';
  for (std::string line; std::getline(lines, line);) {
    if (trimmed(line).empty() || line.front() == '#') continue;
    if (line.find('\t') != std::string::npos) delimiter = '\t';
    break;
  }
  const auto records = read_delimited(text, delimiter, name);
  if (records.empty()) throw InputError(fmt::format("{}: the values file has no header line", name));
  ValuesTable table;
  table.file = file;
  const Layout layout = read_header(records.front(), table, name);
  std::map<RowKey, std::int64_t> line_of;
  for (std::size_t r = 1; r < records.size(); ++r) {
    const DelimitedRecord& record = records[r];
    if (std::all_of(record.fields.begin(), record.fields.end(), [](const auto& f) { return trimmed(f).empty(); }))
      continue;
    if (record.fields.size() != records.front().fields.size())
      throw InputError(fmt::format("{}:{}: {} fields, but the header has {} columns", name, record.line,
                                   record.fields.size(), records.front().fields.size()));
    ValuesRow row = read_row(record, layout, table, name);
    const auto [it, inserted] =
        line_of.try_emplace(RowKey{row.chain, row.residue_number, row.insertion_code, row.atom_name}, row.line);
    if (!inserted)
      throw InputError(fmt::format("{}:{}: {} has a row already (line {}); give each residue or atom one row", name,
                                   row.line, key_text(row.chain, row.residue_number, row.insertion_code, row.atom_name),
                                   it->second));
    table.rows.push_back(std::move(row));
  }
  return table;
}

std::vector<AtomValues> match_values(const ValuesTable& table, const std::vector<Atom>& atoms) {
  const std::string name = table.file.string();
  std::set<std::string> chains;
  for (const Atom& a : atoms) chains.insert(a.chain);
  std::map<RowKey, std::size_t> row_of;
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const ValuesRow& row = table.rows[r];
    if (!chains.count(row.chain))
      throw InputError(
          fmt::format("{}:{}: chain '{}' is not in the structure (its chains, after --chains: {}); fix "
                      "the chain names",
                      name, row.line, row.chain, fmt::join(chains, ", ")));
    row_of[RowKey{row.chain, row.residue_number, row.insertion_code, row.atom_name}] = r;
  }
  std::vector<bool> used(table.rows.size(), false);
  std::vector<std::int64_t> row_of_atom(atoms.size(), -1);
  for (std::size_t a = 0; a < atoms.size(); ++a) {
    const Atom& atom = atoms[a];
    auto found = row_of.find(RowKey{atom.chain, atom.residue_number, atom.insertion_code, atom.name});
    if (found == row_of.end()) found = row_of.find(RowKey{atom.chain, atom.residue_number, atom.insertion_code, ""});
    if (found == row_of.end()) continue;
    row_of_atom[a] = static_cast<std::int64_t>(found->second);
    used[found->second] = true;
  }
  std::vector<AtomValues> result(table.columns.size());
  for (std::size_t c = 0; c < table.columns.size(); ++c) {
    AtomValues& column = result[c];
    column.name = table.columns[c];
    column.rows = static_cast<std::int64_t>(table.rows.size());
    column.per_atom.assign(atoms.size(), std::numeric_limits<double>::quiet_NaN());
    for (std::size_t a = 0; a < atoms.size(); ++a)
      if (row_of_atom[a] >= 0) column.per_atom[a] = table.rows[static_cast<std::size_t>(row_of_atom[a])].values[c];
    column.atoms_without_value =
        std::count_if(column.per_atom.begin(), column.per_atom.end(), [](double v) { return std::isnan(v); });
    for (std::size_t r = 0; r < table.rows.size(); ++r) {
      if (used[r]) continue;
      ++column.rows_unmatched;
      const ValuesRow& row = table.rows[r];
      if (column.unmatched_examples.size() < 5)
        column.unmatched_examples.push_back(fmt::format(
            "line {}: {}", row.line, key_text(row.chain, row.residue_number, row.insertion_code, row.atom_name)));
    }
  }
  return result;
}

}  // namespace spheremap
