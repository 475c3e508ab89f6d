// The map job: read (or surface a structure), prepare, simplify, map, measure, write.
#include "spheremap/pipeline/map_job.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "../util/stage_timer.hpp"
#include "detail.hpp"
#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/normals.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "spheremap/io/gltf.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/pipeline/map_tables.hpp"
#include "spheremap/pipeline/report.hpp"
#include "spheremap/properties/colour_scale.hpp"
#include "spheremap/surface/provenance.hpp"
#include "spheremap/text.hpp"

namespace spheremap {
namespace {

using namespace pipeline_detail;

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
      throw InputError(
          fmt::format("{}: --poles: vertex {} is not part of the mapped surface (unused, or in another "
                      "component); choose another vertex",
                      name, input_vertex));
    return of_input[input_vertex];
  };
  const auto [north, south] = *map.poles;
  map.poles = std::make_pair(translate(north), translate(south));
  if (map.poles->first == map.poles->second)
    throw InputError(
        fmt::format("{}: --poles {},{}: the two poles are the same vertex (after welding)", name, north, south));
  return map;
}

// The properties that need no map (structure and shape), on the prepared mesh.
void compute_surface_properties(MapJobResult& result, const MapJobOptions& options) {
  PropertyInputs inputs;
  inputs.surface = &result.prepared.mesh;
  if (result.from_structure) inputs.atoms = &result.structure_atoms;
  inputs.structure_file = result.input;
  PropertySet set = compute_properties(inputs, options.properties);
  result.properties = std::move(set.properties);
  result.property_report = std::move(set.report);
}

// The part of a job after preparation: the map, its measurements and the map properties.
void map_and_measure(MapJobResult& result, const MapJobOptions& options, const std::string& name) {
  result.map = map_to_sphere(result.prepared.mesh, map_options_for(result.prepared, options, name));
  detail::StageTimer timer("map job");
  result.metrics = measure_distortion(result.prepared.mesh, result.map.sphere);
  result.metrics_seconds = timer.lap("metrics");
  PropertySet set{std::move(result.properties), std::move(result.property_report)};
  add_map_properties(set, result.prepared.mesh, result.map.sphere, options.properties);
  result.properties = std::move(set.properties);
  result.property_report = std::move(set.report);
  result.properties_seconds = 0;
  for (const auto& t : result.property_report.timings) result.properties_seconds += t.seconds;
}

// A structure file to its analysed molecular surface; fills the structure parts of `result`.
// Returns the name used in messages.
std::string load_molecular_surface(const std::filesystem::path& input, const MapJobOptions& options,
                                   MapJobResult& result, MolecularSurface& surface) {
  result.input = input;
  detail::StageTimer timer("map job");
  const Molecule molecule = read_structure(input, options.structure);
  result.read_seconds = timer.lap("read");
  result.from_structure = true;
  result.atoms = static_cast<std::int64_t>(molecule.atoms.size());
  result.structure = molecule.report;
  try {
    surface = repaired_surface(molecule.atoms, options.surface, options.keep_topology, &result.topology, false);
  } catch (const InputError& e) {
    throw InputError(fmt::format("{}: {}", input.string(), e.what()));
  }
  result.surface_seconds = timer.lap("surface");
  result.surface_timings = surface.timings;
  result.components = surface.reports;
  result.structure_atoms = surface.atoms;
  if (surface.components.empty()) throw MeshRefused(fmt::format("{}: the molecular surface is empty", input.string()));
  return fmt::format("{} (molecular surface, probe {} Å, grid {} Å)", valid_utf8(input.string()), options.surface.probe,
                     options.surface.grid);
}

