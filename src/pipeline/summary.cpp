// The batch summary: one row per run from its folder (report.json through read_report, or error.json),
// as CSV and JSON lines; the batch's exit code from the rows.
#include "spheremap/pipeline/summary.hpp"

#include <cmath>
#include <set>

#include <fmt/format.h>

#include "detail.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "spheremap/pipeline/report.hpp"
#include "spheremap/pipeline/run_folder.hpp"
#include "spheremap/text.hpp"

namespace spheremap {
namespace {

using namespace pipeline_detail;

constexpr int kOctants = 8;

// report.json holds null where a number was not finite (JSON has no NaN): so does the row.
Json number(double value) { return std::isfinite(value) ? Json(value) : Json(nullptr); }

// Sets the columns given (each one of summary_columns()).
void put(Json& row, std::initializer_list<std::pair<const char*, Json>> columns) {
  for (const auto& [column, value] : columns) row[column] = value;
}

void set_structure_columns(Json& row, const ReportStructure& s) {
  const ReportTopologyRepair& t = s.topology_repair;
  put(row, {{"atoms", s.atoms},
            {"probe", number(s.probe)},
            {"grid", number(s.grid)},
            {"handles_cut", t.handles_cut},
            {"tunnels_filled", t.tunnels_filled},
            {"repair_method", t.method},
            {"repair_rounds", t.rounds},
            {"repair_samples_changed", t.samples_changed},
            {"repair_volume_changed", number(t.volume_changed)},
            {"repair_area_before", number(t.area_before)},
            {"repair_area_after", number(t.area_after)},
            {"repair_area_changed_percent", number(t.area_changed_percent)}});
}

void set_certificate_columns(Json& row, const std::string& prefix, const ReportCertificate& c) {
  row[prefix + "certified"] = c.certified;
  row[prefix + "folded"] = c.folded;
  row[prefix + "collapsed"] = c.collapsed;
  row[prefix + "coverage"] = number(c.coverage);
  row[prefix + "min_area_ratio"] = number(c.min_area_ratio);
}

void set_distortion_columns(Json& row, const DistortionMetrics& d) {
  put(row, {{"area_distortion_mean_percent", number(d.area_distortion_mean_percent)},
            {"area_distortion_max_percent", number(d.area_distortion_max_percent)},
            {"area_log_ratio_mean", number(d.area_log_ratio_mean)},
            {"angle_distortion_mean_degrees", number(d.angle_distortion_mean_degrees)},
            {"angle_distortion_rms_degrees", number(d.angle_distortion_rms_degrees)},
            {"angle_distortion_max_degrees", number(d.angle_distortion_max_degrees)},
            {"dilatation_mean", number(d.dilatation_mean)},
            {"dilatation_max", number(d.dilatation_max)},
            {"octant_rms_deviation_percent", number(d.octant_rms_deviation_percent)}});
  for (int k = 0; k < kOctants; ++k)
    row[fmt::format("octant_area_percent_{}", k)] = number(d.octant_area_percent[static_cast<std::size_t>(k)]);
}

// Stages of their own column; every other timing is a part of the map.
constexpr const char* kStageColumns[][2] = {{"read", "seconds_read"},
                                            {"surface", "seconds_surface"},
                                            {"simplify", "seconds_simplify"},
                                            {"prepare", "seconds_prepare"},
                                            {"metrics", "seconds_metrics"}};

void set_timing_columns(Json& row, const std::vector<StageTime>& timings) {
  double total = 0, map = 0;
  for (const auto& [stage, seconds] : timings) {
    total += seconds;
    bool own_column = false;
    for (const auto& [name, column] : kStageColumns)
      if (stage == name) row[column] = number(seconds), own_column = true;
    if (!own_column) map += seconds;
  }
  // Sums to the microsecond: their last bits are noise, not information.
  row["seconds_map"] = std::round(map * 1e6) / 1e6;
  row["seconds_total"] = std::round(total * 1e6) / 1e6;
}

void set_report_columns(Json& row, const ReportSummary& r) {
  if (r.structure) set_structure_columns(row, *r.structure);
  // Meshes are never repaired: their genus is the mesh's. Structures: the outer surface before the
  // handle repair.
  const std::int64_t genus_before = r.structure ? r.structure->topology_repair.genus_before : r.genus;
  put(row, {{"vertices", r.vertices},
            {"triangles", r.triangles},
            {"input_vertices", r.input_vertices},
            {"input_faces", r.input_faces},
            {"components", r.components},
            {"genus_before_repair", genus_before}});
  if (const auto& s = r.simplification)
    put(row, {{"simplified_vertices_before", s->vertices_before},
              {"simplified_area_before", number(s->area_before)},
              {"simplified_area_after", number(s->area_after)},
              {"simplified_max_vertex_distance", number(s->max_vertex_distance)}});
  put(row, {{"map_method", r.map_method},
            {"north_pole", r.north_pole},
            {"south_pole", r.south_pole},
            {"pole_graph_distance", r.pole_graph_distance},
            {"solver", r.solver},
            {"reweighting_rounds", r.reweighting_rounds},
            {"untangling_moves", r.untangling_moves},
            {"superposition_rmsd", number(r.superposition_rmsd)},
            {"split_edges", r.split_edges},
            {"decided_exactly", r.certificate.decided_exactly}});
  set_certificate_columns(row, "", r.certificate);
  set_certificate_columns(row, "plain_", r.plain_certificate);
  set_distortion_columns(row, r.distortion);
  set_timing_columns(row, r.timings);
  std::string names;
  for (const auto& name : r.properties) names += (names.empty() ? "" : ";") + name;
  put(row, {{"properties", names}, {"electrostatics_source", r.electrostatics_source}});
}

std::string csv_field(const Json& value) {
  if (value.is_null()) return {};
  std::string text = value.is_string() ? valid_utf8(value.get<std::string>()) : dump(value);
  const bool quote =
      text.find_first_of(",\"\r\n") != std::string::npos ||
      (!text.empty() && (text.front() == ' ' || text.back() == ' ' || text.front() == '\t' || text.back() == '\t'));
  if (!quote) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + '"';
}

}  // namespace

const std::vector<std::string>& summary_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = {"input",
                                  "output",
                                  "weights",
                                  "status",
                                  "exit_code",
                                  "message",
                                  "atoms",
                                  "probe",
                                  "grid",
                                  "vertices",
                                  "triangles",
                                  "input_vertices",
                                  "input_faces",
                                  "components",
                                  "genus_before_repair",
                                  "handles_cut",
                                  "tunnels_filled",
                                  "repair_method",
                                  "repair_rounds",
                                  "repair_samples_changed",
                                  "repair_volume_changed",
                                  "repair_area_before",
                                  "repair_area_after",
                                  "repair_area_changed_percent",
                                  "simplified_vertices_before",
                                  "simplified_area_before",
                                  "simplified_area_after",
                                  "simplified_max_vertex_distance",
                                  "map_method",
                                  "north_pole",
                                  "south_pole",
                                  "pole_graph_distance",
                                  "solver",
                                  "reweighting_rounds",
                                  "untangling_moves",
                                  "superposition_rmsd",
                                  "certified",
                                  "folded",
                                  "collapsed",
                                  "coverage",
                                  "min_area_ratio",
                                  "decided_exactly",
                                  "plain_certified",
                                  "plain_folded",
                                  "plain_collapsed",
                                  "plain_coverage",
                                  "plain_min_area_ratio",
                                  "area_distortion_mean_percent",
                                  "area_distortion_max_percent",
                                  "area_log_ratio_mean",
                                  "angle_distortion_mean_degrees",
                                  "angle_distortion_rms_degrees",
                                  "angle_distortion_max_degrees",
                                  "dilatation_mean",
                                  "dilatation_max"};
    for (int k = 0; k < kOctants; ++k) c.push_back(fmt::format("octant_area_percent_{}", k));
    for (const char* column : {"octant_rms_deviation_percent", "split_edges", "seconds_read", "seconds_surface",
                               "seconds_simplify", "seconds_prepare", "seconds_map", "seconds_metrics", "seconds_total",
                               "peak_rss_mb", "properties", "electrostatics_source"})
      c.emplace_back(column);
    return c;
  }();
  return columns;
}

