// atoms.csv and residues.csv of a structure's map.
#include "spheremap/pipeline/map_tables.hpp"

#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "spheremap/attributes.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/io/csv.hpp"
#include "spheremap/properties/residues.hpp"
#include "spheremap/sphere/certify.hpp"

namespace spheremap {
namespace {

std::string insertion(char code) { return code == ' ' ? std::string() : std::string(1, code); }

// Per-atom properties that repeat a column of atoms.csv (residue_number; chain_index: chain) are left out.
bool repeats_atom_column(const std::string& name) {
  return name == property_names::kResidueNumber || name == property_names::kChainIndex;
}

// residues.csv averages the properties whose mean means something: not classes (chain, octant), not the
// residue number (a column of its own).
bool averaged(const SurfaceProperty& p) {
  return p.info.scale != ScaleKind::categorical && p.info.name != property_names::kResidueNumber;
}

}  // namespace

std::string atoms_csv(const MapJobResult& result) {
  const auto& atoms = result.structure_atoms;
  const auto& columns = result.property_report.atom_properties;
  std::string text =
      "atomid,serial,model,chain,residue_number,insertion_code,residue_name,atom_name,element,x,y,z,radius";
  for (const auto& c : columns)
    if (!repeats_atom_column(c.name)) text.append(1, ',').append(csv_field(c.name));
  text += "\r\n";
  for (std::size_t a = 0; a < atoms.size(); ++a) {
    const Atom& atom = atoms[a];
    text += fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{}", a, atom.serial, atom.model, csv_field(atom.chain),
                        atom.residue_number, csv_field(insertion(atom.insertion_code)), csv_field(atom.residue_name),
                        csv_field(atom.name), csv_field(atom.element), csv_number(atom.position[0]),
                        csv_number(atom.position[1]), csv_number(atom.position[2]), csv_number(atom.radius));
    for (const auto& c : columns)
      if (!repeats_atom_column(c.name)) text.append(1, ',').append(csv_number(c.values[a]));
    text += "\r\n";
  }
  return text;
}

ResidueAreas residue_areas(const MapJobResult& result) {
  const Mesh& mesh = result.prepared.mesh;
  const ResidueIndex index = index_residues(result.structure_atoms);
  const auto& atomid = mesh.integer_attributes.at(attributes::kAtomId);
  std::vector<double> vertex_surface(mesh.vertex_count(), 0.0), vertex_sphere(mesh.vertex_count(), 0.0);
  const auto& sphere = result.map.sphere;
  for (const auto& t : mesh.triangles) {
    const double a = triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]) / 3;
    const double s = sphere.size() == mesh.vertex_count()
                         ? std::abs(signed_solid_angle(sphere[t[0]], sphere[t[1]], sphere[t[2]])) / 3
                         : 0.0;
    for (const auto v : t) vertex_surface[v] += a, vertex_sphere[v] += s;
  }
  const std::size_t residues = index.residues.size();
  ResidueAreas areas;
  areas.surface_area.assign(residues, 0.0);
  areas.sphere_area.assign(residues, 0.0);
  std::vector<std::vector<double>> weighted(result.properties.size(), std::vector<double>(residues, 0.0));
  std::vector<std::vector<double>> weight = weighted;
  // A value the same on every vertex of the residue (a residue table's) is its mean exactly, without rounding.
  std::vector<std::vector<double>> first(result.properties.size(),
                                         std::vector<double>(residues, std::numeric_limits<double>::quiet_NaN()));
  std::vector<std::vector<bool>> constant(result.properties.size(), std::vector<bool>(residues, true));
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const auto atom = atomid[v];
    if (atom < 0 || static_cast<std::size_t>(atom) >= index.residue_of_atom.size()) continue;
    const auto r = static_cast<std::size_t>(index.residue_of_atom[static_cast<std::size_t>(atom)]);
    areas.surface_area[r] += vertex_surface[v];
    areas.sphere_area[r] += vertex_sphere[v];
    for (std::size_t p = 0; p < result.properties.size(); ++p) {
      const double value = result.properties[p].values[v];
      if (std::isnan(value)) continue;
      if (std::isnan(first[p][r])) first[p][r] = value;
      constant[p][r] = constant[p][r] && value == first[p][r];
      weighted[p][r] += vertex_surface[v] * value;
      weight[p][r] += vertex_surface[v];
    }
  }
  areas.means.assign(result.properties.size(), std::vector<double>(residues, std::numeric_limits<double>::quiet_NaN()));
  for (std::size_t p = 0; p < result.properties.size(); ++p)
    for (std::size_t r = 0; r < residues; ++r)
      if (weight[p][r] > 0) areas.means[p][r] = constant[p][r] ? first[p][r] : weighted[p][r] / weight[p][r];
  return areas;
}

std::string residues_csv(const MapJobResult& result) {
  const ResidueIndex index = index_residues(result.structure_atoms);
  const ResidueAreas areas = residue_areas(result);
  std::string text = "chain,residue_number,insertion_code,residue_name,surface_area,sphere_area";
  for (const auto& p : result.properties)
    if (averaged(p)) text.append(1, ',').append(csv_field("mean_" + p.info.name));
  text += "\r\n";
  for (std::size_t r = 0; r < index.residues.size(); ++r) {
    const Residue& residue = index.residues[r];
    text += fmt::format("{},{},{},{},{},{}", csv_field(residue.chain), residue.number,
                        csv_field(insertion(residue.insertion_code)), csv_field(residue.name),
                        csv_number(areas.surface_area[r]), csv_number(areas.sphere_area[r]));
    for (std::size_t p = 0; p < result.properties.size(); ++p)
      if (averaged(result.properties[p])) text.append(1, ',').append(csv_number(areas.means[p][r]));
    text += "\r\n";
  }
  return text;
}

}  // namespace spheremap