// Prepares component `chosen` of a molecular surface for mapping (flagged as mapped in the report).
// With `last_use` the surface's mesh is taken (the component made from it in place; at 0.25 Å a copy of
// 23M vertices would stand beside the simplification). Returns the component's name for messages.
std::string prepare_surface_component(MolecularSurface& surface, std::size_t chosen, const std::string& name,
                                      const MapJobOptions& options, MapJobResult& result, bool last_use) {
  if (surface.components[chosen].genus != 0) {
    throw MeshRefused(fmt::format(
        "{}: the {} surface has genus {} ({} handle(s) or tunnel(s)), but a one-to-one map onto a sphere needs "
        "genus 0{}",
        name, chosen == 0 ? "outer" : fmt::format("component {} of the", chosen), surface.components[chosen].genus,
        surface.components[chosen].genus,
        options.keep_topology ? ". --keep-topology was given: leave it out to repair the handles" : ""));
  }
  for (std::size_t c = 0; c < result.components.size(); ++c) result.components[c].mapped = c == chosen;
  result.component_index = static_cast<std::int64_t>(chosen);
  MapJobOptions named = options;
  named.prepare.source_name = chosen == 0 ? name : fmt::format("{}, component {}", name, chosen);
  named.prepare.component = ComponentChoice::refuse();
  // add_atom_provenance below writes these again from `atomid`: meanwhile they would be extracted and
  // carried through the simplification for nothing.
  for (const char* derived : {attributes::kAtomSerial, attributes::kResidueNumber, attributes::kModel})
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
    detail::StageTimer timer("map job");
    component = simplify_surface(std::move(component), options.simplify, &result.simplification);
    result.simplified = true;
    result.simplify_seconds = timer.lap("simplify");
  }
  // The text provenance of the vertices that are mapped (load_molecular_surface leaves it out).
  add_atom_provenance(component, surface.atoms);
  detail::StageTimer timer("map job");
  result.prepared = prepare_mesh(component, named.prepare);
  result.prepare_seconds = timer.lap("prepare");
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
  detail::StageTimer timer("map job");
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
  result.simplify_seconds = timer.lap("simplify");
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
    if (options.prepare.component.mode == ComponentChoice::Mode::kNumbered) {
      chosen = static_cast<std::size_t>(options.prepare.component.number);
      if (chosen >= surface.components.size())
        throw InputError(
            fmt::format("{}: --component {}: the molecular surface has {} component(s), numbered 0 to {} "
                        "by decreasing area",
                        name, chosen, surface.components.size(), surface.components.size() - 1));
    }
    return prepare_surface_component(surface, chosen, name, options, result, true);
  }
  detail::StageTimer timer("map job");
  const PolygonSoup soup = read_polygon_soup(input);
  result.read_seconds = timer.lap("read");
  MapJobOptions named = options;
  if (named.prepare.source_name == "mesh") named.prepare.source_name = input.string();
  result.prepared = prepare_mesh(soup, named.prepare);
  result.prepare_seconds = timer.lap("prepare");
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
    compute_surface_properties(result, options);
    map_and_measure(result, options, component_name);
    results.push_back(std::move(result));
  }
  return results;
}

MapJobResult run_map_job(const std::filesystem::path& input, const MapJobOptions& options) {
  MapJobResult result;
  const std::string name = load_and_prepare(input, options, result);
  compute_surface_properties(result, options);
  map_and_measure(result, options, name);
  return result;
}

std::vector<MapJobResult> run_map_jobs(const std::filesystem::path& input, const MapJobOptions& options,
                                       const std::vector<Weights>& weights) {
  if (weights.empty()) throw std::invalid_argument("run_map_jobs: no weights");
  MapJobResult loaded;
  const std::string name = load_and_prepare(input, options, loaded);
  compute_surface_properties(loaded, options);
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
  detail::StageTimer timer("map job");
  result.prepared = prepare_mesh(mesh, named.prepare);
  result.prepare_seconds = timer.lap("prepare");
  if (options.simplify_mesh_files) simplify_prepared_mesh(result, named, name);
  compute_surface_properties(result, options);
  map_and_measure(result, options, name);
  return result;
}
namespace {

// The structure's lines of summary_text: components, the handle repair (the reader's warnings: the caller's).
std::string structure_text(const MapJobResult& result) {
  std::int64_t cavities = 0, pieces = 0;
  for (const auto& c : result.components)
    cavities += c.kind == SurfaceComponentKind::kCavity, pieces += c.kind == SurfaceComponentKind::kPiece;
  const bool outer_mapped = result.components.empty() || result.components.front().mapped;
  std::string text = fmt::format(
      "  structure: {} atoms; molecular surface: outer surface, {} cavities, {} detached "
      "pieces (in report.json); the {} is mapped\n",
      result.atoms, cavities, pieces, outer_mapped ? "outer surface" : "chosen component");
  const HandleRepairReport& t = result.topology;
  if (t.method != RepairMethod::kNone) {
    std::int64_t cuts = 0, fills = 0;
    for (const auto& c : t.closures) (c.kind == ClosureKind::kCut ? cuts : fills) += 1;
    text += fmt::format(
        "  handle repair ({}): genus {} -> 0, {} handle(s) cut, {} tunnel(s) filled ({} grid "
        "samples, {:.1f} Å³), outer area {:.1f} -> {:.1f} Å² ({:+.2f}%)\n",
        to_string(t.method), t.genus_before, cuts, fills, t.samples_changed, t.volume_changed, t.area_before,
        t.area_after, 100 * (t.area_after / t.area_before - 1));
  }
  return text;
}

// The properties' line: their names, where the potential came from, and their warnings.
std::string properties_text(const MapJobResult& result) {
  if (result.properties.empty()) return {};
  std::vector<std::string> names;
  for (const auto& p : result.properties) {
    names.push_back(p.info.name);
    if (p.info.name == property_names::kElectrostatics) names.back() += " (" + p.source + ")";
  }
  std::string text = fmt::format("  properties: {}\n", fmt::join(names, ", "));
  for (const auto& warning : result.property_report.warnings) text += fmt::format("  warning: {}\n", warning);
  return text;
}

std::string simplification_text(const SimplifyReport& r) {
  return fmt::format(
      "  simplified: {} -> {} vertices (mean edge {:.3g} -> {:.3g}, smallest angle {:.1f}° -> "
      "{:.1f}°), area {:+.2f}%, every removed vertex within {:.3g} of the result\n",
      r.vertices_before, r.vertices_after, r.mean_edge_before, r.mean_edge_after, r.min_angle_before_degrees,
      r.min_angle_after_degrees, r.area_before > 0 ? 100 * (r.area_after / r.area_before - 1) : 0.0,
      r.max_vertex_distance);
}

}  // namespace

