// The viewer's data for a mapped surface (see viewer_data.hpp).
#include "spheremap/render/viewer_data.hpp"

#include <map>
#include <stdexcept>

#include "mesh_attributes.hpp"
#include "spheremap/attributes.hpp"

namespace spheremap {
namespace {

using detail::find_attribute;

// One atom per distinct atomid, named from the first vertex that carries it.
void add_atoms(const Mesh& surface, ViewerData& data) {
  const std::vector<std::int32_t>* atom_ids = find_attribute(surface.integer_attributes, attributes::kAtomId);
  if (atom_ids == nullptr) return;
  const TextAttribute* chain = find_attribute(surface.text_attributes, attributes::kChain);
  const TextAttribute* residue = find_attribute(surface.text_attributes, attributes::kResidueName);
  const TextAttribute* insertion = find_attribute(surface.text_attributes, attributes::kInsertionCode);
  const TextAttribute* atom_name = find_attribute(surface.text_attributes, attributes::kAtomName);
  const std::vector<std::int32_t>* number = find_attribute(surface.integer_attributes, attributes::kResidueNumber);
  const auto text_of = [](const TextAttribute* a, std::size_t v) { return a ? a->at(v) : std::string(); };
  std::map<std::int32_t, std::int32_t> index_of;
  data.vertex_atoms.reserve(surface.vertex_count());
  for (std::size_t v = 0; v < surface.vertex_count(); ++v) {
    const auto [it, inserted] = index_of.try_emplace((*atom_ids)[v], static_cast<std::int32_t>(data.atoms.size()));
    if (inserted)
      data.atoms.push_back({text_of(chain, v), text_of(residue, v), number ? (*number)[v] : 0, text_of(insertion, v),
                            text_of(atom_name, v)});
    data.vertex_atoms.push_back(it->second);
  }
}

ViewerProperty octant_property(const std::vector<Vec3>& sphere) {
  ViewerProperty p{"octant", "", ScaleKind::categorical,
                   {0, 255}, {}, {"+x+y+z", "-x+y+z", "+x-y+z", "-x-y+z", "+x+y-z", "-x+y-z", "+x-y-z", "-x-y-z"}};
  p.values.reserve(sphere.size());
  // A zero coordinate counts as +, as in the octant metrics.
  for (const Vec3& s : sphere) p.values.push_back(static_cast<float>((s[0] < 0) + 2 * (s[1] < 0) + 4 * (s[2] < 0)));
  return p;
}

template <typename T>
ViewerProperty value_property(std::string name, std::string unit, ScaleKind scale, const std::vector<T>& source) {
  ViewerProperty p{std::move(name), std::move(unit), scale, {}, {}, {}};
  p.values.assign(source.begin(), source.end());
  p.range = data_range(scale, p.values);
  return p;
}

void add_properties(const Mesh& surface, const std::vector<Vec3>& sphere, ViewerData& data) {
  data.properties.push_back(octant_property(sphere));
  if (const TextAttribute* chain = find_attribute(surface.text_attributes, attributes::kChain)) {
    ViewerProperty p = value_property("chain", "", ScaleKind::categorical, chain->codes);
    p.categories = chain->dictionary;
    data.properties.push_back(std::move(p));
  }
  if (const auto* number = find_attribute(surface.integer_attributes, attributes::kResidueNumber))
    data.properties.push_back(value_property("residue number", "", ScaleKind::sequential, *number));
  if (const auto* b = find_attribute(surface.real_attributes, attributes::kBFactor))
    data.properties.push_back(value_property("B-factor", "Å²", ScaleKind::sequential, *b));
  if (const auto* charge = find_attribute(surface.real_attributes, attributes::kCharge))
    data.properties.push_back(value_property("charge", "e", ScaleKind::diverging, *charge));
}

}  // namespace

namespace {

// The viewer's data without properties: the sizes checked, the geometry and the atoms.
ViewerData viewer_geometry(const Mesh& surface, const std::vector<Vec3>& sphere, std::string title) {
  if (sphere.size() != surface.vertex_count())
    throw std::invalid_argument("viewer_data_for_map: " + std::to_string(sphere.size()) + " sphere points for " +
                                std::to_string(surface.vertex_count()) + " surface vertices");
  ViewerData data;
  data.title = std::move(title);
  data.surface_positions = surface.positions;
  data.sphere_positions = sphere;
  data.triangles = surface.triangles;
  add_atoms(surface, data);
  return data;
}

}  // namespace

ViewerData viewer_data_for_map(const Mesh& surface, const std::vector<Vec3>& sphere, std::string title) {
  ViewerData data = viewer_geometry(surface, sphere, std::move(title));
  add_properties(surface, sphere, data);
  return data;
}

ViewerData viewer_data_for_map(const Mesh& surface, const std::vector<Vec3>& sphere, std::string title,
                               const std::vector<SurfaceProperty>& properties) {
  ViewerData data = viewer_geometry(surface, sphere, std::move(title));
  for (const SurfaceProperty& property : properties) {
    if (property.values.size() != surface.vertex_count())
      throw std::invalid_argument("viewer_data_for_map: property " + property.info.name + " has " +
                                  std::to_string(property.values.size()) + " values");
    ViewerProperty p{property.info.name, property.info.unit, property.info.scale, {}, {}, property.info.categories};
    p.values.assign(property.values.begin(), property.values.end());
    p.range = property.info.scale == ScaleKind::categorical ? ValueRange{0, 255}
              : property.info.default_range                 ? *property.info.default_range
                                                            : data_range(property.info.scale, p.values);
    data.properties.push_back(std::move(p));
  }
  return data;
}

}  // namespace spheremap