Json summary_row(const BatchInput& input, Weights weights, const fs::path& root, const fs::path& folder) {
  Json row = Json::object();
  for (const auto& column : summary_columns()) row[column] = nullptr;
  const RunFolder state = read_run_folder(folder);
  row["input"] = valid_utf8(input.path.string());
  row["output"] = valid_utf8(folder.lexically_relative(root).generic_string());
  row["weights"] = to_string(weights);
  row["status"] = to_string(state.status);
  if (state.status == RunStatus::kPending) return row;
  row["exit_code"] = state.exit_code;
  if (state.status == RunStatus::kError) {
    row["message"] = valid_utf8(state.message);
    return row;
  }
  const ReportSummary& r = *state.report;
  std::vector<std::string> message;
  if (state.status == RunStatus::kNotCertified)
    message.push_back(fmt::format("NOT certified: {} folded, {} collapsed triangles, coverage {}", r.certificate.folded,
                                  r.certificate.collapsed, dump(number(r.certificate.coverage))));
  if (r.structure)
    for (const auto& warning : r.structure->warnings) message.push_back("warning: " + valid_utf8(warning));
  if (!message.empty()) row["message"] = fmt::format("{}", fmt::join(message, "; "));
  set_report_columns(row, r);
  if (state.peak_rss_mb) row["peak_rss_mb"] = *state.peak_rss_mb;
  return row;
}

