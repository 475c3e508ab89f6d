#include "spheremap/pipeline/map_job.hpp"

#include <algorithm>
#include <cctype>
#include <chrono>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/handles.hpp"
#include "spheremap/surface/provenance.hpp"

namespace spheremap {
namespace {

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

nlohmann::json certificate_json(const Certificate& c) {
  static constexpr std::size_t kListed = 1000;  // the report lists at most this many bad triangles of each kind
  auto head = [](const std::vector<std::int32_t>& v) {
    return std::vector<std::int32_t>(v.begin(), v.begin() + static_cast<std::ptrdiff_t>(std::min(v.size(), kListed)));
  };
  return {{"certified", c.certified()},
          {"triangles", c.triangle_count},
          {"folded", c.folded},
          {"collapsed", c.collapsed},
          {"decided_exactly", c.decided_exactly},
          {"total_solid_angle", c.total_solid_angle},
          {"coverage", c.coverage},
          {"min_area_ratio", c.min_area_ratio},
          {"collapse_floor", c.collapse_floor},
          {"folded_triangles", head(c.folded_triangles)},
          {"collapsed_triangles", head(c.collapsed_triangles)}};
}

// Poles are given as indices in the input file; the map wants indices in the prepared mesh.
MapOptions map_options_for(const PreparedMesh& prepared, const MapJobOptions& options, const std::string& name) {
  MapOptions map = options.map;
  if (!map.poles) return map;
  const auto& of_input = prepared.report.vertex_of_input;
  auto translate = [&](std::int32_t input_vertex) {
    if (input_vertex < 0 || input_vertex >= static_cast<std::int32_t>(of_input.size()))
      throw InputError(fmt::format("{}: --poles: vertex {} does not exist (the file has vertices 0 to {})", name,
                                   input_vertex, static_cast<std::int64_t>(of_input.size()) - 1));
    if (of_input[input_vertex] < 0)
      throw InputError(fmt::format("{}: --poles: vertex {} is not part of the mapped surface (unused, or in another "
                                   "component); choose another vertex",
                                   name, input_vertex));
    return of_input[input_vertex];
  };
  const auto [north, south] = *map.poles;
  map.poles = std::make_pair(translate(north), translate(south));
  if (map.poles->first == map.poles->second)
    throw InputError(fmt::format("{}: --poles {},{}: the two poles are the same vertex (after welding)", name, north, south));
  return map;
}

}  // namespace

namespace {

// The part of a job after preparation: the map and its measurements.
void map_and_measure(MapJobResult& result, const MapJobOptions& options, const std::string& name) {
  result.map = map_to_sphere(result.prepared.mesh, map_options_for(result.prepared, options, name));
  const auto metrics_start = std::chrono::steady_clock::now();
  result.metrics = measure_distortion(result.prepared.mesh, result.map.sphere);
  result.metrics_seconds = seconds_since(metrics_start);
}

}  // namespace

bool is_structure_file(const std::filesystem::path& path) {
  std::filesystem::path p = path;
  auto lower = [](std::string text) {
    std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
    return text;
  };
  if (lower(p.extension().string()) == ".gz") p = p.stem();
  const auto extension = lower(p.extension().string());
  return extension == ".pdb" || extension == ".ent" || extension == ".cif" || extension == ".mmcif" || extension == ".pqr";
}

Mesh molecular_surface(const std::filesystem::path& path, const StructureOptions& structure,
                       const SurfaceOptions& surface, StructureReport* report) {
  const Molecule molecule = read_structure(path, structure);
  if (report) *report = molecule.report;
  Mesh mesh = solvent_excluded_surface(molecule.atoms, surface);
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
HandleChangeReport describe_change(const Grid3<T>& field, bool filled, const std::vector<std::int64_t>& samples,
                                   double area_change, int handles_removed, const std::vector<Atom>& atoms, double reach) {
  HandleChangeReport change;
  change.kind = filled ? "fill" : "cut";
  change.area_change = area_change;
  change.handles_removed = handles_removed;
  change.samples = static_cast<std::int64_t>(samples.size());
  change.volume = static_cast<double>(samples.size()) * std::pow(field.spacing, 3);
  const auto [nx, ny, nz] = field.size;
  for (const auto s : samples) change.centre = change.centre + field.point(s % nx, (s / nx) % ny, s / (nx * ny));
  if (!samples.empty()) change.centre = (1.0 / static_cast<double>(samples.size())) * change.centre;
  change.lining_residues = residues_near_samples(field, samples, atoms, reach);
  return change;
}

std::vector<SurfaceComponentReport> describe_components(const Mesh& mesh, const std::vector<MeshComponent>& components,
                                                        const std::vector<Atom>& atoms) {
  constexpr std::size_t kListedResidues = 200;
  const auto& atom_of = mesh.integer_attributes.at("atomid");
  std::vector<SurfaceComponentReport> reports;
  for (std::size_t c = 0; c < components.size(); ++c) {
    const auto& component = components[c];
    SurfaceComponentReport report;
    report.kind = c == 0 ? "outer" : component.signed_volume < 0 ? "cavity" : "piece";
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

MolecularSurface repaired_surface(const std::vector<Atom>& atoms, const SurfaceOptions& surface, bool keep_topology,
                                  TopologyRepair* repair, bool full_provenance) {
  MolecularSurface result;
  TopologyRepair local;
  TopologyRepair& report = repair ? *repair : local;
  auto stage_start = std::chrono::steady_clock::now();
  auto lap = [&](const char* stage) {
    result.timings.push_back({stage, seconds_since(stage_start)});
    stage_start = std::chrono::steady_clock::now();
  };
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
    lap("field");
    mesh = contour_isosurface(field, 0.0, surface.threads, surface.contour_minimum_fraction);
    {
      // Scoped, and kept only when no repair follows: its triangle lists (one index per triangle) would
      // otherwise stay through the repair.
      auto before = mesh_components(mesh);
      report.genus_before = before.empty() ? 0 : before.front().genus;
      report.area_before = before.empty() ? 0 : before.front().area;
      if (keep_topology || report.genus_before == 0) final_components = std::move(before);
    }
    lap("contour");
    if (!keep_topology && report.genus_before != 0) {
      mesh = Mesh{};  // the repair needs the memory; its last genus check contours the repaired field
      GenusRepair fix =
          repair_outer_genus(field, 0.0, report.genus_before, surface.threads, surface.contour_minimum_fraction, mesh);
      double largest_radius = 0;
      for (const auto& a : atoms) largest_radius = std::max(largest_radius, a.radius);
      const double reach = largest_radius + surface.probe + 2 * surface.grid;
      final_components = std::move(fix.final_components);
      report.method = fix.method;
      report.rounds = fix.rounds;  // 0 unless "per-handle"
      report.samples_changed = fix.samples_changed;
      report.volume_changed = static_cast<double>(fix.samples_changed) * std::pow(surface.grid, 3);
      for (const auto& change : fix.per_handle.changes)
        report.changes.push_back(
            describe_change(field, change.filled, change.samples, change.area_change, change.euler_change, atoms, reach));
      if (!fix.global.removed_samples.empty())
        report.changes.push_back(describe_change(field, fix.global.filled, fix.global.removed_samples, fix.global.area_change,
                                                 report.genus_before, atoms, reach));
      lap("repair");
    }
  }
  add_nearest_atoms(mesh, atoms, surface);
  if (full_provenance) add_atom_provenance(mesh, atoms);
  result.atoms = atoms;
  lap("provenance");
  result.mesh = std::move(mesh);
  result.components = final_components ? std::move(*final_components) : mesh_components(result.mesh);
  result.reports = describe_components(result.mesh, result.components, atoms);
  report.area_after = result.components.empty() ? 0 : result.components.front().area;
  if (report.method == "none") report.area_before = report.area_after;
  lap("components");
  return result;
}

namespace {

// A structure file to its analysed molecular surface; fills the structure parts of `result`.
// Returns the name used in messages.
std::string load_molecular_surface(const std::filesystem::path& input, const MapJobOptions& options,
                                   MapJobResult& result, MolecularSurface& surface) {
  result.input = input;
  const auto start = std::chrono::steady_clock::now();
  const Molecule molecule = read_structure(input, options.structure);
  result.read_seconds = seconds_since(start);
  result.from_structure = true;
  result.atoms = static_cast<std::int64_t>(molecule.atoms.size());
  result.structure = molecule.report;
  const auto surface_start = std::chrono::steady_clock::now();
  try {
    surface = repaired_surface(molecule.atoms, options.surface, options.keep_topology, &result.topology, false);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", input.string(), e.what()));
  }
  result.surface_seconds = seconds_since(surface_start);
  result.surface_timings = surface.timings;
  result.components = surface.reports;
  if (surface.components.empty())
    throw MeshRefused(fmt::format("{}: the molecular surface is empty", input.string()));
  return fmt::format("{} (molecular surface, probe {} Å, grid {} Å)", input.string(), options.surface.probe,
                     options.surface.grid);
}

// Prepares component `chosen` of a molecular surface for mapping (flagged as mapped in the report).
// With `last_use` the surface's mesh is taken (the component made from it in place; at 0.25 Å a copy of
// 23M vertices would stand beside the simplification). Returns the component's name for messages.
std::string prepare_surface_component(MolecularSurface& surface, std::size_t chosen, const std::string& name,
                                      const MapJobOptions& options, MapJobResult& result, bool last_use) {
  if (surface.components[chosen].genus != 0) {
    throw MeshRefused(fmt::format(
        "{}: the {} surface has genus {} ({} handle(s) or tunnel(s)), but a one-to-one map onto a sphere needs genus 0{}",
        name, chosen == 0 ? "outer" : fmt::format("component {} of the", chosen), surface.components[chosen].genus,
        surface.components[chosen].genus,
        options.keep_topology ? ". --keep-topology was given: leave it out to repair the handles" : ""));
  }
  for (std::size_t c = 0; c < result.components.size(); ++c) result.components[c].mapped = c == chosen;
  result.component_index = static_cast<std::int64_t>(chosen);
  MapJobOptions named = options;
  named.prepare.source_name = chosen == 0 ? name : fmt::format("{}, component {}", name, chosen);
  named.prepare.component = kComponentRefuse;
  // add_atom_provenance below writes these again from `atomid`: meanwhile they would be extracted and
  // carried through the simplification for nothing.
  for (const char* derived : {"vertex_atom_serial", "vertex_residue_number", "vertex_model"})
    surface.mesh.integer_attributes.erase(derived);
  Mesh component;
  if (surface.components.size() == 1) {
    component = std::move(surface.mesh);  // nothing else needs it
  } else if (last_use) {
    component = extract_component(std::move(surface.mesh), surface.components[chosen]);
    surface.components = {};
  } else {
    component = extract_component(surface.mesh, surface.components[chosen]);
  }
  if (options.simplify.target_edge_length > 0) {
    const auto simplify_start = std::chrono::steady_clock::now();
    component = simplify_surface(std::move(component), options.simplify, &result.simplification);
    result.simplified = true;
    result.simplify_seconds = seconds_since(simplify_start);
  }
  // The text provenance of the vertices that are mapped (load_molecular_surface leaves it out).
  add_atom_provenance(component, surface.atoms);
  const auto prepare_start = std::chrono::steady_clock::now();
  result.prepared = prepare_mesh(component, named.prepare);
  result.prepare_seconds = seconds_since(prepare_start);
  return named.prepare.source_name;
}

// Simplifies a prepared mesh file's mesh (options.simplify), keeping user-given poles; the prepare report's
// vertex correspondences then refer to the simplified mesh.
void simplify_prepared_mesh(MapJobResult& result, const MapJobOptions& options, const std::string& name) {
  if (!(options.simplify.target_edge_length > 0)) return;
  SimplifyOptions simplify = options.simplify;
  if (options.map.poles) {
    const auto poles = *map_options_for(result.prepared, options, name).poles;
    simplify.kept_vertices.insert(simplify.kept_vertices.end(), {poles.first, poles.second});
  }
  const auto start = std::chrono::steady_clock::now();
  auto& prepared = result.prepared;
  prepared.mesh = simplify_surface(std::move(prepared.mesh), simplify, &result.simplification);
  const auto& kept = result.simplification.kept_vertex;
  std::vector<std::int32_t> new_index(prepared.report.original_vertex.size(), -1), original(kept.size());
  for (std::size_t i = 0; i < kept.size(); ++i) {
    new_index[static_cast<std::size_t>(kept[i])] = static_cast<std::int32_t>(i);
    original[i] = prepared.report.original_vertex[static_cast<std::size_t>(kept[i])];
  }
  prepared.report.original_vertex = std::move(original);
  for (auto& v : prepared.report.vertex_of_input)
    if (v >= 0) v = new_index[static_cast<std::size_t>(v)];
  result.simplified = true;
  result.simplify_seconds = seconds_since(start);
}

// Everything before the map: read (and for structures, the surface and its repair), then prepare.
// Returns the name used in messages.
std::string load_and_prepare(const std::filesystem::path& input, const MapJobOptions& options, MapJobResult& result) {
  result.input = input;
  if (is_structure_file(input)) {
    MolecularSurface surface;
    const std::string name = load_molecular_surface(input, options, result, surface);
    // The outer surface is the largest piece; cavities and detached pieces are reported, not mapped.
    std::size_t chosen = 0;
    if (options.prepare.component >= 0) {
      chosen = static_cast<std::size_t>(options.prepare.component);
      if (chosen >= surface.components.size())
        throw InputError(fmt::format("{}: --component {}: the molecular surface has {} component(s), numbered 0 to {} "
                                     "by decreasing area",
                                     name, chosen, surface.components.size(), surface.components.size() - 1));
    }
    return prepare_surface_component(surface, chosen, name, options, result, true);
  }
  const auto start = std::chrono::steady_clock::now();
  const PolygonSoup soup = read_polygon_soup(input);
  result.read_seconds = seconds_since(start);
  MapJobOptions named = options;
  if (named.prepare.source_name == "mesh") named.prepare.source_name = input.string();
  const auto prepare_start = std::chrono::steady_clock::now();
  result.prepared = prepare_mesh(soup, named.prepare);
  result.prepare_seconds = seconds_since(prepare_start);
  if (options.simplify_mesh_files) simplify_prepared_mesh(result, options, named.prepare.source_name);
  return named.prepare.source_name;
}

}  // namespace

std::vector<MapJobResult> run_map_job_components(const std::filesystem::path& input, const MapJobOptions& options) {
  if (!is_structure_file(input))
    throw InputError(fmt::format("{}: --components all is for structure files (a mesh's components: --component N)",
                                 input.string()));
  MapJobResult base;
  MolecularSurface surface;
  const std::string name = load_molecular_surface(input, options, base, surface);
  std::vector<MapJobResult> results;
  for (std::size_t c = 0; c < surface.components.size(); ++c) {
    if (surface.components[c].genus != 0) continue;  // reported in the components list, never mapped
    MapJobResult result = base;
    const std::string component_name = prepare_surface_component(surface, c, name, options, result, false);
    map_and_measure(result, options, component_name);
    results.push_back(std::move(result));
  }
  return results;
}

MapJobResult run_map_job(const std::filesystem::path& input, const MapJobOptions& options) {
  MapJobResult result;
  const std::string name = load_and_prepare(input, options, result);
  map_and_measure(result, options, name);
  return result;
}

std::vector<MapJobResult> run_map_jobs(const std::filesystem::path& input, const MapJobOptions& options,
                                       const std::vector<Weights>& weights) {
  if (weights.empty()) throw std::invalid_argument("run_map_jobs: no weights");
  MapJobResult loaded;
  const std::string name = load_and_prepare(input, options, loaded);
  std::vector<MapJobResult> results;
  results.reserve(weights.size());
  for (std::size_t k = 0; k < weights.size(); ++k) {
    MapJobResult result = k + 1 < weights.size() ? loaded : std::move(loaded);
    MapJobOptions weighted = options;
    weighted.map.weights = weights[k];
    map_and_measure(result, weighted, name);
    results.push_back(std::move(result));
  }
  return results;
}

MapJobResult run_map_job(const Mesh& mesh, const std::string& name, const MapJobOptions& options) {
  MapJobOptions named = options;
  named.prepare.source_name = name;
  MapJobResult result;
  result.input = name;
  const auto prepare_start = std::chrono::steady_clock::now();
  result.prepared = prepare_mesh(mesh, named.prepare);
  result.prepare_seconds = seconds_since(prepare_start);
  if (options.simplify_mesh_files) simplify_prepared_mesh(result, named, name);
  map_and_measure(result, options, name);
  return result;
}

namespace {

nlohmann::json changes_json(const std::vector<HandleChangeReport>& changes) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : changes)
    list.push_back({{"kind", c.kind},
                    {"samples", c.samples},
                    {"volume", c.volume},
                    {"area_change", c.area_change},
                    {"handles_removed", c.handles_removed},
                    {"centre", std::vector<double>(c.centre.begin(), c.centre.end())},
                    {"lining_residues", c.lining_residues}});
  return list;
}

nlohmann::json components_json(const std::vector<SurfaceComponentReport>& components) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : components)
    list.push_back({{"kind", c.kind},
                    {"mapped", c.mapped},
                    {"vertices", c.vertices},
                    {"triangles", c.triangles},
                    {"area", c.area},
                    {"volume", c.volume},
                    {"genus", c.genus},
                    {"residue_count", c.residue_count},
                    {"residues", c.residues}});
  return list;
}

