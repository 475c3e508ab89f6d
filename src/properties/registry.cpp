// The built-in properties and compute_properties: per-atom properties through `atomid`, electrostatics
// through surface_electrostatics, shape through principal curvatures, map properties from the sphere.
#include "spheremap/properties/registry.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "../util/stage_timer.hpp"
#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/curvature.hpp"
#include "spheremap/properties/colour_scale.hpp"
#include "spheremap/properties/residue_scales.hpp"
#include "spheremap/properties/residues.hpp"
#include "spheremap/properties/shape.hpp"

namespace spheremap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

PropertyDefinition definition(const char* name, const char* unit, ScaleKind scale, std::optional<ValueRange> range,
                              PropertyBasis basis, bool per_atom, const char* description) {
  PropertyDefinition d;
  d.info.name = name;
  d.info.unit = unit;
  d.info.scale = scale;
  d.info.default_range = range;
  d.basis = basis;
  d.per_atom = per_atom;
  d.description = description;
  return d;
}

ValueRange scale_range(ResidueScale scale) {
  const auto [lo, hi] = residue_scale_bounds(scale);
  return {lo, hi};
}

std::vector<PropertyDefinition> make_registry() {
  using namespace property_names;
  using K = ScaleKind;
  using B = PropertyBasis;
  return {
      definition(kElectrostatics, "kT/e", K::diverging, ValueRange{-2, 2}, B::kStructure, false,
                 "Electrostatic potential 1.4 Å outside the surface (Coulomb sum, an APBS map, or APBS run)"),
      definition(kHydrophobicity, "", K::sequential, scale_range(ResidueScale::kKyteDoolittle), B::kStructure, true,
                 "Kyte-Doolittle (1982) hydropathy of the vertex's residue"),
      definition(kWimleyWhite, "kcal/mol", K::sequential, scale_range(ResidueScale::kWimleyWhite), B::kStructure, true,
                 "Wimley-White (1996) interface scale of the vertex's residue (lower: more hydrophobic)"),
      definition(kEisenberg, "", K::sequential, scale_range(ResidueScale::kEisenberg), B::kStructure, true,
                 "Eisenberg et al. (1984) consensus hydrophobicity of the vertex's residue"),
      definition(kSequencePosition, "", K::spectrum, ValueRange{0, 1}, B::kStructure, true,
                 "Position of the vertex's residue along its chain: 0 at the N-terminus, 1 at the C-terminus"),
      definition(kResidueNumber, "", K::sequential, std::nullopt, B::kStructure, true,
                 "Residue number of the vertex's atom, as in the file"),
      definition(kChainIndex, "", K::categorical, std::nullopt, B::kStructure, true,
                 "Chain of the vertex's atom: 0 for the first chain of the file, 1 for the next, ..."),
      definition(kBFactor, "Å²", K::sequential, std::nullopt, B::kStructure, true,
                 "B-factor of the vertex's atom (PDB and mmCIF files)"),
      definition(kCharge, "e", K::diverging, ValueRange{-1, 1}, B::kStructure, true,
                 "Partial charge of the vertex's atom (PQR files)"),
      definition(kShapeIndex, "", K::diverging, ValueRange{-1, 1}, B::kSurface, false,
                 "Koenderink's shape index of the surface: -1 cup, -1/2 rut, 0 saddle, 1/2 ridge, 1 cap"),
      definition(kCurvedness, "1/Å", K::sequential, std::nullopt, B::kSurface, false,
                 "Koenderink's curvedness sqrt((k1² + k2²)/2) of the surface"),
      definition(kAreaDistortion, "", K::diverging, ValueRange{-2, 2}, B::kMap, false,
                 "ln of the map's local area ratio (sphere share / surface share of the vertex's triangles)"),
      definition(kOctant, "", K::categorical, std::nullopt, B::kMap, false,
                 "Octant of the vertex's point on the sphere: (x<0) + 2 (y<0) + 4 (z<0)"),
  };
}

bool wanted(const PropertyOptions& options, const std::string& name) {
  return !options.only || std::find(options.only->begin(), options.only->end(), name) != options.only->end();
}

// Per-atom values to per-vertex values through `atomid` (NaN for a vertex without an atom).
std::vector<double> per_vertex(const Mesh& surface, const std::vector<double>& per_atom) {
  std::vector<double> values(surface.vertex_count(), kNaN);
  const auto found = surface.integer_attributes.find(attributes::kAtomId);
  if (found == surface.integer_attributes.end()) return values;
  for (std::size_t v = 0; v < values.size(); ++v) {
    const auto atom = found->second[v];
    if (atom >= 0 && static_cast<std::size_t>(atom) < per_atom.size())
      values[v] = per_atom[static_cast<std::size_t>(atom)];
  }
  return values;
}