std::string summary_text(const MapJobResult& result) {
  const auto& map = result.map;
  const auto& c = map.certificate;
  const auto& m = result.metrics;
  double total_seconds = result.read_seconds + result.surface_seconds + result.simplify_seconds +
                         result.prepare_seconds + result.metrics_seconds;
  for (const auto& t : map.diagnostics.timings) total_seconds += t.seconds;
  total_seconds += result.properties_seconds;
  std::string text = fmt::format("{}: {} vertices, {} triangles\n", valid_utf8(result.input.string()),
                                 result.prepared.mesh.vertex_count(), result.prepared.mesh.triangle_count());
  if (result.from_structure) text += structure_text(result);
  if (result.simplified) text += simplification_text(result.simplification);
  const auto& repair = map.diagnostics.repair;
  text += fmt::format("  map: {}, poles {} and {} (graph distance {}), {} split edges, solver {}\n",
                      to_string(map.diagnostics.construction.method), map.poles.north, map.poles.south,
                      map.poles.graph_distance, map.diagnostics.construction.split_edges.size(),
                      to_string(map.diagnostics.solve.solver));
  if (const auto& solve = map.diagnostics.solve; solve.singular_systems > 0)
    text += fmt::format("  warning: {} linear system(s) singular (extreme geometry): {}\n", solve.singular_systems,
                        solve.uniform_weights_instead ? "the map was made with uniform weights instead"
                                                      : "the re-weighting rounds that met them were rejected");
  text += fmt::format(
      "  plain algorithm: {} folded, {} collapsed; repair: {} re-weighting rounds, {} untangling "
      "moves\n",
      repair.plain_certificate.folded, repair.plain_certificate.collapsed, repair.reweighting_rounds,
      repair.untangling_moves);
  if (map.diagnostics.fallback.ran) {
    const auto& e = map.diagnostics.fallback.embedding;
    text += fmt::format(
        "  fallback (the map above was not certified): progressive embedding, {} levels down to {} vertices, "
        "{} re-insertions, {} optimizer iterations ({} on the whole mesh, {}), {}\n",
        e.levels, e.base_vertices, e.insertions, e.optimizer_iterations, e.final_iterations,
        to_string(e.final_stop_reason), e.valid ? "valid" : "NOT VALID (doubles could not hold it)");
  }
  const auto& objective = map.diagnostics.objective;
  if (objective.objective != MapObjective::kPaper) {
    const auto& o = objective.optimization;
    const char* outcome = objective.outcome == ObjectiveOutcome::kOptimized ? "the map below"
                          : objective.outcome == ObjectiveOutcome::kResultNotCertified
                              ? "NOT CERTIFIED, the map below is the unoptimized one"
                              : "not run: the map was not certified";
    text += fmt::format("  objective {} ({}): energy {:.6g} -> {:.6g} in {} iterations ({}); {}\n",
                        to_string(objective.objective), to_string(objective.energy), o.energy_before, o.energy_after,
                        o.iterations, to_string(o.stop_reason), outcome);
  }
  text +=
      fmt::format("  certificate: {} — {} folded, {} collapsed, coverage {:.12f}, {} signs decided exactly\n",
                  c.certified() ? "CERTIFIED" : "NOT CERTIFIED", c.folded, c.collapsed, c.coverage, c.decided_exactly);
  text += fmt::format(
      "  area distortion {:.1f}% mean ({:.0f}% max), angle distortion {:.1f}° mean ({:.1f}° RMS), "
      "dilatation {:.2f} mean, octant RMS {:.1f}%\n",
      m.area_distortion_mean_percent, m.area_distortion_max_percent, m.angle_distortion_mean_degrees,
      m.angle_distortion_rms_degrees, m.dilatation_mean, m.octant_rms_deviation_percent);
  text += properties_text(result);
  text += fmt::format("  superposition RMSD {:.4g}; total {:.3f} s\n", map.superposition.rmsd, total_seconds);
  return text;
}