nlohmann::json simplification_json(const MapJobResult& result, const MapJobOptions& options) {
  if (!result.simplified) return nullptr;
  const auto& r = result.simplification;
  return {{"target_edge_length", options.simplify.target_edge_length},
          {"max_error", options.simplify.max_error},
          {"min_angle_degrees", options.simplify.min_angle_degrees},
          {"max_normal_change_degrees", options.simplify.max_normal_change_degrees},
          {"vertices_before", r.vertices_before},
          {"vertices_after", r.vertices_after},
          {"triangles_before", r.triangles_before},
          {"triangles_after", r.triangles_after},
          {"collapses", r.collapses},
          {"flips", r.flips},
          {"rounds", r.rounds},
          {"area_before", r.area_before},
          {"area_after", r.area_after},
          {"mean_edge_before", r.mean_edge_before},
          {"mean_edge_after", r.mean_edge_after},
          {"min_angle_before_degrees", r.min_angle_before_degrees},
          {"min_angle_after_degrees", r.min_angle_after_degrees},
          {"max_vertex_distance", r.max_vertex_distance}};
}

}  // namespace

nlohmann::json make_report(const MapJobResult& result, const MapJobOptions& options) {
  const auto& map = result.map;
  const auto& prep = result.prepared.report;
  const auto& m = result.metrics;
  nlohmann::json timings = nlohmann::json::object();
  timings["read"] = result.read_seconds;
  if (result.from_structure) timings["surface"] = result.surface_seconds;
  if (result.from_structure) {
    // The parts of "surface", nested so that a sum over the stages counts each second once.
    nlohmann::json parts = nlohmann::json::object();
    for (const auto& t : result.surface_timings) parts[t.stage] = t.seconds;
    timings["surface_stages"] = parts;
  }
  if (result.simplified) timings["simplify"] = result.simplify_seconds;
  timings["prepare"] = result.prepare_seconds;
  for (const auto& t : map.timings) timings[t.stage] = t.seconds;
  timings["metrics"] = result.metrics_seconds;
  nlohmann::json splits = nlohmann::json::array();
  for (const auto& s : map.split_edges)
    splits.push_back({{"a", s.a}, {"b", s.b}, {"ring", std::string(1, s.pole)}});
  const auto& r = map.superposition.rotation;
  return {
      {"spheremap_version", "0.1.0"},
      {"input", result.input.string()},
      {"options",
       {{"weights", to_string(options.map.weights)},
        {"solver", to_string(options.map.solver)},
        {"repair", options.map.repair},
        {"collapse_floor", options.map.collapse_floor},
        {"max_equalizing_rounds", options.map.max_equalizing_rounds},
        {"weld_tolerance", options.prepare.weld_tolerance},
        {"poles_given", map.poles_from_options}}},
      {"structure",
       result.from_structure
           ? nlohmann::json{{"atoms", result.atoms},
                            {"probe", options.surface.probe},
                            {"carve_cavities", options.surface.carve_cavities},
                            {"contour_minimum_fraction", options.surface.contour_minimum_fraction},
                            {"grid", options.surface.grid},
                            {"models_in_file", result.structure.models_in_file},
                            {"atoms_in_model", result.structure.atoms_in_model},
                            {"hydrogens_removed", result.structure.hydrogens_removed},
                            {"waters_removed", result.structure.waters_removed},
                            {"hetero_removed", result.structure.hetero_removed},
                            {"other_chains_removed", result.structure.other_chains_removed},
                            {"alternate_locations_removed", result.structure.alternate_locations_removed},
                            {"warnings", result.structure.warnings},
                            {"topology_repair",
                             {{"method", result.topology.method},
                              {"rounds", result.topology.rounds},
                              {"samples_changed", result.topology.samples_changed},
                              {"volume_changed", result.topology.volume_changed},
                              {"area_before", result.topology.area_before},
                              {"area_after", result.topology.area_after},
                              {"area_changed_percent", result.topology.area_before > 0 ? 100 * (result.topology.area_after / result.topology.area_before - 1) : 0.0},
                              {"genus_before", result.topology.genus_before},
                              {"changes", changes_json(result.topology.changes)}}},
                            {"components", components_json(result.components)},
                            {"component_mapped", result.component_index}}
           : nlohmann::json(nullptr)},
      {"simplification", simplification_json(result, options)},
      {"mesh",
       {{"vertices", result.prepared.mesh.vertex_count()},
        {"triangles", result.prepared.mesh.triangle_count()},
        {"input_vertices", prep.input_vertices},
        {"input_faces", prep.input_faces},
        {"polygons_triangulated", prep.polygons_triangulated},
        {"vertices_welded", prep.vertices_welded},
        {"unreferenced_vertices_dropped", prep.unreferenced_vertices},
        {"degenerate_faces_dropped", prep.degenerate_faces_dropped},
        {"duplicate_faces_dropped", prep.duplicate_faces_dropped},
        {"components", prep.components},
        {"component_kept", prep.component_kept},
        {"triangles_reoriented", prep.triangles_flipped},
        {"genus", prep.genus}}},
      {"map",
       {{"method", map.method},
        {"refinement_levels", map.refinement_levels},
        {"north_pole", map.north},
        {"south_pole", map.south},
        {"pole_graph_distance", map.pole_graph_distance},
        {"theta0", map.theta0},
        {"mercator_c", map.mercator_c},
        {"ring_z", map.ring_z},
        {"north_ring_size", map.north_ring_size},
        {"south_ring_size", map.south_ring_size},
        {"split_edges", splits},
        {"meridian_length", map.meridian.size()},
        {"meridian_method", map.meridian_method},
        {"meridian_round", map.meridian_round},
        {"solver", map.solver_used},
        {"elimination_order", map.elimination_order},
        {"gauss_seidel_sweeps", map.gauss_seidel_sweeps},
        {"gauss_seidel_converged", map.gauss_seidel_converged},
        {"weight_fallback_rows", map.weight_fallback_rows},
        {"reweighting_rounds", map.reweighting_rounds},
        {"equalizing_rounds", map.equalizing_rounds},
        {"untangling_moves", map.untangling_moves},
        {"superposition_rotation", std::vector<double>(r.begin(), r.end())},
        {"superposition_rmsd", map.superposition.rmsd},
        {"superposition_scale", map.superposition.scale}}},
      {"certificate", certificate_json(map.certificate)},
      {"plain_algorithm_certificate", certificate_json(map.plain_certificate)},
      {"distortion",
       {{"area_distortion_mean_percent", m.area_distortion_mean_percent},
        {"area_distortion_max_percent", m.area_distortion_max_percent},
        {"area_log_ratio_mean", m.area_log_ratio_mean},
        {"angle_distortion_mean_degrees", m.angle_distortion_mean_degrees},
        {"angle_distortion_rms_degrees", m.angle_distortion_rms_degrees},
        {"angle_distortion_max_degrees", m.angle_distortion_max_degrees},
        {"dilatation_mean", m.dilatation_mean},
        {"dilatation_max", m.dilatation_max},
        {"octant_area_percent", std::vector<double>(m.octant_area_percent.begin(), m.octant_area_percent.end())},
        {"octant_rms_deviation_percent", m.octant_rms_deviation_percent}}},
      {"timings_seconds", timings},
  };
}