// The per-atom values of one per-atom built-in property; `report` gets the unknown residues.
std::vector<double> atom_values(const std::string& name, const std::vector<Atom>& atoms, const ResidueIndex& index,
                                const std::vector<double>& sequence, PropertyReport& report) {
  using namespace property_names;
  std::vector<double> values(atoms.size(), kNaN);
  const auto residue = [&](std::size_t a) -> const Residue& {
    return index.residues[static_cast<std::size_t>(index.residue_of_atom[a])];
  };
  const auto scale = [&](ResidueScale s) {
    for (std::size_t a = 0; a < atoms.size(); ++a) values[a] = residue_scale_value(s, residue(a).name).value_or(kNaN);
  };
  if (name == kHydrophobicity) {
    scale(ResidueScale::kKyteDoolittle);
    std::set<std::string> unknown;
    for (const Residue& r : index.residues)
      if (!residue_scale_value(ResidueScale::kKyteDoolittle, r.name))
        ++report.unknown_residues.residues, unknown.insert(r.name);
    report.unknown_residues.names.assign(unknown.begin(), unknown.end());
    if (report.unknown_residues.residues > 0)
      report.warnings.push_back(
          fmt::format("hydrophobicity: {} residue(s) of a type no hydrophobicity table knows ({}): "
                      "no value on their vertices",
                      report.unknown_residues.residues, fmt::join(unknown, ", ")));
  } else if (name == kWimleyWhite) {
    scale(ResidueScale::kWimleyWhite);
  } else if (name == kEisenberg) {
    scale(ResidueScale::kEisenberg);
  } else if (name == kSequencePosition) {
    for (std::size_t a = 0; a < atoms.size(); ++a)
      values[a] = sequence[static_cast<std::size_t>(index.residue_of_atom[a])];
  } else if (name == kResidueNumber) {
    for (std::size_t a = 0; a < atoms.size(); ++a) values[a] = atoms[a].residue_number;
  } else if (name == kChainIndex) {
    for (std::size_t a = 0; a < atoms.size(); ++a) values[a] = residue(a).chain_index;
  } else if (name == kBFactor) {
    for (std::size_t a = 0; a < atoms.size(); ++a) values[a] = atoms[a].b_factor.value_or(kNaN);
  } else if (name == kCharge) {
    for (std::size_t a = 0; a < atoms.size(); ++a) values[a] = atoms[a].charge.value_or(kNaN);
  }
  return values;
}

std::string dielectric_text(const ElectrostaticsOptions& options) {
  if (options.method == ElectrostaticsMethod::kApbs)
    return fmt::format("pdie {}, sdie {}", options.apbs.solute_dielectric, options.apbs.solvent_dielectric);
  if (options.method == ElectrostaticsMethod::kPotentialMap) return {};
  return options.coulomb.dielectric == Dielectric::kDistanceDependent
             ? fmt::format("{}r", options.coulomb.dielectric_value)
             : fmt::format("{}", options.coulomb.dielectric_value);
}

SurfaceProperty electrostatics(const PropertyDefinition& def, const PropertyInputs& inputs,
                               const PropertyOptions& options, PropertyReport& report) {
  const ElectrostaticsOptions& e = options.electrostatics;
  ElectrostaticsResult result =
      surface_electrostatics(*inputs.surface, *inputs.atoms, inputs.structure_file, e, options.progress);
  ElectrostaticsDetails details;
  details.method = e.method;
  details.temperature = e.temperature;
  details.offset = e.offset;
  details.dielectric = dielectric_text(e);
  details.potential_map = e.method == ElectrostaticsMethod::kPotentialMap ? e.potential_map : std::filesystem::path{};
  if (result.charges) {
    const ChargeAssignment& c = *result.charges;
    details.charges = c.source;
    details.net_charge = c.net_charge;
    details.atoms_charged = c.atoms_charged;
    details.atoms_unmatched = c.atoms_unmatched;
    details.added_atoms = c.added_atoms;
    details.added_hydrogens = c.added_hydrogens;
    if (e.method == ElectrostaticsMethod::kApbs || c.source.rfind("pdb2pqr", 0) == 0)
      details.force_field = e.force_field;
  }
  report.electrostatics = details;
  for (auto& w : result.warnings) report.warnings.push_back("electrostatics: " + w);
  return {def.info, result.source, std::move(result.potential)};
}

