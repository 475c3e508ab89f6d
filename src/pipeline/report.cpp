// make_report writes report.json's keys and read_report reads them back: the schema in one file.
#include "spheremap/pipeline/report.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/text.hpp"

namespace spheremap {
namespace {

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

nlohmann::json closures_json(const std::vector<ClosureReport>& closures) {
  nlohmann::json list = nlohmann::json::array();
  for (const auto& c : closures)
    list.push_back({{"kind", to_string(c.kind)},
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
    list.push_back({{"kind", to_string(c.kind)},
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

nlohmann::json timings_json(const MapJobResult& result) {
  nlohmann::json timings = nlohmann::json::object();
  timings["read"] = result.read_seconds;
  if (result.from_structure) {
    timings["surface"] = result.surface_seconds;
    // The parts of "surface", nested so that a sum over the stages counts each second once.
    nlohmann::json parts = nlohmann::json::object();
    for (const auto& t : result.surface_timings) parts[t.stage] = t.seconds;
    timings["surface_stages"] = parts;
  }
  if (result.simplified) timings["simplify"] = result.simplify_seconds;
  timings["prepare"] = result.prepare_seconds;
  for (const auto& t : result.map.diagnostics.timings) timings[t.stage] = t.seconds;
  timings["metrics"] = result.metrics_seconds;
  timings["properties"] = result.properties_seconds;
  nlohmann::json parts = nlohmann::json::object();
  for (const auto& t : result.property_report.timings) parts[t.stage] = t.seconds;
  timings["property_stages"] = parts;
  return timings;
}

std::string method_name(ElectrostaticsMethod method) {
  switch (method) {
    case ElectrostaticsMethod::kCoulomb: return "coulomb";
    case ElectrostaticsMethod::kPotentialMap: return "potential_map";
    case ElectrostaticsMethod::kApbs: return "apbs";
  }
  return "coulomb";
}

nlohmann::json electrostatics_json(const ElectrostaticsDetails& e, const std::vector<std::string>& warnings) {
  nlohmann::json block = {
      {"method", method_name(e.method)},
      {"charges", e.charges.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.charges)},
      {"force_field", e.force_field ? nlohmann::json(to_string(*e.force_field)) : nullptr},
      {"temperature", e.temperature},
      {"offset", e.offset},
      {"dielectric", e.dielectric.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.dielectric)},
      {"potential_map", e.potential_map.empty() ? nlohmann::json(nullptr) : nlohmann::json(e.potential_map.string())},
      {"net_charge", e.net_charge ? nlohmann::json(*e.net_charge) : nullptr},
      {"atoms_charged", e.atoms_charged},
      {"atoms_unmatched", e.atoms_unmatched},
      {"added_atoms", e.added_atoms},
      {"added_hydrogens", e.added_hydrogens}};
  nlohmann::json list = nlohmann::json::array();
  for (const auto& w : warnings)
    if (w.rfind("electrostatics: ", 0) == 0) list.push_back(w.substr(16));
  block["warnings"] = list;
  return block;
}

// `properties`: name -> what a reader needs to show or compare it (docs/report.md).
nlohmann::json properties_json(const MapJobResult& result) {
  nlohmann::json block = nlohmann::json::object();
  const PropertyReport& report = result.property_report;
  for (const SurfaceProperty& p : result.properties) {
    double lo = std::numeric_limits<double>::infinity(), hi = -lo, sum = 0;
    std::int64_t finite = 0, missing = 0;
    for (const double v : p.values) {
      if (!std::isfinite(v)) {
        ++missing;
        continue;
      }
      lo = std::min(lo, v), hi = std::max(hi, v), sum += v, ++finite;
    }
    nlohmann::json range = nullptr;
    if (finite > 0) range = {{"min", lo}, {"max", hi}, {"mean", sum / static_cast<double>(finite)}};
    nlohmann::json entry = {
        {"source", p.source},
        {"unit", p.info.unit},
        {"scale", std::string(to_string(p.info.scale))},
        {"default_range", p.info.default_range ? nlohmann::json{p.info.default_range->lo, p.info.default_range->hi}
                                               : nlohmann::json(nullptr)},
        {"range", range},
        {"missing", missing}};
    if (!p.info.categories.empty()) entry["categories"] = p.info.categories;
    if (p.info.name == property_names::kElectrostatics && report.electrostatics)
      entry["electrostatics"] = electrostatics_json(*report.electrostatics, report.warnings);
    if (p.info.name == property_names::kHydrophobicity)
      entry["unknown_residues"] = {{"count", report.unknown_residues.residues},
                                   {"names", report.unknown_residues.names}};
    for (const AtomValues& column : report.values)
      if (column.name == p.info.name)
        entry["values_file"] = {{"rows", column.rows},
                                {"rows_unmatched", column.rows_unmatched},
                                {"atoms_without_value", column.atoms_without_value},
                                {"unmatched_examples", column.unmatched_examples}};
    block[p.info.name] = entry;
  }
  return block;
}

nlohmann::json options_json(const MapJobResult& result, const MapJobOptions& options) {
  nlohmann::json json = {{"weights", to_string(options.map.weights)},
                         {"solver", to_string(options.map.solver)},
                         {"repair", options.map.repair},
                         {"collapse_floor", options.map.collapse_floor},
                         {"max_equalizing_rounds", options.map.max_equalizing_rounds},
                         {"weld_tolerance", options.prepare.weld_tolerance},
                         {"poles_given", result.map.poles.from_options}};
  // Only an objective other than the paper's map is written: the default reports stay as they were.
  if (options.map.objective != MapObjective::kPaper) {
    json["objective"] = to_string(options.map.objective);
    json["objective_max_iterations"] = options.map.objective_max_iterations;
  }
  return json;
}

nlohmann::json topology_repair_json(const HandleRepairReport& repair) {
  return {{"method", to_string(repair.method)},
          {"rounds", repair.rounds},
          {"samples_changed", repair.samples_changed},
          {"volume_changed", repair.volume_changed},
          {"area_before", repair.area_before},
          {"area_after", repair.area_after},
          {"area_changed_percent", repair.area_before > 0 ? 100 * (repair.area_after / repair.area_before - 1) : 0.0},
          {"genus_before", repair.genus_before},
          {"changes", closures_json(repair.closures)}};
}

nlohmann::json structure_json(const MapJobResult& result, const MapJobOptions& options) {
  if (!result.from_structure) return nullptr;
  const StructureReport& s = result.structure;
  return {{"atoms", result.atoms},
          {"probe", options.surface.probe},
          {"carve_cavities", options.surface.carve_cavities},
          {"contour_minimum_fraction", options.surface.contour_minimum_fraction},
          {"grid", options.surface.grid},
          {"models_in_file", s.models_in_file},
          {"atoms_in_model", s.atoms_in_model},
          {"hydrogens_removed", s.hydrogens_removed},
          {"waters_removed", s.waters_removed},
          {"hetero_removed", s.hetero_removed},
          {"other_chains_removed", s.other_chains_removed},
          {"alternate_locations_removed", s.alternate_locations_removed},
          {"warnings", s.warnings},
          {"topology_repair", topology_repair_json(result.topology)},
          {"components", components_json(result.components)},
          {"component_mapped", result.component_index}};
}

nlohmann::json mesh_json(const PreparedMesh& prepared) {
  const PrepareReport& prep = prepared.report;
  return {{"vertices", prepared.mesh.vertex_count()},
          {"triangles", prepared.mesh.triangle_count()},
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
          {"genus", prep.genus}};
}

nlohmann::json fallback_json(const FallbackReport& fallback) {
  const auto& e = fallback.embedding;
  return {{"method", "progressive-embedding"},
          {"south_vertex", fallback.south},
          {"levels", e.levels},
          {"base_vertices", e.base_vertices},
          {"insertions", e.insertions},
          {"failed_insertions", e.failed_insertions},
          {"optimizer_iterations", e.optimizer_iterations},
          {"final_iterations", e.final_iterations},
          {"final_stop_reason", to_string(e.final_stop_reason)},
          {"energy", to_string(SphereEnergy::kSymmetricDirichlet)},
          {"energy_before", e.energy_before},
          {"energy_after", e.energy_after},
          {"valid", e.valid}};
}

nlohmann::json objective_json(const ObjectiveReport& objective) {
  const auto& o = objective.optimization;
  nlohmann::json json = {{"objective", to_string(objective.objective)},
                         {"energy", to_string(objective.energy)},
                         {"outcome", to_string(objective.outcome)},
                         {"iterations", o.iterations},
                         {"stop_reason", to_string(o.stop_reason)},
                         {"energy_before", o.energy_before},
                         {"energy_after", o.energy_after}};
  if (objective.energy != SphereEnergy::kSymmetricDirichlet) json["stages"] = objective.stages;
  if (objective.energy == SphereEnergy::kLogAreaRatio) {
    json["shape_weight"] = objective.shape_weight;
    json["coarse_start"] = objective.coarse_levels == 0 ? nlohmann::json(nullptr)
                                                        : nlohmann::json{{"vertices", objective.coarse_vertices},
                                                                         {"levels", objective.coarse_levels},
                                                                         {"iterations", objective.coarse_iterations}};
  }
  return json;
}

nlohmann::json map_json(const SphereMap& map) {
  const auto& construction = map.diagnostics.construction;
  const auto& solve = map.diagnostics.solve;
  const auto& repair = map.diagnostics.repair;
  nlohmann::json splits = nlohmann::json::array();
  for (const auto& s : construction.split_edges)
    splits.push_back({{"a", s.a}, {"b", s.b}, {"ring", std::string(1, s.pole)}});
  const auto& r = map.superposition.rotation;
  nlohmann::json json = {{"method", to_string(construction.method)},
                         {"refinement_levels", construction.refinement_levels},
                         {"north_pole", map.poles.north},
                         {"south_pole", map.poles.south},
                         {"pole_graph_distance", map.poles.graph_distance},
                         {"theta0", construction.theta0},
                         {"mercator_c", construction.mercator_c},
                         {"ring_z", construction.ring_z},
                         {"north_ring_size", construction.north_ring_size},
                         {"south_ring_size", construction.south_ring_size},
                         {"split_edges", splits},
                         {"meridian_length", construction.meridian.size()},
                         {"meridian_method", to_string(construction.meridian_method)},
                         {"meridian_round", construction.meridian_round},
                         {"solver", to_string(solve.solver)},
                         {"elimination_order", to_string(solve.elimination_order)},
                         {"gauss_seidel_sweeps", solve.gauss_seidel_sweeps},
                         {"gauss_seidel_converged", solve.gauss_seidel_converged},
                         {"weight_fallback_rows", solve.weight_fallback_rows},
                         {"reweighting_rounds", repair.reweighting_rounds},
                         {"equalizing_rounds", repair.equalizing_rounds},
                         {"untangling_moves", repair.untangling_moves},
                         {"superposition_rotation", std::vector<double>(r.begin(), r.end())},
                         {"superposition_rmsd", map.superposition.rmsd},
                         {"superposition_scale", map.superposition.scale}};
  // Only maps that met a singular system carry these keys, as only maps that needed the fallback carry
  // its report: every other report stays as it was.
  if (solve.singular_systems > 0) {
    json["singular_systems"] = solve.singular_systems;
    json["uniform_weights_instead"] = solve.uniform_weights_instead;
  }
  if (map.diagnostics.fallback.ran) json["fallback"] = fallback_json(map.diagnostics.fallback);
  if (map.diagnostics.objective.objective != MapObjective::kPaper)
    json["objective"] = objective_json(map.diagnostics.objective);
  return json;
}

nlohmann::json distortion_json(const DistortionMetrics& m) {
  return {{"area_distortion_mean_percent", m.area_distortion_mean_percent},
          {"area_distortion_max_percent", m.area_distortion_max_percent},
          {"area_log_ratio_mean", m.area_log_ratio_mean},
          {"angle_distortion_mean_degrees", m.angle_distortion_mean_degrees},
          {"angle_distortion_rms_degrees", m.angle_distortion_rms_degrees},
          {"angle_distortion_max_degrees", m.angle_distortion_max_degrees},
          {"dilatation_mean", m.dilatation_mean},
          {"dilatation_max", m.dilatation_max},
          {"octant_area_percent", std::vector<double>(m.octant_area_percent.begin(), m.octant_area_percent.end())},
          {"octant_rms_deviation_percent", m.octant_rms_deviation_percent}};
}

}  // namespace

nlohmann::json make_report(const MapJobResult& result, const MapJobOptions& options) {
  return {
      {"spheremap_version", "0.1.0"},
      {"input", valid_utf8(result.input.string())},
      {"options", options_json(result, options)},
      {"structure", structure_json(result, options)},
      {"simplification", simplification_json(result, options)},
      {"mesh", mesh_json(result.prepared)},
      {"map", map_json(result.map)},
      {"certificate", certificate_json(result.map.certificate)},
      {"plain_algorithm_certificate", certificate_json(result.map.diagnostics.repair.plain_certificate)},
      {"distortion", distortion_json(result.metrics)},
      {"properties", properties_json(result)},
      {"timings_seconds", timings_json(result)},
  };
}

// ---------------------------------------------------------------------------------------------------
// Reading

namespace {

// The fields of one report, each looked up by its path of keys; a missing or mistyped one throws an
// InputError naming the file and the path (the first one met, in the order read_report asks).
class ReportFields {
 public:
  ReportFields(const nlohmann::json& report, const std::filesystem::path& source) : report_(report), source_(source) {}

  const nlohmann::json& at(std::initializer_list<const char*> keys) const {
    const nlohmann::json* node = &report_;
    std::string path;
    for (const char* key : keys) {
      path += path.empty() ? key : std::string(".") + key;
      if (!node->is_object() || !node->contains(key))
        throw InputError(
            fmt::format("{}: field '{}' is missing; this is not a report.json of spheremap map (or of an "
                        "older version): map the input again",
                        source_.string(), path));
      node = &(*node)[key];
    }
    return *node;
  }
  bool is_null(std::initializer_list<const char*> keys) const { return at(keys).is_null(); }
  // For fields added later (a report of an earlier version lacks them).
  bool has(std::initializer_list<const char*> keys) const {
    const nlohmann::json* node = &report_;
    for (const char* key : keys) {
      if (!node->is_object() || !node->contains(key)) return false;
      node = &(*node)[key];
    }
    return true;
  }
  const std::filesystem::path& source() const { return source_; }

  std::string text(std::initializer_list<const char*> keys) const {
    const auto& value = at(keys);
    if (!value.is_string()) wrong_type(keys, value);
    return value.get<std::string>();
  }
  bool flag(std::initializer_list<const char*> keys) const {
    const auto& value = at(keys);
    if (!value.is_boolean()) wrong_type(keys, value);
    return value.get<bool>();
  }
  std::int64_t integer(std::initializer_list<const char*> keys) const {
    const auto& value = at(keys);
    if (!value.is_number_integer()) wrong_type(keys, value);
    return value.get<std::int64_t>();
  }
  // JSON has no NaN or infinity: nlohmann writes them as null.
  double number(std::initializer_list<const char*> keys) const {
    const auto& value = at(keys);
    if (value.is_null()) return std::numeric_limits<double>::quiet_NaN();
    if (!value.is_number()) wrong_type(keys, value);
    return value.get<double>();
  }
  const nlohmann::json& array(std::initializer_list<const char*> keys) const {
    const auto& value = at(keys);
    if (!value.is_array()) wrong_type(keys, value);
    return value;
  }
  const nlohmann::json& object(std::initializer_list<const char*> keys) const {
    const auto& value = at(keys);
    if (!value.is_object()) wrong_type(keys, value);
    return value;
  }

  [[noreturn]] void wrong_type(std::initializer_list<const char*> keys, const nlohmann::json& value) const {
    std::string path;
    for (const char* key : keys) path += path.empty() ? key : std::string(".") + key;
    throw InputError(fmt::format("{}: field '{}' has the wrong type ({}); map the input again", source_.string(), path,
                                 value.type_name()));
  }

 private:
  const nlohmann::json& report_;
  const std::filesystem::path& source_;
};

ReportCertificate read_certificate(const ReportFields& f, const char* name) {
  ReportCertificate c;
  c.certified = f.flag({name, "certified"});
  c.folded = f.integer({name, "folded"});
  c.collapsed = f.integer({name, "collapsed"});
  c.coverage = f.number({name, "coverage"});
  c.min_area_ratio = f.number({name, "min_area_ratio"});
  c.decided_exactly = f.integer({name, "decided_exactly"});
  return c;
}

ReportStructure read_structure_part(const ReportFields& f) {
  ReportStructure s;
  s.atoms = f.integer({"structure", "atoms"});
  s.probe = f.number({"structure", "probe"});
  s.grid = f.number({"structure", "grid"});
  if (f.has({"structure", "warnings"}))
    for (const auto& warning : f.array({"structure", "warnings"}))
      if (warning.is_string()) s.warnings.push_back(warning.get<std::string>());
  ReportTopologyRepair& r = s.topology_repair;
  r.method = f.text({"structure", "topology_repair", "method"});
  r.rounds = f.integer({"structure", "topology_repair", "rounds"});
  r.samples_changed = f.integer({"structure", "topology_repair", "samples_changed"});
  r.volume_changed = f.number({"structure", "topology_repair", "volume_changed"});
  r.area_before = f.number({"structure", "topology_repair", "area_before"});
  r.area_after = f.number({"structure", "topology_repair", "area_after"});
  r.area_changed_percent = f.number({"structure", "topology_repair", "area_changed_percent"});
  r.genus_before = f.integer({"structure", "topology_repair", "genus_before"});
  for (const auto& change : f.array({"structure", "topology_repair", "changes"})) {
    const auto kind = change.is_object() ? change.find("kind") : change.end();
    if (kind == change.end()) continue;
    r.handles_cut += *kind == "cut";
    r.tunnels_filled += *kind == "fill";
  }
  return s;
}

ReportSimplification read_simplification(const ReportFields& f) {
  ReportSimplification s;
  s.vertices_before = f.integer({"simplification", "vertices_before"});
  s.area_before = f.number({"simplification", "area_before"});
  s.area_after = f.number({"simplification", "area_after"});
  s.max_vertex_distance = f.number({"simplification", "max_vertex_distance"});
  return s;
}

DistortionMetrics read_distortion(const ReportFields& f) {
  DistortionMetrics d;
  d.area_distortion_mean_percent = f.number({"distortion", "area_distortion_mean_percent"});
  d.area_distortion_max_percent = f.number({"distortion", "area_distortion_max_percent"});
  d.area_log_ratio_mean = f.number({"distortion", "area_log_ratio_mean"});
  d.angle_distortion_mean_degrees = f.number({"distortion", "angle_distortion_mean_degrees"});
  d.angle_distortion_rms_degrees = f.number({"distortion", "angle_distortion_rms_degrees"});
  d.angle_distortion_max_degrees = f.number({"distortion", "angle_distortion_max_degrees"});
  d.dilatation_mean = f.number({"distortion", "dilatation_mean"});
  d.dilatation_max = f.number({"distortion", "dilatation_max"});
  const auto& octants = f.array({"distortion", "octant_area_percent"});
  if (octants.size() != d.octant_area_percent.size())
    throw InputError(
        fmt::format("{}: field 'distortion.octant_area_percent' has {} values instead of {}; map the "
                    "input again",
                    f.source().string(), octants.size(), d.octant_area_percent.size()));
  for (std::size_t k = 0; k < octants.size(); ++k) {
    if (!octants[k].is_number()) f.wrong_type({"distortion", "octant_area_percent"}, octants[k]);
    d.octant_area_percent[k] = octants[k].get<double>();
  }
  d.octant_rms_deviation_percent = f.number({"distortion", "octant_rms_deviation_percent"});
  return d;
}

void read_map_part(const ReportFields& f, ReportSummary& r) {
  r.map_method = f.text({"map", "method"});
  r.north_pole = f.integer({"map", "north_pole"});
  r.south_pole = f.integer({"map", "south_pole"});
  r.pole_graph_distance = f.integer({"map", "pole_graph_distance"});
  r.split_edges = static_cast<std::int64_t>(f.array({"map", "split_edges"}).size());
  r.solver = f.text({"map", "solver"});
  r.reweighting_rounds = f.integer({"map", "reweighting_rounds"});
  r.untangling_moves = f.integer({"map", "untangling_moves"});
  r.superposition_rmsd = f.number({"map", "superposition_rmsd"});
}

}  // namespace

ReportSummary read_report(const nlohmann::json& report, const std::filesystem::path& source) {
  const ReportFields f(report, source);
  ReportSummary r;
  r.source = source;
  r.input = f.text({"input"});
  r.weights = f.text({"options", "weights"});
  r.repair = f.flag({"options", "repair"});
  r.triangles = f.integer({"mesh", "triangles"});
  if (r.triangles <= 0)
    throw InputError(fmt::format("{}: mesh.triangles is {}; map the input again", source.string(), r.triangles));
  r.certificate = read_certificate(f, "certificate");
  r.plain_certificate = read_certificate(f, "plain_algorithm_certificate");
  r.distortion = read_distortion(f);
  r.vertices = f.integer({"mesh", "vertices"});
  r.input_vertices = f.integer({"mesh", "input_vertices"});
  r.input_faces = f.integer({"mesh", "input_faces"});
  r.components = f.integer({"mesh", "components"});
  r.genus = f.integer({"mesh", "genus"});
  if (!f.is_null({"structure"})) r.structure = read_structure_part(f);
  if (!f.is_null({"simplification"})) r.simplification = read_simplification(f);
  read_map_part(f, r);
  // `properties` (reports of spheremap before 0.2 have none): the names, and the electrostatics' source.
  if (report.contains("properties") && report["properties"].is_object()) {
    for (const auto& [name, entry] : f.object({"properties"}).items()) {
      r.properties.push_back(name);
      if (name == "electrostatics") r.electrostatics_source = f.text({"properties", "electrostatics", "source"});
    }
  }
  for (const auto& [stage, seconds] : f.object({"timings_seconds"}).items())
    if (seconds.is_number()) r.timings.push_back({stage, seconds.get<double>()});
  return r;
}

std::vector<ReportProperty> read_report_properties(const nlohmann::json& report, const std::filesystem::path& source) {
  std::vector<ReportProperty> properties;
  if (!report.is_object() || !report.contains("properties") || !report["properties"].is_object()) return properties;
  const ReportFields f(report, source);
  for (const auto& [name, entry] : report["properties"].items()) {
    ReportProperty p;
    p.info.name = name;
    p.info.unit = f.text({"properties", name.c_str(), "unit"});
    p.source = f.text({"properties", name.c_str(), "source"});
    const std::string scale = f.text({"properties", name.c_str(), "scale"});
    bool known = false;
    for (const ScaleKind kind :
         {ScaleKind::sequential, ScaleKind::diverging, ScaleKind::categorical, ScaleKind::spectrum})
      if (to_string(kind) == scale) p.info.scale = kind, known = true;
    if (!known)
      throw InputError(
          fmt::format("{}: field 'properties.{}.scale' is '{}', not a colour scale of spheremap; map the "
                      "input again",
                      source.string(), name, scale));
    const auto range = entry.find("default_range");
    if (range != entry.end() && !range->is_null()) {
      if (!range->is_array() || range->size() != 2 || !(*range)[0].is_number() || !(*range)[1].is_number())
        f.wrong_type({"properties", name.c_str(), "default_range"}, *range);
      p.info.default_range = ValueRange{(*range)[0].get<double>(), (*range)[1].get<double>()};
    }
    const auto categories = entry.find("categories");
    if (categories != entry.end() && categories->is_array())
      for (const auto& c : *categories)
        if (c.is_string()) p.info.categories.push_back(c.get<std::string>());
    properties.push_back(std::move(p));
  }
  return properties;
}

ReportSummary read_report_file(const std::filesystem::path& report_json) {
  std::ifstream in(report_json, std::ios::binary);
  if (!in)
    throw InputError(
        fmt::format("{}: cannot open the file; check that it exists and is readable", report_json.string()));
  std::stringstream text;
  text << in.rdbuf();
  nlohmann::json report;
  try {
    report = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(fmt::format("{}: not valid JSON ({}); map the input again", report_json.string(), e.what()));
  }
  return read_report(report, report_json);
}

}  // namespace spheremap