std::string summary_text(const MapJobResult& result) {
  const auto& map = result.map;
  const auto& c = map.certificate;
  const auto& m = result.metrics;
  double total_seconds = result.read_seconds + result.surface_seconds + result.simplify_seconds +
                         result.prepare_seconds + result.metrics_seconds;
  for (const auto& t : map.timings) total_seconds += t.seconds;
  std::string text = fmt::format("{}: {} vertices, {} triangles\n", result.input.string(),
                                 result.prepared.mesh.vertex_count(), result.prepared.mesh.triangle_count());
  if (result.from_structure) {
    std::int64_t cavities = 0, pieces = 0;
    for (const auto& c : result.components) cavities += c.kind == "cavity", pieces += c.kind == "piece";
    text += fmt::format("  structure: {} atoms; molecular surface: outer surface, {} cavities, {} detached pieces "
                        "(in report.json); the {} is mapped\n",
                        result.atoms, cavities, pieces,
                        result.components.empty() || result.components.front().mapped ? "outer surface" : "chosen component");
    if (result.topology.method != "none") {
      std::int64_t cuts = 0, fills = 0;
      for (const auto& c : result.topology.changes) (c.kind == "cut" ? cuts : fills) += 1;
      text += fmt::format("  handle repair ({}): genus {} -> 0, {} handle(s) cut, {} tunnel(s) filled ({} grid samples, "
                          "{:.1f} Å³), outer area {:.1f} -> {:.1f} Å² ({:+.2f}%)\n",
                          result.topology.method, result.topology.genus_before, cuts, fills,
                          result.topology.samples_changed, result.topology.volume_changed, result.topology.area_before,
                          result.topology.area_after, 100 * (result.topology.area_after / result.topology.area_before - 1));
    }
    for (const auto& warning : result.structure.warnings) text += fmt::format("  warning: {}\n", warning);
  }
  if (result.simplified) {
    const auto& r = result.simplification;
    text += fmt::format("  simplified: {} -> {} vertices (mean edge {:.3g} -> {:.3g}, smallest angle {:.1f}° -> {:.1f}°), "
                        "area {:+.2f}%, every removed vertex within {:.3g} of the result\n",
                        r.vertices_before, r.vertices_after, r.mean_edge_before, r.mean_edge_after,
                        r.min_angle_before_degrees, r.min_angle_after_degrees,
                        r.area_before > 0 ? 100 * (r.area_after / r.area_before - 1) : 0.0, r.max_vertex_distance);
  }
  text += fmt::format("  map: {}, poles {} and {} (graph distance {}), {} split edges, solver {}\n", map.method,
                      map.north, map.south, map.pole_graph_distance, map.split_edges.size(), map.solver_used);
  text += fmt::format("  plain algorithm: {} folded, {} collapsed; repair: {} re-weighting rounds, {} untangling moves\n",
                      map.plain_certificate.folded, map.plain_certificate.collapsed, map.reweighting_rounds,
                      map.untangling_moves);
  text += fmt::format("  certificate: {} — {} folded, {} collapsed, coverage {:.12f}, {} signs decided exactly\n",
                      c.certified() ? "CERTIFIED" : "NOT CERTIFIED", c.folded, c.collapsed, c.coverage,
                      c.decided_exactly);
  text += fmt::format("  area distortion {:.1f}% mean ({:.0f}% max), angle distortion {:.1f}° mean ({:.1f}° RMS), "
                      "dilatation {:.2f} mean, octant RMS {:.1f}%\n",
                      m.area_distortion_mean_percent, m.area_distortion_max_percent, m.angle_distortion_mean_degrees,
                      m.angle_distortion_rms_degrees, m.dilatation_mean, m.octant_rms_deviation_percent);
  text += fmt::format("  superposition RMSD {:.4g}; total {:.3f} s\n", map.superposition.rmsd, total_seconds);
  return text;
}

void write_map_outputs(const std::filesystem::path& directory, const MapJobResult& result,
                       const MapJobOptions& options) {
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (error)
    throw InputError(fmt::format("{}: cannot create the output folder: {}", directory.string(), error.message()));
  Mesh surface = result.prepared.mesh;
  surface.real_attributes["theta"] = result.map.theta;
  surface.real_attributes["phi"] = result.map.phi;
  surface.integer_attributes["input_vertex"] = result.prepared.report.original_vertex;
  Mesh sphere = surface;
  sphere.positions = result.map.sphere;
  const PlyWriteOptions ply{options.ascii};
  write_ply(directory / "surface.ply", surface, ply);
  write_ply(directory / "sphere.ply", sphere, ply);
  write_file_atomically(directory / "report.json", make_report(result, options).dump(2) + "\n");
}

}  // namespace spheremap