void check_inputs(const PropertyInputs& inputs) {
  if (inputs.surface == nullptr) throw std::invalid_argument("compute_properties: no surface");
  if (inputs.sphere && inputs.sphere->size() != inputs.surface->vertex_count())
    throw std::invalid_argument("compute_properties: the sphere has another number of vertices than the surface");
}

// The names options.only may hold: the built-in ones and the value columns.
void check_requested(const PropertyOptions& options, const std::vector<AtomValues>& columns) {
  for (const AtomValues& column : columns)
    if (find_property_definition(column.name))
      throw InputError(
          fmt::format("--values: column '{}' has the name of a built-in property; rename the column", column.name));
  if (!options.only) return;
  for (const std::string& name : *options.only) {
    const bool column =
        std::any_of(columns.begin(), columns.end(), [&](const AtomValues& c) { return c.name == name; });
    if (find_property_definition(name) || column) continue;
    std::vector<std::string> known;
    for (const auto& d : property_registry()) known.push_back(d.info.name);
    for (const auto& c : columns) known.push_back(c.name);
    throw InputError(fmt::format("--properties: no property '{}' (there are: {})", name, fmt::join(known, ", ")));
  }
}

// Reads and matches the --values files (they need a structure's atoms).
std::vector<AtomValues> value_columns(const PropertyInputs& inputs, const PropertyOptions& options) {
  std::vector<AtomValues> columns;
  for (const auto& file : options.values_files) {
    if (inputs.atoms == nullptr)
      throw InputError(
          fmt::format("--values {}: values are given per atom or residue, but the input is a mesh file "
                      "without atoms; map a structure file",
                      file.string()));
    for (AtomValues& column : match_values(read_values_file(file), *inputs.atoms)) {
      if (std::any_of(columns.begin(), columns.end(), [&](const AtomValues& c) { return c.name == column.name; }))
        throw InputError(
            fmt::format("--values {}: column '{}' is also in another values file", file.string(), column.name));
      columns.push_back(std::move(column));
    }
  }
  return columns;
}

// The structure and surface properties, registry order (map properties come from add_map_properties).
void structure_and_surface_properties(const PropertyInputs& inputs, const PropertyOptions& options, PropertySet& set) {
  using namespace property_names;
  detail::StageTimer timer("properties");
  const Mesh& surface = *inputs.surface;
  std::optional<ResidueIndex> index;
  std::vector<double> sequence;
  std::optional<PrincipalCurvatures> curvatures;
  if (inputs.atoms) {
    index = index_residues(*inputs.atoms);
    sequence = sequence_positions(*index);
  }
  const std::vector<Atom>* atoms = inputs.atoms;
  for (const PropertyDefinition& def : property_registry()) {
    const std::string& name = def.info.name;
    if (def.basis == PropertyBasis::kMap || !wanted(options, name)) continue;
    if (def.basis == PropertyBasis::kStructure && atoms == nullptr) continue;
    // b_factor and charge are there when the file has the column (or when asked for by name).
    const bool asked = options.only.has_value();
    if (name == kBFactor && !asked &&
        std::none_of(atoms->begin(), atoms->end(), [](const Atom& a) { return a.b_factor.has_value(); }))
      continue;
    if (name == kCharge && !asked &&
        std::none_of(atoms->begin(), atoms->end(), [](const Atom& a) { return a.charge.has_value(); }))
      continue;
    if (name == kElectrostatics) {
      set.properties.push_back(electrostatics(def, inputs, options, set.report));
      set.report.timings.push_back({name, timer.lap(name)});
    } else if (def.per_atom) {
      std::vector<double> per_atom = atom_values(name, *atoms, *index, sequence, set.report);
      SurfaceProperty p{def.info, "structure", per_vertex(surface, per_atom)};
      if (name == kChainIndex) p.info.categories = index->chains;
      if (name == kHydrophobicity || name == kWimleyWhite || name == kEisenberg) p.source = "residue table";
      set.properties.push_back(std::move(p));
      set.report.atom_properties.push_back({name, std::move(per_atom)});
    } else if (name == kShapeIndex || name == kCurvedness) {
      if (!curvatures) curvatures = principal_curvatures(surface.positions, surface.triangles);
      std::vector<double> values(surface.vertex_count());
      for (std::size_t v = 0; v < values.size(); ++v)
        values[v] = name == kShapeIndex ? shape_index(curvatures->k1[v], curvatures->k2[v])
                                        : curvedness(curvatures->k1[v], curvatures->k2[v]);
      set.properties.push_back({def.info, "surface curvature (Rusinkiewicz 2004)", std::move(values)});
    }
  }
  set.report.timings.push_back({"structure and shape", timer.lap("structure and shape")});
}

}  // namespace