std::vector<Json> build_summary(const fs::path& root, const std::vector<BatchInput>& inputs,
                                const std::vector<Weights>& weights) {
  std::vector<Json> rows;
  rows.reserve(inputs.size() * weights.size());
  for (const auto& input : inputs)
    for (std::size_t k = 0; k < weights.size(); ++k)
      rows.push_back(summary_row(input, weights[k], root, batch_run_folder(root, input, weights, k)));
  return rows;
}

std::string summary_csv(const std::vector<Json>& rows) {
  std::string text;
  const auto& columns = summary_columns();
  for (std::size_t k = 0; k < columns.size(); ++k) text += (k ? "," : "") + columns[k];
  text += '\n';
  for (const auto& row : rows) {
    for (std::size_t k = 0; k < columns.size(); ++k) {
      if (k) text += ',';
      const auto it = row.find(columns[k]);
      if (it != row.end()) text += csv_field(*it);
    }
    text += '\n';
  }
  return text;
}

std::string summary_jsonl(const std::vector<Json>& rows) {
  std::string text;
  for (const auto& row : rows) text += dump(row) + "\n";
  return text;
}

std::vector<Json> write_batch_summary(const fs::path& root, const std::vector<BatchInput>& inputs,
                                      const std::vector<Weights>& weights) {
  auto rows = build_summary(root, inputs, weights);
  write_file_atomically(root / kSummaryCsvFile, summary_csv(rows));
  write_file_atomically(root / kSummaryJsonlFile, summary_jsonl(rows));
  return rows;
}

int batch_exit_code(const std::vector<Json>& rows) {
  std::set<int> codes;
  for (const auto& row : rows) {
    const auto status = row.value("status", std::string());
    if (status == "pending")
      codes.insert(4);
    else if (status == "not-certified")
      codes.insert(static_cast<int>(ExitCode::kNotCertified));
    else if (status == "error") {
      const auto& code = row.at("exit_code");
      codes.insert(code.is_number_integer() ? code.get<int>() : 4);
    }
  }
  for (const int code : {4, 1, 2, 3})
    if (codes.count(code)) return code;
  for (const int code : codes)
    if (code != 0) return code;  // an unknown code from an error.json: still a failure
  return 0;
}

}  // namespace spheremap