namespace {

// Atom provenance that atoms.csv carries instead of the PLY (text), or that a property replaces
// (vertex_residue_number, vertex_b_factor, vertex_charge become float properties).
void drop_provenance(Mesh& mesh) {
  mesh.text_attributes.clear();
  for (const char* name : {attributes::kAtomSerial, attributes::kResidueNumber, attributes::kModel})
    mesh.integer_attributes.erase(name);
  for (const char* name : {attributes::kBFactor, attributes::kCharge}) mesh.real_attributes.erase(name);
}

// Properties (float), normals (float) and colours (uchar) of the two PLY files; `ply` learns their types.
void add_property_attributes(Mesh& surface, const MapJobResult& result, const MapJobOptions& options,
                             PlyWriteOptions& ply) {
  // A mesh file's own attributes of these names give way (the map's are written instead).
  for (const char* name : {attributes::kNormalX, attributes::kNormalY, attributes::kNormalZ, attributes::kRed,
                           attributes::kGreen, attributes::kBlue}) {
    surface.real_attributes.erase(name);
    surface.integer_attributes.erase(name);
    surface.text_attributes.erase(name);
  }
  for (const auto& p : result.properties) {
    const std::string name = attributes::kPropertyPrefix + p.info.name;
    surface.real_attributes[name] = p.values;
    ply.float_attributes.insert(name);
  }
  const std::vector<Vec3> normals = vertex_normals(surface.positions, surface.triangles);
  const char* axes[] = {attributes::kNormalX, attributes::kNormalY, attributes::kNormalZ};
  for (int k = 0; k < 3; ++k) {
    auto& values = surface.real_attributes[axes[k]];
    values.resize(normals.size());
    for (std::size_t v = 0; v < normals.size(); ++v) values[v] = normals[v][static_cast<std::size_t>(k)];
    ply.float_attributes.insert(axes[k]);
  }
  const SurfaceProperty* shown = colour_property(result.properties, options.colour);
  if (shown == nullptr) return;
  const ValueRange range = colour_range(*shown);
  const char* channels[] = {attributes::kRed, attributes::kGreen, attributes::kBlue};
  for (const char* channel : channels) surface.integer_attributes[channel].resize(surface.vertex_count());
  for (std::size_t v = 0; v < surface.vertex_count(); ++v) {
    const Rgb8 c = colour_of(shown->info.scale, range, shown->values[v]);
    surface.integer_attributes[attributes::kRed][v] = c.r;
    surface.integer_attributes[attributes::kGreen][v] = c.g;
    surface.integer_attributes[attributes::kBlue][v] = c.b;
  }
  for (const char* channel : channels) ply.uchar_attributes.insert(channel);
}

// The glTF twin of a PLY output: positions, normals, the PLY's colours, every property as _<NAME>.
GlbMesh glb_mesh(const Mesh& ply, const std::vector<Vec3>& normals, const MapJobResult& result, const char* name) {
  GlbMesh glb;
  glb.name = name;
  glb.positions = ply.positions;
  glb.normals = normals;
  glb.triangles = ply.triangles;
  const auto red = ply.integer_attributes.find(attributes::kRed);
  if (red != ply.integer_attributes.end()) {
    const auto& green = ply.integer_attributes.at(attributes::kGreen);
    const auto& blue = ply.integer_attributes.at(attributes::kBlue);
    glb.colours.resize(ply.vertex_count());
    for (std::size_t v = 0; v < ply.vertex_count(); ++v)
      glb.colours[v] = {static_cast<std::uint8_t>(red->second[v]), static_cast<std::uint8_t>(green[v]),
                        static_cast<std::uint8_t>(blue[v])};
  }
  for (const auto& p : result.properties) glb.attributes.emplace_back(glb_attribute_name(p.info.name), p.values);
  return glb;
}

}  // namespace

