// The molecular-surface stage: the SES of the atoms, the handle repair of its outer surface, and the
// components and repairs described with the residues that line them.
#include "spheremap/pipeline/molecular_surface.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <limits>
#include <optional>

#include <fmt/format.h>

#include "../util/stage_timer.hpp"
#include "detail.hpp"
#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"
#include "spheremap/repair/handle_repair.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/nearest_atoms.hpp"
#include "spheremap/surface/provenance.hpp"

namespace spheremap {

const char* to_string(SurfaceComponentKind kind) {
  constexpr const char* kNames[] = {"outer", "piece", "cavity"};  // in the order of the enum
  return kNames[static_cast<int>(kind)];
}

bool is_structure_file(const std::filesystem::path& path) {
  std::filesystem::path p = path;
  using pipeline_detail::lower;
  if (lower(p.extension().string()) == ".gz") p = p.stem();
  const auto extension = lower(p.extension().string());
  return extension == ".pdb" || extension == ".ent" || extension == ".cif" || extension == ".mmcif" ||
         extension == ".pqr";
}

namespace {

// The atoms that make the surface: those of positive radius. Atoms of radius 0 (a PQR's hydrogens) carry
// charge but make no surface; `index` maps the solid atoms back to the structure's (empty when every atom
// is solid, and `atoms` is the structure's list itself).
struct SolidAtoms {
  std::vector<Atom> list;
  std::vector<std::int32_t> index;
};

SolidAtoms solid_atoms(const std::vector<Atom>& atoms) {
  if (std::none_of(atoms.begin(), atoms.end(), [](const Atom& a) { return a.radius > 0; }))
    throw InputError(
        fmt::format("none of the {} atom(s) has a positive radius: atoms of radius 0 carry charge but make "
                    "no surface",
                    atoms.size()));
  SolidAtoms solid;
  if (std::all_of(atoms.begin(), atoms.end(), [](const Atom& a) { return a.radius > 0; })) return solid;
  for (std::size_t a = 0; a < atoms.size(); ++a) {
    if (!(atoms[a].radius > 0)) continue;
    solid.list.push_back(atoms[a]);
    solid.index.push_back(static_cast<std::int32_t>(a));
  }
  return solid;
}

// `atomid` from indices into the solid atoms to indices into the structure's.
void restore_atom_ids(Mesh& mesh, const SolidAtoms& solid) {
  if (solid.index.empty()) return;
  for (auto& id : mesh.integer_attributes.at(attributes::kAtomId)) id = solid.index[static_cast<std::size_t>(id)];
}

}  // namespace

Mesh molecular_surface(const std::filesystem::path& path, const StructureOptions& structure,
                       const SurfaceOptions& surface, StructureReport* report) {
  const Molecule molecule = read_structure(path, structure);
  if (report) *report = molecule.report;
  SolidAtoms solid;
  try {
    solid = solid_atoms(molecule.atoms);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", path.string(), e.what()));
  }
  Mesh mesh = solvent_excluded_surface(solid.index.empty() ? molecule.atoms : solid.list, surface);
  restore_atom_ids(mesh, solid);
  add_atom_provenance(mesh, molecule.atoms);
  return mesh;
}

namespace {

std::string residue_label(const Atom& atom) {
  std::string label = fmt::format("{}:{}{}", atom.chain, atom.residue_name, atom.residue_number);
  if (atom.insertion_code != ' ') label += atom.insertion_code;
  return label;
}

std::vector<std::string> sorted_unique(std::vector<std::string> labels) {
  std::sort(labels.begin(), labels.end());
  labels.erase(std::unique(labels.begin(), labels.end()), labels.end());
  return labels;
}

// The residues of the atoms nearest (smallest |x - centre| - radius) to the given grid samples.
template <typename T>
std::vector<std::string> residues_near_samples(const Grid3<T>& field, const std::vector<std::int64_t>& samples,
                                               const std::vector<Atom>& atoms, double reach) {
  Vec3 low{1e300, 1e300, 1e300}, high{-1e300, -1e300, -1e300};
  std::vector<Vec3> points;
  points.reserve(samples.size());
  for (const auto s : samples) {
    const auto [nx, ny, nz] = field.size;
    const Vec3 p = field.point(s % nx, (s / nx) % ny, s / (nx * ny));
    points.push_back(p);
    for (int d = 0; d < 3; ++d) low[d] = std::min(low[d], p[d] - reach), high[d] = std::max(high[d], p[d] + reach);
  }
  std::vector<std::int32_t> candidates;
  for (std::int32_t a = 0; a < static_cast<std::int32_t>(atoms.size()); ++a) {
    const auto& c = atoms[a].position;
    if (c[0] >= low[0] && c[0] <= high[0] && c[1] >= low[1] && c[1] <= high[1] && c[2] >= low[2] && c[2] <= high[2])
      candidates.push_back(a);
  }
  std::vector<std::string> labels;
  for (const auto& p : points) {
    double best = std::numeric_limits<double>::infinity();
    std::int32_t chosen = -1;
    for (const auto a : candidates) {
      const double gap = norm(p - atoms[a].position) - atoms[a].radius;
      if (gap < best) best = gap, chosen = a;
    }
    if (chosen >= 0) labels.push_back(residue_label(atoms[chosen]));
  }
  return sorted_unique(std::move(labels));
}

template <typename T>
ClosureReport describe_closure(const Grid3<T>& field, const Closure& closure, const std::vector<Atom>& atoms,
                               double reach) {
  const auto& samples = closure.samples;
  ClosureReport report;
  report.kind = closure.kind;
  report.area_change = closure.area_change;
  report.handles_removed = closure.handles_removed;
  report.samples = static_cast<std::int64_t>(samples.size());
  report.volume = static_cast<double>(samples.size()) * std::pow(field.spacing, 3);
  const auto [nx, ny, nz] = field.size;
  for (const auto s : samples) report.centre = report.centre + field.point(s % nx, (s / nx) % ny, s / (nx * ny));
  if (!samples.empty()) report.centre = (1.0 / static_cast<double>(samples.size())) * report.centre;
  report.lining_residues = residues_near_samples(field, samples, atoms, reach);
  return report;
}

std::vector<SurfaceComponentReport> describe_components(const Mesh& mesh, const std::vector<MeshComponent>& components,
                                                        const std::vector<Atom>& atoms) {
  constexpr std::size_t kListedResidues = 200;
  const auto& atom_of = mesh.integer_attributes.at(attributes::kAtomId);
  std::vector<SurfaceComponentReport> reports;
  for (std::size_t c = 0; c < components.size(); ++c) {
    const auto& component = components[c];
    SurfaceComponentReport report;
    report.kind = c == 0                        ? SurfaceComponentKind::kOuter
                  : component.signed_volume < 0 ? SurfaceComponentKind::kCavity
                                                : SurfaceComponentKind::kPiece;
    report.vertices = component.vertices;
    report.triangles = static_cast<std::int64_t>(component.triangles.size());
    report.area = component.area;
    report.volume = std::abs(component.signed_volume);
    report.genus = component.genus;
    std::vector<bool> has_atom(atoms.size(), false);
    for (const auto t : component.triangles)
      for (const auto v : mesh.triangles[t]) has_atom[static_cast<std::size_t>(atom_of[v])] = true;
    std::vector<std::string> labels;
    for (std::size_t a = 0; a < atoms.size(); ++a)
      if (has_atom[a]) labels.push_back(residue_label(atoms[a]));
    labels = sorted_unique(std::move(labels));
    report.residue_count = static_cast<std::int64_t>(labels.size());
    if (labels.size() > kListedResidues) labels.resize(kListedResidues);
    report.residues = std::move(labels);
    reports.push_back(std::move(report));
  }
  return reports;
}

}  // namespace

MolecularSurface repaired_surface(const std::vector<Atom>& structure_atoms, const SurfaceOptions& surface,
                                  bool keep_topology, HandleRepairReport* repair, bool full_provenance) {
  const SolidAtoms solid = solid_atoms(structure_atoms);
  const std::vector<Atom>& atoms = solid.index.empty() ? structure_atoms : solid.list;
  MolecularSurface result;
  HandleRepairReport local;
  HandleRepairReport& report = repair ? *repair : local;
  detail::StageTimer timer("surface", &result.timings);
  Mesh mesh;
  // The components of the final contour, when a step computed them already (adding provenance changes
  // neither its triangles nor its positions).
  std::optional<std::vector<MeshComponent>> final_components;
  {
    // The single-precision field (4 bytes per sample) is freed as soon as the final contour exists; the
    // repair adds a state byte and two bytes of distance per sample, counted against the memory budget.
    SurfaceOptions budgeted = surface;
    if (!keep_topology) budgeted.extra_bytes_per_sample += 3;
    Grid3<float> field = solvent_excluded_field_float(atoms, budgeted);
    timer.lap("field");
    mesh = contour_isosurface(field, 0.0, surface.threads, surface.contour_minimum_fraction);
    {
      // Scoped, and kept only when no repair follows: its triangle lists (one index per triangle) would
      // otherwise stay through the repair.
      auto before = mesh_components(mesh);
      report.genus_before = before.empty() ? 0 : before.front().genus;
      report.area_before = before.empty() ? 0 : before.front().area;
      if (keep_topology || report.genus_before == 0) final_components = std::move(before);
    }
    timer.lap("contour");
    if (!keep_topology && report.genus_before != 0) {
      mesh = Mesh{};  // the repair needs the memory; its last genus check contours the repaired field
      OuterGenusRepair fix =
          repair_outer_genus(field, 0.0, report.genus_before, surface.threads, surface.contour_minimum_fraction, mesh);
      double largest_radius = 0;
      for (const auto& a : atoms) largest_radius = std::max(largest_radius, a.radius);
      const double reach = largest_radius + surface.probe + 2 * surface.grid;
      final_components = std::move(fix.final_components);
      report.method = fix.method;
      report.rounds = fix.rounds;  // 0 unless kPerHandle
      report.samples_changed = fix.samples_changed;
      report.volume_changed = static_cast<double>(fix.samples_changed) * std::pow(surface.grid, 3);
      for (const auto& closure : fix.closures)
        report.closures.push_back(describe_closure(field, closure, atoms, reach));
      timer.lap("repair");
    }
  }
  add_nearest_atoms(mesh, atoms, surface);
  restore_atom_ids(mesh, solid);
  if (full_provenance) add_atom_provenance(mesh, structure_atoms);
  result.atoms = structure_atoms;
  timer.lap("provenance");
  result.mesh = std::move(mesh);
  result.components = final_components ? std::move(*final_components) : mesh_components(result.mesh);
  result.reports = describe_components(result.mesh, result.components, structure_atoms);
  report.area_after = result.components.empty() ? 0 : result.components.front().area;
  if (report.method == RepairMethod::kNone) report.area_before = report.area_after;
  timer.lap("components");
  return result;
}

}  // namespace spheremap
