// Reading a map output folder back (see map_folder.hpp).
#include "spheremap/pipeline/map_folder.hpp"

#include <algorithm>
#include <charconv>
#include <fstream>
#include <map>
#include <sstream>

#include <fmt/format.h>

#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/csv.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/pipeline/report.hpp"
#include "spheremap/properties/registry.hpp"
#include "spheremap/text.hpp"

namespace spheremap {
namespace {

const char* const kFix = "give the folder that `spheremap map INPUT -o FOLDER` wrote (or map again)";

std::string input_name(const std::string& input) {
  std::filesystem::path name = std::filesystem::path(input).filename();
  if (name.extension() == ".gz") name = name.stem();
  return valid_utf8(name.stem().string());  // titles go through cairo, which takes UTF-8 only
}

std::string file_text(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A text attribute of one value per vertex: the `column` of the atom each vertex names.
TextAttribute text_column(const std::vector<DelimitedRecord>& rows, std::size_t column,
                          const std::vector<std::int32_t>& atomid) {
  TextAttribute attribute;
  std::map<std::string, std::int32_t> code;
  attribute.codes.reserve(atomid.size());
  for (const std::int32_t atom : atomid) {
    const std::string& text = rows[static_cast<std::size_t>(atom) + 1].fields[column];
    const auto [at, added] = code.try_emplace(text, static_cast<std::int32_t>(attribute.dictionary.size()));
    if (added) attribute.dictionary.push_back(text);
    attribute.codes.push_back(at->second);
  }
  return attribute;
}

std::vector<std::int32_t> integer_column(const std::vector<DelimitedRecord>& rows, std::size_t column,
                                         const std::vector<std::int32_t>& atomid, const std::filesystem::path& path,
                                         const std::string& name) {
  std::vector<std::int32_t> values;
  values.reserve(atomid.size());
  for (const std::int32_t atom : atomid) {
    const DelimitedRecord& row = rows[static_cast<std::size_t>(atom) + 1];
    const std::string& text = row.fields[column];
    std::int32_t value = 0;
    const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
    if (error != std::errc() || end != text.data() + text.size())
      throw InputError(
          fmt::format("{}:{}: {} '{}' is not a whole number; {}", path.string(), row.line, name, text, kFix));
    values.push_back(value);
  }
  return values;
}

// Joins atoms.csv's provenance columns to the surface's vertices by `atomid` (row k + 1 is atom k).
void join_atoms(Mesh& surface, const std::filesystem::path& path) {
  const std::vector<std::int32_t>& atomid = surface.integer_attributes.at(attributes::kAtomId);
  const std::vector<DelimitedRecord> rows = read_delimited(file_text(path), ',', path.string());
  if (rows.empty()) throw InputError(fmt::format("{}: empty, no header; {}", path.string(), kFix));
  const std::vector<std::string>& header = rows.front().fields;
  auto column = [&](const char* name) {
    const auto found = std::find(header.begin(), header.end(), name);
    if (found == header.end())
      throw InputError(fmt::format("{}: no column '{}' in the header; {}", path.string(), name, kFix));
    return static_cast<std::size_t>(found - header.begin());
  };
  const std::size_t id = column("atomid");
  for (std::size_t k = 1; k < rows.size(); ++k)
    if (rows[k].fields.size() != header.size() || rows[k].fields[id] != std::to_string(k - 1))
      throw InputError(fmt::format("{}:{}: expected {} fields and atomid {}; {}", path.string(), rows[k].line,
                                   header.size(), k - 1, kFix));
  for (const std::int32_t atom : atomid)
    if (atom < 0 || static_cast<std::size_t>(atom) + 1 >= rows.size())
      throw InputError(fmt::format("{}: surface.ply names atomid {} but the file lists {} atoms (from two runs?); {}",
                                   path.string(), atom, rows.size() - 1, kFix));
  surface.text_attributes[attributes::kChain] = text_column(rows, column("chain"), atomid);
  surface.text_attributes[attributes::kInsertionCode] = text_column(rows, column("insertion_code"), atomid);
  surface.text_attributes[attributes::kResidueName] = text_column(rows, column("residue_name"), atomid);
  surface.text_attributes[attributes::kAtomName] = text_column(rows, column("atom_name"), atomid);
  surface.text_attributes[attributes::kElement] = text_column(rows, column("element"), atomid);
  surface.integer_attributes[attributes::kResidueNumber] =
      integer_column(rows, column("residue_number"), atomid, path, "residue_number");
  surface.integer_attributes[attributes::kAtomSerial] = integer_column(rows, column("serial"), atomid, path, "serial");
  surface.integer_attributes[attributes::kModel] = integer_column(rows, column("model"), atomid, path, "model");
}

// The PLY's `vertex_<name>` values of the properties report.json lists: registry order, then the others
// (--values columns) in the report's order.
std::vector<SurfaceProperty> folder_properties(const Mesh& surface, const nlohmann::json& report,
                                               const std::filesystem::path& folder) {
  std::vector<ReportProperty> listed = read_report_properties(report, folder / kReportFile);
  std::vector<ReportProperty> ordered;
  for (const PropertyDefinition& definition : property_registry())
    for (ReportProperty& p : listed)
      if (p.info.name == definition.info.name) ordered.push_back(std::move(p)), p.info.name.clear();
  for (ReportProperty& p : listed)
    if (!p.info.name.empty()) ordered.push_back(std::move(p));
  std::vector<SurfaceProperty> properties;
  for (ReportProperty& p : ordered) {
    const auto values = surface.real_attributes.find(attributes::kPropertyPrefix + p.info.name);
    if (values == surface.real_attributes.end())
      throw InputError(fmt::format("{}: report.json lists the property {} but {} has no {}{}; {}", folder.string(),
                                   p.info.name, kSurfaceFile, attributes::kPropertyPrefix, p.info.name, kFix));
    SurfaceProperty property{std::move(p.info), std::move(p.source), values->second};
    if (const PropertyInfo* built_in = find_property(property.info.name)) {
      std::vector<std::string> categories = std::move(property.info.categories);  // this surface's (chains)
      property.info = *built_in;
      if (!categories.empty()) property.info.categories = std::move(categories);
    }
    properties.push_back(std::move(property));
  }
  return properties;
}

}  // namespace

MapFolder read_map_folder(const std::filesystem::path& folder) {
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error))
    throw InputError(fmt::format("{}: no such folder; {}", folder.string(), kFix));
  for (const char* file : {kSurfaceFile, kSphereFile, kReportFile})
    if (!std::filesystem::is_regular_file(folder / file, error))
      throw InputError(
          fmt::format("{}: the folder has no {}, so it is not a finished map; {}", folder.string(), file, kFix));
  MapFolder map;
  map.folder = folder;
  map.surface = read_ply_mesh(folder / kSurfaceFile);
  const Mesh sphere = read_ply_mesh(folder / kSphereFile);
  if (sphere.vertex_count() != map.surface.vertex_count() || sphere.triangles != map.surface.triangles)
    throw InputError(fmt::format("{}: {} and {} do not have the same vertices and triangles (from two runs?); {}",
                                 folder.string(), kSurfaceFile, kSphereFile, kFix));
  map.sphere = sphere.positions;
  try {
    map.report = nlohmann::json::parse(file_text(folder / kReportFile));
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON ({}); {}", (folder / kReportFile).string(), e.what(), kFix));
  }
  const auto input = map.report.find("input");
  map.name = input != map.report.end() && input->is_string() ? input_name(input->get<std::string>())
                                                             : folder.filename().string();
  if (map.name.empty()) map.name = "map";
  // Folders before the property registry carried the provenance as PLY text; now atoms.csv holds it.
  const bool has_atoms = map.surface.integer_attributes.count(attributes::kAtomId) > 0;
  if (has_atoms && map.surface.text_attributes.count(attributes::kChain) == 0) {
    if (std::filesystem::is_regular_file(folder / kAtomsFile, error))
      join_atoms(map.surface, folder / kAtomsFile);
    else
      map.no_residues_reason = fmt::format(
          "{} has no {}, which names the chain and residue of each atom (surface.ply's atomid); map the structure "
          "again to write it",
          folder.string(), kAtomsFile);
  }
  map.properties = folder_properties(map.surface, map.report, folder);
  return map;
}

}  // namespace spheremap