const std::vector<std::string>& map_output_names() {
  static const std::vector<std::string> names = {kSurfaceFile, kSphereFile,   kSurfaceGlbFile, kSphereGlbFile,
                                                 kAtomsFile,   kResiduesFile, kReportFile,     kViewerFile};
  return names;
}

namespace {

// The writes of write_map_outputs: on a failure, what was written is removed again.
class OutputsWritten {
 public:
  explicit OutputsWritten(std::filesystem::path directory, bool created)
      : directory_(std::move(directory)), created_(created) {}
  OutputsWritten(const OutputsWritten&) = delete;
  OutputsWritten& operator=(const OutputsWritten&) = delete;
  ~OutputsWritten() {
    if (committed_) return;
    std::error_code ignored;
    for (const auto& file : written_) std::filesystem::remove(file, ignored);
    if (created_ && std::filesystem::is_empty(directory_, ignored)) std::filesystem::remove(directory_, ignored);
  }
  void write(const std::string& name, const std::function<void(const std::filesystem::path&)>& writer) {
    const auto path = directory_ / name;
    writer(path);
    written_.push_back(path);
  }
  void commit() { committed_ = true; }

 private:
  std::filesystem::path directory_;
  bool created_;
  bool committed_ = false;
  std::vector<std::filesystem::path> written_;
};

}  // namespace

void write_map_outputs(const std::filesystem::path& directory, const MapJobResult& result,
                       const MapJobOptions& options) {
  // Everything that can fail on the user's input (--color) fails before the folder is touched.
  PlyWriteOptions ply;
  ply.ascii = options.ascii;
  Mesh surface = result.prepared.mesh;
  if (result.from_structure) drop_provenance(surface);
  surface.real_attributes[attributes::kTheta] = result.map.theta;
  surface.real_attributes[attributes::kPhi] = result.map.phi;
  surface.integer_attributes[attributes::kInputVertex] = result.prepared.report.original_vertex;
  add_property_attributes(surface, result, options, ply);
  std::error_code error;
  const bool existed = std::filesystem::is_directory(directory, error);
  std::filesystem::create_directories(directory, error);
  if (error)
    throw InputError(fmt::format("{}: cannot create the output folder: {}", directory.string(), error.message()));
  Mesh sphere = surface;
  sphere.positions = result.map.sphere;
  OutputsWritten outputs(directory, !existed);
  outputs.write(kSurfaceFile, [&](const auto& path) { write_ply(path, surface, ply); });
  outputs.write(kSphereFile, [&](const auto& path) { write_ply(path, sphere, ply); });
  // The surface's normals from the PLY columns (rounded to float); the sphere's are its unit points.
  std::vector<Vec3> normals(surface.vertex_count());
  for (std::size_t v = 0; v < normals.size(); ++v)
    normals[v] = normalized(Vec3{surface.real_attributes.at(attributes::kNormalX)[v],
                                 surface.real_attributes.at(attributes::kNormalY)[v],
                                 surface.real_attributes.at(attributes::kNormalZ)[v]});
  outputs.write(kSurfaceGlbFile,
                [&](const auto& path) { write_glb(path, glb_mesh(surface, normals, result, "surface")); });
  outputs.write(kSphereGlbFile,
                [&](const auto& path) { write_glb(path, glb_mesh(sphere, result.map.sphere, result, "sphere")); });
  if (result.from_structure) {
    outputs.write(kAtomsFile, [&](const auto& path) { write_file_atomically(path, atoms_csv(result)); });
    outputs.write(kResiduesFile, [&](const auto& path) { write_file_atomically(path, residues_csv(result)); });
  }
  // Text from the input is valid UTF-8 already (valid_utf8); the handler keeps a stray byte from ever
  // becoming an exception here.
  const std::string report =
      make_report(result, options).dump(2, ' ', false, nlohmann::json::error_handler_t::replace) + "\n";
  outputs.write(kReportFile, [&](const auto& path) { write_file_atomically(path, report); });
  outputs.commit();
}

}  // namespace spheremap
