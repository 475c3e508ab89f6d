// The data every picture of a map draws from (see globe.hpp).
#include "spheremap/render/globe.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <stdexcept>
#include <tuple>

#include "mesh_attributes.hpp"
#include "spheremap/attributes.hpp"
#include "spheremap/properties/shape.hpp"

namespace spheremap {
namespace {

using detail::find_attribute;

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

using ResidueKey = std::tuple<std::string, std::int32_t, std::string>;  // chain, number, insertion code

// The residue of each vertex, from its atom's chain and number; residues sorted by key.
void add_residues(const Mesh& surface, Globe& globe) {
  const TextAttribute* chain = find_attribute(surface.text_attributes, attributes::kChain);
  const auto* number = find_attribute(surface.integer_attributes, attributes::kResidueNumber);
  if (chain == nullptr || number == nullptr) return;
  const TextAttribute* insertion = find_attribute(surface.text_attributes, attributes::kInsertionCode);
  const TextAttribute* name = find_attribute(surface.text_attributes, attributes::kResidueName);
  // The vertices' residues by their attributes' codes first (integers: cheap to compare), then each distinct one
  // by its text (a few thousand, however many vertices): the same residues, names and order as keying every vertex
  // by its text.
  std::map<std::array<std::int32_t, 3>, std::int32_t> slots;  // codes -> slot, in order of first vertex
  std::vector<std::size_t> first_vertex;                      // of each slot
  std::vector<std::int32_t> vertex_slot(surface.vertex_count());
  for (std::size_t v = 0; v < surface.vertex_count(); ++v) {
    const std::array<std::int32_t, 3> codes{chain->codes[v], (*number)[v], insertion ? insertion->codes[v] : -1};
    const auto [slot, added] = slots.try_emplace(codes, static_cast<std::int32_t>(first_vertex.size()));
    if (added) first_vertex.push_back(v);
    vertex_slot[v] = slot->second;
  }
  std::map<ResidueKey, std::string> names;  // the name of the first vertex of each residue
  std::vector<ResidueKey> slot_key;
  slot_key.reserve(first_vertex.size());
  for (const std::size_t v : first_vertex) {
    slot_key.emplace_back(chain->at(v), (*number)[v], insertion ? insertion->at(v) : std::string());
    names.try_emplace(slot_key.back(), name ? name->at(v) : std::string());
  }
  std::map<ResidueKey, std::int32_t> index;
  for (const auto& [key, residue_name] : names) {
    index.emplace(key, static_cast<std::int32_t>(globe.residues.size()));
    globe.residues.push_back({std::get<0>(key), std::get<1>(key), std::get<2>(key), residue_name});
  }
  std::vector<std::int32_t> slot_residue;
  slot_residue.reserve(slot_key.size());
  for (const ResidueKey& key : slot_key) slot_residue.push_back(index.at(key));
  globe.vertex_residue.reserve(vertex_slot.size());
  for (const std::int32_t slot : vertex_slot)
    globe.vertex_residue.push_back(slot_residue[static_cast<std::size_t>(slot)]);
}

SurfaceProperty octant_property(const std::vector<Vec3>& sphere) {
  SurfaceProperty p{
      {"octant", "", ScaleKind::categorical, std::nullopt, {octant_names().begin(), octant_names().end()}},
      "globe position",
      {}};
  p.values.reserve(sphere.size());
  // A zero coordinate counts as +, as in the octant metrics.
  for (const Vec3& s : sphere) p.values.push_back((s[0] < 0) + 2 * (s[1] < 0) + 4 * (s[2] < 0));
  return p;
}

// Chains numbered in order of their first atom (atomid) on the surface.
SurfaceProperty chain_property(const Mesh& surface, const TextAttribute& chain) {
  SurfaceProperty p{{"chain_index", "", ScaleKind::categorical, std::nullopt, {}}, "structure", {}};
  const auto* atom = find_attribute(surface.integer_attributes, attributes::kAtomId);
  std::vector<std::int32_t> first_atom(chain.dictionary.size(), std::numeric_limits<std::int32_t>::max());
  for (std::size_t v = 0; v < surface.vertex_count(); ++v) {
    auto& first = first_atom[static_cast<std::size_t>(chain.codes[v])];
    first = std::min(first, atom ? (*atom)[v] : static_cast<std::int32_t>(v));
  }
  std::vector<std::int32_t> order;  // codes present, by first atom
  for (std::size_t c = 0; c < first_atom.size(); ++c)
    if (first_atom[c] != std::numeric_limits<std::int32_t>::max()) order.push_back(static_cast<std::int32_t>(c));
  std::sort(order.begin(), order.end(),
            [&](std::int32_t a, std::int32_t b) { return std::tie(first_atom[a], a) < std::tie(first_atom[b], b); });
  std::vector<double> class_of(chain.dictionary.size(), kNaN);
  for (std::size_t k = 0; k < order.size(); ++k) {
    class_of[order[k]] = static_cast<double>(k);
    p.info.categories.push_back(chain.dictionary[order[k]]);
  }
  p.values.reserve(surface.vertex_count());
  for (const std::int32_t code : chain.codes) p.values.push_back(class_of[code]);
  return p;
}

// Residues of the polymer: amino acids (with the protonation names of PQR files) and nucleotides. Ligands,
// ions and waters are not in the sequence.
bool polymer_residue(const std::string& name) {
  static const std::set<std::string> names{
      "ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU", "GLY", "HIS", "ILE", "LEU", "LYS", "MET", "PHE", "PRO", "SER",
      "THR", "TRP", "TYR", "VAL", "MSE", "SEC", "PYL", "HID", "HIE", "HIP", "HSD", "HSE", "HSP", "CYX", "CYM", "ASH",
      "GLH", "LYN", "ARN", "TYM", "A",   "C",   "G",   "U",   "I",   "DA",  "DC",  "DG",  "DT",  "DI"};
  return names.count(name) > 0;
}

// Polymer residues of each chain ranked by (number, insertion code), 0 for the first, 1 for the last; NaN for
// ligands, ions and waters.
SurfaceProperty sequence_property(const Globe& globe) {
  SurfaceProperty p{
      {"sequence_position", "", ScaleKind::spectrum, ValueRange{0, 1}, {}}, "residue order on the surface", {}};
  std::vector<double> position(globe.residues.size(), kNaN);
  // globe.residues is sorted by chain, then number and insertion code: each chain is one run.
  for (std::size_t first = 0; first < globe.residues.size();) {
    std::size_t last = first;
    while (last + 1 < globe.residues.size() && globe.residues[last + 1].chain == globe.residues[first].chain) ++last;
    std::vector<std::size_t> polymer;
    for (std::size_t r = first; r <= last; ++r)
      if (polymer_residue(globe.residues[r].name)) polymer.push_back(r);
    for (std::size_t k = 0; k < polymer.size(); ++k)
      position[polymer[k]] =
          polymer.size() > 1 ? static_cast<double>(k) / static_cast<double>(polymer.size() - 1) : 0.0;
    first = last + 1;
  }
  p.values.reserve(globe.vertex_residue.size());
  for (const std::int32_t r : globe.vertex_residue) p.values.push_back(r < 0 ? kNaN : position[r]);
  return p;
}

template <typename T>
SurfaceProperty copied_property(std::string name, std::string unit, ScaleKind scale, const std::vector<T>& values,
                                std::string source) {
  SurfaceProperty p{{std::move(name), std::move(unit), scale, std::nullopt, {}}, std::move(source), {}};
  p.values.assign(values.begin(), values.end());
  return p;
}

}  // namespace

std::string residue_id(const ResidueLabel& residue) {
  return residue.chain + ":" + std::to_string(residue.number) + residue.insertion_code;
}

Globe make_globe(const Mesh& surface, const std::vector<Vec3>& sphere, std::vector<SurfaceProperty> properties,
                 std::string name) {
  if (sphere.size() != surface.vertex_count())
    throw std::invalid_argument("make_globe: " + std::to_string(sphere.size()) + " globe points for " +
                                std::to_string(surface.vertex_count()) + " surface vertices");
  for (const auto& p : properties)
    if (p.values.size() != surface.vertex_count())
      throw std::invalid_argument("make_globe: property " + p.info.name + " has " + std::to_string(p.values.size()) +
                                  " values for " + std::to_string(surface.vertex_count()) + " vertices");
  Globe globe;
  globe.name = std::move(name);
  globe.surface = surface.positions;
  globe.sphere = sphere;
  globe.triangles = surface.triangles;
  add_residues(surface, globe);
  globe.properties = std::move(properties);
  return globe;
}

std::string no_residues_text(const Globe& globe) {
  return globe.no_residues_reason.empty() ? "it was made from a mesh file, not a structure" : globe.no_residues_reason;
}

const SurfaceProperty* find_globe_property(const Globe& globe, std::string_view name) {
  for (const auto& p : globe.properties)
    if (p.info.name == name) return &p;
  return nullptr;
}

std::string globe_property_names(const Globe& globe) {
  std::string names;
  for (const auto& p : globe.properties) names += (names.empty() ? "" : ", ") + p.info.name;
  return names.empty() ? "(none)" : names;
}

std::vector<SurfaceProperty> properties_from_attributes(const Mesh& surface, const std::vector<Vec3>& sphere) {
  std::vector<SurfaceProperty> properties{octant_property(sphere)};
  if (const TextAttribute* chain = find_attribute(surface.text_attributes, attributes::kChain))
    properties.push_back(chain_property(surface, *chain));
  Globe residues;
  add_residues(surface, residues);
  if (!residues.residues.empty()) properties.push_back(sequence_property(residues));
  if (const auto* number = find_attribute(surface.integer_attributes, attributes::kResidueNumber))
    properties.push_back(copied_property("residue_number", "", ScaleKind::sequential, *number, "structure"));
  if (const auto* b = find_attribute(surface.real_attributes, attributes::kBFactor))
    properties.push_back(copied_property("b_factor", "Å²", ScaleKind::sequential, *b, "structure"));
  if (const auto* charge = find_attribute(surface.real_attributes, attributes::kCharge))
    properties.push_back(copied_property("charge", "e", ScaleKind::diverging, *charge, "PQR"));
  return properties;
}

}  // namespace spheremap