const std::vector<PropertyDefinition>& property_registry() {
  static const std::vector<PropertyDefinition> registry = make_registry();
  return registry;
}

const PropertyDefinition* find_property_definition(std::string_view name) {
  for (const auto& d : property_registry())
    if (d.info.name == name) return &d;
  return nullptr;
}

const PropertyInfo* find_property(std::string_view name) {
  const PropertyDefinition* d = find_property_definition(name);
  return d ? &d->info : nullptr;
}

PropertySet compute_properties(const PropertyInputs& inputs, const PropertyOptions& options) {
  check_inputs(inputs);
  PropertySet set;
  std::vector<AtomValues> columns = value_columns(inputs, options);
  check_requested(options, columns);
  structure_and_surface_properties(inputs, options, set);
  for (AtomValues& column : columns) {
    if (!wanted(options, column.name)) continue;
    PropertyInfo info;
    info.name = column.name;
    info.scale = ScaleKind::sequential;
    set.properties.push_back({info, "values file", per_vertex(*inputs.surface, column.per_atom)});
    set.report.atom_properties.push_back({column.name, column.per_atom});
    if (column.rows_unmatched > 0 || column.atoms_without_value > 0)
      set.report.warnings.push_back(
          fmt::format("--values column '{}': {} of {} row(s) match no atom; {} atom(s) without "
                      "a value",
                      column.name, column.rows_unmatched, column.rows, column.atoms_without_value));
    column.per_atom.clear();  // kept in atom_properties; the report needs only the counts
    set.report.values.push_back(std::move(column));
  }
  if (inputs.sphere) add_map_properties(set, *inputs.surface, *inputs.sphere, options);
  return set;
}

void add_map_properties(PropertySet& set, const Mesh& surface, const std::vector<Vec3>& sphere,
                        const PropertyOptions& options) {
  using namespace property_names;
  if (sphere.size() != surface.vertex_count())
    throw std::invalid_argument("add_map_properties: the sphere has another number of vertices than the surface");
  detail::StageTimer timer("properties");
  // Map properties follow the other built-in ones and precede the value columns.
  auto at = std::find_if(set.properties.begin(), set.properties.end(),
                         [](const SurfaceProperty& p) { return find_property_definition(p.info.name) == nullptr; });
  std::vector<SurfaceProperty> added;
  for (const PropertyDefinition& def : property_registry()) {
    if (def.basis != PropertyBasis::kMap || !wanted(options, def.info.name)) continue;
    if (def.info.name == kAreaDistortion) {
      added.push_back({def.info, "map", vertex_log_area_ratios(surface, sphere)});
    } else if (def.info.name == kOctant) {
      std::vector<double> values(sphere.size());
      for (std::size_t v = 0; v < values.size(); ++v) values[v] = octant_of(sphere[v]);
      SurfaceProperty p{def.info, "map", std::move(values)};
      p.info.categories.assign(octant_names().begin(), octant_names().end());
      added.push_back(std::move(p));
    }
  }
  set.properties.insert(at, std::make_move_iterator(added.begin()), std::make_move_iterator(added.end()));
  set.report.timings.push_back({"map properties", timer.lap("map properties")});
}

const SurfaceProperty* colour_property(const std::vector<SurfaceProperty>& properties, const std::string& requested) {
  const auto named = [&](std::string_view name) -> const SurfaceProperty* {
    for (const auto& p : properties)
      if (p.info.name == name) return &p;
    return nullptr;
  };
  if (!requested.empty()) {
    if (const SurfaceProperty* p = named(requested)) return p;
    std::vector<std::string> names;
    for (const auto& p : properties) names.push_back(p.info.name);
    throw InputError(fmt::format("--color {}: no such property on this surface (there are: {})", requested,
                                 names.empty() ? std::string("none") : fmt::format("{}", fmt::join(names, ", "))));
  }
  for (const char* name : {property_names::kElectrostatics, property_names::kHydrophobicity, property_names::kOctant})
    if (const SurfaceProperty* p = named(name)) return p;
  return properties.empty() ? nullptr : &properties.front();
}

ValueRange colour_range(const SurfaceProperty& property) {
  if (property.info.default_range) return *property.info.default_range;
  std::vector<float> values(property.values.begin(), property.values.end());
  return data_range(property.info.scale, values);
}

}  // namespace spheremap
