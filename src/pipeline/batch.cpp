// Batch runs (see include/spheremap/batch.hpp): input expansion, output names, run folders as the
// state of a batch, the summary built from them, and the parallel runner.
#include "spheremap/pipeline/batch.hpp"

#include <fcntl.h>
#include <glob.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <fstream>
#include <map>
#include <mutex>
#include <new>
#include <optional>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;
using Json = nlohmann::ordered_json;

std::string lower(std::string text) {
  std::transform(text.begin(), text.end(), text.begin(), [](unsigned char c) { return std::tolower(c); });
  return text;
}

std::string trim(const std::string& text) {
  const auto first = text.find_first_not_of(" \t\r\n");
  if (first == std::string::npos) return {};
  const auto last = text.find_last_not_of(" \t\r\n");
  return text.substr(first, last - first + 1);
}

std::optional<std::string> read_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return std::nullopt;
  std::stringstream text;
  text << in.rdbuf();
  if (in.bad()) return std::nullopt;
  return text.str();
}

// JSON text that never throws on invalid UTF-8 (file names and messages are arbitrary bytes).
std::string dump(const Json& value, int indent = -1) {
  return value.dump(indent, ' ', false, nlohmann::json::error_handler_t::replace);
}

// ---------------------------------------------------------------------------------------------------
// Inputs

constexpr int kMaxListDepth = 8;

bool has_glob_characters(const std::string& text) { return text.find_first_of("*?[") != std::string::npos; }

void expand_argument(const std::string& argument, const fs::path& base, int depth, std::vector<fs::path>& out);

void expand_list(const fs::path& list, int depth, std::vector<fs::path>& out) {
  if (depth >= kMaxListDepth)
    throw InputError(fmt::format("{}: lists include lists more than {} levels deep (a list including itself?); "
                                 "flatten the lists",
                                 list.string(), kMaxListDepth));
  const auto text = read_text(list);
  std::error_code ec;
  if (!text || fs::is_directory(list, ec))
    throw InputError(fmt::format("{}: cannot read this list of inputs; check the path (a list holds one input per line)",
                                 list.string()));
  std::istringstream lines(*text);
  for (std::string line; std::getline(lines, line);) {
    line = trim(line);
    if (line.empty() || line[0] == '#') continue;
    expand_argument(line, list.parent_path(), depth + 1, out);
  }
}

void expand_folder(const fs::path& folder, std::vector<fs::path>& out) {
  std::vector<std::pair<std::string, fs::path>> files;
  std::error_code ec;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const auto name = it->path().filename().string();
    if (name.empty() || name[0] == '.') continue;
    std::error_code type_error;
    if (it->is_directory(type_error)) continue;
    if (is_batch_input_file(it->path())) files.emplace_back(name, it->path());
  }
  if (ec) throw InputError(fmt::format("{}: cannot list this folder ({}); check its permissions", folder.string(), ec.message()));
  std::sort(files.begin(), files.end());
  for (auto& [name, path] : files) out.push_back(std::move(path));
}

// A path (not an @list): a folder, a .txt list, a glob pattern or a file.
void expand_path(const fs::path& path, int depth, std::vector<fs::path>& out) {
  std::error_code ec;
  const auto status = fs::status(path, ec);
  if (fs::is_directory(status)) {
    expand_folder(path, out);
  } else if (fs::exists(status)) {
    if (lower(path.extension().string()) == ".txt") expand_list(path, depth, out);
    else out.push_back(path);
  } else if (has_glob_characters(path.string())) {
    glob_t matches{};
    const int found = ::glob(path.c_str(), GLOB_NOSORT, nullptr, &matches);
    std::vector<std::string> names;
    if (found == 0)
      for (std::size_t k = 0; k < matches.gl_pathc; ++k) names.emplace_back(matches.gl_pathv[k]);
    ::globfree(&matches);
    if (names.empty()) {
      out.push_back(path);  // nothing matches: taken as given, like a shell without nullglob
      return;
    }
    std::sort(names.begin(), names.end());
    for (const auto& name : names) {
      const fs::path match = name;
      if (fs::is_directory(match, ec)) expand_folder(match, out);
      else if (lower(match.extension().string()) == ".txt") expand_list(match, depth, out);
      else out.push_back(match);
    }
  } else {
    out.push_back(path);
  }
}

void expand_argument(const std::string& argument, const fs::path& base, int depth, std::vector<fs::path>& out) {
  if (argument.empty()) return;
  fs::path path = argument[0] == '@' ? fs::path(argument.substr(1)) : fs::path(argument);
  if (path.is_relative()) path = base / path;
  if (argument[0] == '@') expand_list(path, depth, out);
  else expand_path(path, depth, out);
}

// ---------------------------------------------------------------------------------------------------
// Run folders

// Written after report.json by the process that mapped the input: {"peak_rss_mb": ...}. Optional: a run
// is complete without it (its column is then empty).
constexpr const char* kRunResourcesFile = "resources.json";

const std::vector<std::string>& run_file_names() {
  static const std::vector<std::string> names = {"surface.ply", "sphere.ply", kRunReportFile, kRunErrorFile,
                                                 kRunResourcesFile};
  return names;
}

const std::vector<std::string>& root_file_names() {
  static const std::vector<std::string> names = {"summary.csv", "summary.jsonl", "batch.json"};
  return names;
}

// `name` is `<one of known>.tmp-<digits>`: what write_file_atomically leaves behind when killed.
bool is_leftover_temporary(const std::string& name, const std::vector<std::string>& known) {
  const auto marker = name.rfind(".tmp-");
  if (marker == std::string::npos || marker + 5 == name.size()) return false;
  if (!std::all_of(name.begin() + static_cast<std::ptrdiff_t>(marker) + 5, name.end(),
                   [](unsigned char c) { return std::isdigit(c); }))
    return false;
  return std::find(known.begin(), known.end(), name.substr(0, marker)) != known.end();
}

void remove_leftover_temporaries(const fs::path& folder, const std::vector<std::string>& known) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  std::vector<fs::path> doomed;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (is_leftover_temporary(it->path().filename().string(), known)) doomed.push_back(it->path());
  for (const auto& path : doomed) fs::remove(path, ec);
}

// Removes what a run writes (and leftovers), so that the folder is pending; other files are left alone.
void clear_run_folder(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  remove_leftover_temporaries(folder, run_file_names());
  // report.json first: from then on the folder is pending whatever happens next.
  for (const char* name : {kRunReportFile, kRunErrorFile, kRunResourcesFile, "surface.ply", "sphere.ply"}) {
    fs::remove(folder / name, ec);
    if (ec)
      throw InputError(fmt::format("{}: cannot remove it ({}); check the permissions of the output folder",
                                   (folder / name).string(), ec.message()));
  }
}

constexpr Weights kAllWeights[] = {Weights::kUniform, Weights::kCotangent, Weights::kMeanValue};

// Every folder an input may have used, whatever the weightings of earlier batches.
std::vector<fs::path> all_input_folders(const fs::path& root, const BatchInput& input) {
  std::vector<fs::path> folders = {root / input.name};
  for (const Weights w : kAllWeights) folders.push_back(root / input.name / to_string(w));
  return folders;
}

// ---------------------------------------------------------------------------------------------------
// Summary

template <typename Keys>
const Json& at_path(const Json& object, const Keys& keys) {
  static const Json null_value;
  const Json* node = &object;
  for (const char* key : keys) {
    if (!node->is_object()) return null_value;
    const auto it = node->find(key);
    if (it == node->end()) return null_value;
    node = &*it;
  }
  return *node;
}

const Json& at(const Json& object, std::initializer_list<const char*> keys) { return at_path(object, keys); }

struct FolderState {
  RunStatus status = RunStatus::kPending;
  Json report;      // parsed report.json (kOk, kNotCertified)
  int exit_code = 0;
  std::string message;
};

FolderState read_folder(const fs::path& folder) {
  FolderState state;
  std::error_code ec;
  if (fs::exists(folder / kRunReportFile, ec)) {
    const auto text = read_text(folder / kRunReportFile);
    try {
      if (!text) throw std::runtime_error("cannot read it");
      state.report = Json::parse(*text);
      const Json& certified = at(state.report, {"certificate", "certified"});
      if (!certified.is_boolean()) throw std::runtime_error("no certificate.certified");
      state.status = certified.get<bool>() ? RunStatus::kOk : RunStatus::kNotCertified;
      state.exit_code = certified.get<bool>() ? 0 : static_cast<int>(ExitCode::kNotCertified);
    } catch (const std::exception& e) {
      state = {};
      state.status = RunStatus::kError;
      state.exit_code = 4;
      state.message = fmt::format("{}: unreadable ({}); rerun with --force", (folder / kRunReportFile).string(), e.what());
    }
    return state;
  }
  if (fs::exists(folder / kRunErrorFile, ec)) {
    state.status = RunStatus::kError;
    const auto text = read_text(folder / kRunErrorFile);
    try {
      if (!text) throw std::runtime_error("cannot read it");
      const Json error = Json::parse(*text);
      state.exit_code = error.at("exit_code").get<int>();
      state.message = error.at("message").get<std::string>();
    } catch (const std::exception& e) {
      state.exit_code = 4;
      state.message = fmt::format("{}: unreadable ({}); rerun with --retry-errors", (folder / kRunErrorFile).string(), e.what());
    }
  }
  return state;
}

// Columns taken from report.json as they are: column name, then the path in the report.
struct ReportColumn {
  const char* column;
  std::vector<const char*> path;  // not an initializer_list: its array would not outlive the table
};

const std::vector<ReportColumn>& report_columns_before_repair() {
  static const std::vector<ReportColumn> columns = {
      {"atoms", {"structure", "atoms"}},
      {"probe", {"structure", "probe"}},
      {"grid", {"structure", "grid"}},
      {"vertices", {"mesh", "vertices"}},
      {"triangles", {"mesh", "triangles"}},
      {"input_vertices", {"mesh", "input_vertices"}},
      {"input_faces", {"mesh", "input_faces"}},
      {"components", {"mesh", "components"}},
  };
  return columns;
}

const std::vector<ReportColumn>& report_columns_after_repair() {
  static const std::vector<ReportColumn> columns = {
      {"repair_method", {"structure", "topology_repair", "method"}},
      {"repair_rounds", {"structure", "topology_repair", "rounds"}},
      {"repair_samples_changed", {"structure", "topology_repair", "samples_changed"}},
      {"repair_volume_changed", {"structure", "topology_repair", "volume_changed"}},
      {"repair_area_before", {"structure", "topology_repair", "area_before"}},
      {"repair_area_after", {"structure", "topology_repair", "area_after"}},
      {"repair_area_changed_percent", {"structure", "topology_repair", "area_changed_percent"}},
      {"simplified_vertices_before", {"simplification", "vertices_before"}},
      {"simplified_area_before", {"simplification", "area_before"}},
      {"simplified_area_after", {"simplification", "area_after"}},
      {"simplified_max_vertex_distance", {"simplification", "max_vertex_distance"}},
      {"map_method", {"map", "method"}},
      {"north_pole", {"map", "north_pole"}},
      {"south_pole", {"map", "south_pole"}},
      {"pole_graph_distance", {"map", "pole_graph_distance"}},
      {"solver", {"map", "solver"}},
      {"reweighting_rounds", {"map", "reweighting_rounds"}},
      {"untangling_moves", {"map", "untangling_moves"}},
      {"superposition_rmsd", {"map", "superposition_rmsd"}},
      {"certified", {"certificate", "certified"}},
      {"folded", {"certificate", "folded"}},
      {"collapsed", {"certificate", "collapsed"}},
      {"coverage", {"certificate", "coverage"}},
      {"min_area_ratio", {"certificate", "min_area_ratio"}},
      {"decided_exactly", {"certificate", "decided_exactly"}},
      {"plain_certified", {"plain_algorithm_certificate", "certified"}},
      {"plain_folded", {"plain_algorithm_certificate", "folded"}},
      {"plain_collapsed", {"plain_algorithm_certificate", "collapsed"}},
      {"plain_coverage", {"plain_algorithm_certificate", "coverage"}},
      {"plain_min_area_ratio", {"plain_algorithm_certificate", "min_area_ratio"}},
      {"area_distortion_mean_percent", {"distortion", "area_distortion_mean_percent"}},
      {"area_distortion_max_percent", {"distortion", "area_distortion_max_percent"}},
      {"area_log_ratio_mean", {"distortion", "area_log_ratio_mean"}},
      {"angle_distortion_mean_degrees", {"distortion", "angle_distortion_mean_degrees"}},
      {"angle_distortion_rms_degrees", {"distortion", "angle_distortion_rms_degrees"}},
      {"angle_distortion_max_degrees", {"distortion", "angle_distortion_max_degrees"}},
      {"dilatation_mean", {"distortion", "dilatation_mean"}},
      {"dilatation_max", {"distortion", "dilatation_max"}},
  };
  return columns;
}

constexpr int kOctants = 8;
constexpr const char* kTimingColumns[] = {"seconds_read", "seconds_surface", "seconds_simplify", "seconds_prepare",
                                          "seconds_map",  "seconds_metrics", "seconds_total"};

}  // namespace

// -----------------------------------------------------------------------------------------------------

bool is_batch_input_file(const fs::path& path) {
  const auto extension = lower(path.extension().string());
  return extension == ".obj" || extension == ".off" || extension == ".ply" || extension == ".stl" ||
         is_structure_file(path);
}

std::vector<fs::path> expand_batch_inputs(const std::vector<std::string>& arguments) {
  std::vector<fs::path> expanded;
  for (const auto& argument : arguments) expand_argument(argument, fs::path(), 0, expanded);
  std::vector<fs::path> unique;
  std::set<fs::path> seen;
  for (auto& path : expanded) {
    std::error_code ec;
    fs::path key = fs::weakly_canonical(path, ec);
    if (ec) key = fs::absolute(path, ec).lexically_normal();
    if (seen.insert(key).second) unique.push_back(std::move(path));
  }
  if (unique.empty()) {
    std::string given;
    for (const auto& argument : arguments) given += (given.empty() ? "" : " ") + argument;
    throw InputError(fmt::format("no input files in '{}': folders give their .obj .off .ply .stl .pdb .ent .cif "
                                 ".mmcif .pqr (.gz) files (not those of subfolders)",
                                 given));
  }
  return unique;
}

std::vector<BatchInput> name_batch_inputs(const std::vector<fs::path>& paths) {
  auto stem_of = [](const fs::path& path) {
    fs::path name = path.filename();
    if (lower(name.extension().string()) == ".gz") name = name.stem();
    std::string stem = name.stem().string();
    return stem.empty() ? name.string() : stem;
  };
  std::map<std::string, int> stem_count;
  for (const auto& name : root_file_names()) ++stem_count[name];
  for (const auto& path : paths) ++stem_count[lower(stem_of(path))];
  std::vector<BatchInput> inputs;
  std::set<std::string> taken(root_file_names().begin(), root_file_names().end());
  for (const auto& path : paths) {
    std::string name = stem_of(path);
    if (stem_count[lower(name)] > 1) name = path.filename().string();
    if (name.empty() || name == "." || name == "..") name = "input";
    std::string unique = name;
    for (int k = 2; taken.count(lower(unique)) != 0; ++k) unique = fmt::format("{}~{}", name, k);
    taken.insert(lower(unique));
    inputs.push_back({path, unique});
  }
  return inputs;
}

fs::path batch_run_folder(const fs::path& root, const BatchInput& input, const std::vector<Weights>& weights,
                          std::size_t weighting) {
  if (weights.size() == 1) return root / input.name;
  return root / input.name / to_string(weights.at(weighting));
}

const char* to_string(RunStatus status) {
  switch (status) {
    case RunStatus::kPending: return "pending";
    case RunStatus::kOk: return "ok";
    case RunStatus::kNotCertified: return "not-certified";
    case RunStatus::kError: return "error";
  }
  return "?";
}

RunStatus run_status(const fs::path& folder) { return read_folder(folder).status; }

void write_run_error(const fs::path& folder, const fs::path& input, int exit_code, const std::string& message) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create the output folder: {}", folder.string(), ec.message()));
  const Json error = {{"status", "error"}, {"exit_code", exit_code}, {"message", message}, {"input", input.string()}};
  write_file_atomically(folder / kRunErrorFile, dump(error, 2) + "\n");
}

const std::vector<std::string>& summary_columns() {
  static const std::vector<std::string> columns = [] {
    std::vector<std::string> c = {"input", "output", "weights", "status", "exit_code", "message"};
    for (const auto& column : report_columns_before_repair()) c.emplace_back(column.column);
    c.emplace_back("genus_before_repair");
    c.emplace_back("handles_cut");
    c.emplace_back("tunnels_filled");
    for (const auto& column : report_columns_after_repair()) c.emplace_back(column.column);
    for (int k = 0; k < kOctants; ++k) c.push_back(fmt::format("octant_area_percent_{}", k));
    c.emplace_back("octant_rms_deviation_percent");
    c.emplace_back("split_edges");
    for (const char* column : kTimingColumns) c.emplace_back(column);
    c.emplace_back("peak_rss_mb");
    return c;
  }();
  return columns;
}

Json summary_row(const BatchInput& input, Weights weights, const fs::path& root, const fs::path& folder) {
  Json row = Json::object();
  for (const auto& column : summary_columns()) row[column] = nullptr;
  const FolderState state = read_folder(folder);
  row["input"] = input.path.string();
  row["output"] = folder.lexically_relative(root).generic_string();
  row["weights"] = to_string(weights);
  row["status"] = to_string(state.status);
  if (state.status == RunStatus::kPending) return row;
  row["exit_code"] = state.exit_code;
  if (state.status == RunStatus::kError) {
    row["message"] = state.message;
    return row;
  }
  const Json& r = state.report;
  if (state.status == RunStatus::kNotCertified)
    row["message"] = fmt::format("NOT certified: {} folded, {} collapsed triangles, coverage {}",
                                 dump(at(r, {"certificate", "folded"})), dump(at(r, {"certificate", "collapsed"})),
                                 dump(at(r, {"certificate", "coverage"})));
  for (const auto& column : report_columns_before_repair()) row[column.column] = at_path(r, column.path);
  // Meshes are never repaired: their genus is the mesh's. Structures: the outer surface before the
  // handle repair, when the report has it.
  row["genus_before_repair"] = at(r, {"structure"}).is_object() ? at(r, {"structure", "topology_repair", "genus_before"})
                                                                : at(r, {"mesh", "genus"});
  const Json& changes = at(r, {"structure", "topology_repair", "changes"});
  if (changes.is_array()) {
    std::int64_t cuts = 0, fills = 0;
    for (const auto& change : changes) {
      const Json& kind = at(change, {"kind"});
      cuts += kind == "cut";
      fills += kind == "fill";
    }
    row["handles_cut"] = cuts;
    row["tunnels_filled"] = fills;
  }
  for (const auto& column : report_columns_after_repair()) row[column.column] = at_path(r, column.path);
  const Json& octants = at(r, {"distortion", "octant_area_percent"});
  for (int k = 0; k < kOctants; ++k)
    if (octants.is_array() && static_cast<int>(octants.size()) == kOctants)
      row[fmt::format("octant_area_percent_{}", k)] = octants[static_cast<std::size_t>(k)];
  row["octant_rms_deviation_percent"] = at(r, {"distortion", "octant_rms_deviation_percent"});
  const Json& splits = at(r, {"map", "split_edges"});
  if (splits.is_array()) row["split_edges"] = splits.size();
  const Json& timings = at(r, {"timings_seconds"});
  if (timings.is_object()) {
    double total = 0, map = 0;
    for (const auto& [stage, value] : timings.items()) {
      if (!value.is_number()) continue;
      const double seconds = value.get<double>();
      total += seconds;
      if (stage != "read" && stage != "surface" && stage != "simplify" && stage != "prepare" && stage != "metrics")
        map += seconds;
    }
    row["seconds_read"] = at(timings, {"read"});
    row["seconds_surface"] = at(timings, {"surface"});
    row["seconds_simplify"] = at(timings, {"simplify"});
    row["seconds_prepare"] = at(timings, {"prepare"});
    // Sums to the microsecond: their last bits are noise, not information.
    row["seconds_map"] = std::round(map * 1e6) / 1e6;
    row["seconds_metrics"] = at(timings, {"metrics"});
    row["seconds_total"] = std::round(total * 1e6) / 1e6;
  }
  std::ifstream resources(folder / kRunResourcesFile);
  if (resources) {
    const Json parsed = Json::parse(resources, nullptr, false);
    if (parsed.is_object() && parsed.contains("peak_rss_mb")) row["peak_rss_mb"] = parsed["peak_rss_mb"];
  }
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

namespace {

std::string csv_field(const Json& value) {
  if (value.is_null()) return {};
  std::string text = value.is_string() ? value.get<std::string>() : dump(value);
  const bool quote = text.find_first_of(",\"\r\n") != std::string::npos ||
                     (!text.empty() && (text.front() == ' ' || text.back() == ' ' || text.front() == '\t' ||
                                        text.back() == '\t'));
  if (!quote) return text;
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + '"';
}

}  // namespace

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
  write_file_atomically(root / "summary.csv", summary_csv(rows));
  write_file_atomically(root / "summary.jsonl", summary_jsonl(rows));
  return rows;
}

int batch_exit_code(const std::vector<Json>& rows) {
  std::set<int> codes;
  for (const auto& row : rows) {
    const auto status = row.value("status", std::string());
    if (status == "pending") codes.insert(4);
    else if (status == "not-certified") codes.insert(static_cast<int>(ExitCode::kNotCertified));
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

BatchLock::BatchLock(const fs::path& root) {
  std::error_code ec;
  fs::create_directories(root, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create the output folder: {}", root.string(), ec.message()));
  const fs::path lock = root / ".batch.lock";
  descriptor_ = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
  if (descriptor_ < 0)
    throw InputError(fmt::format("{}: cannot create the lock file ({}); check that the output folder is writable",
                                 lock.string(), std::strerror(errno)));
  if (::flock(descriptor_, LOCK_EX | LOCK_NB) != 0) {
    const int error = errno;
    ::close(descriptor_);
    descriptor_ = -1;
    if (error == EWOULDBLOCK)
      throw InputError(fmt::format("{}: another spheremap batch is writing into this folder; wait for it to end, "
                                   "or choose another -o folder",
                                   root.string()));
    throw InputError(fmt::format("{}: cannot lock the output folder ({})", root.string(), std::strerror(error)));
  }
}

BatchLock::~BatchLock() {
  if (descriptor_ >= 0) ::close(descriptor_);  // closing releases the flock
}

void BatchLock::forget_in_child() const noexcept {
  if (descriptor_ >= 0) ::close(descriptor_);  // this process's descriptor only: the parent keeps the lock
}

nlohmann::ordered_json batch_options_json(const BatchOptions& options) {
  const auto& job = options.job;
  Json weights = Json::array();
  for (const Weights w : options.weights) weights.push_back(to_string(w));
  Json radii = nullptr;
  if (job.structure.radii) {
    radii = Json::object();
    for (const auto& [element, radius] : *job.structure.radii) radii[element] = radius;
  }
  return {
      {"weights", weights},
      {"solver", to_string(job.map.solver)},
      {"repair", job.map.repair},
      {"collapse_floor", job.map.collapse_floor},
      {"max_equalizing_rounds", job.map.max_equalizing_rounds},
      {"weld_tolerance", job.prepare.weld_tolerance},
      {"component", job.prepare.component == kComponentLargest  ? Json("largest")
                    : job.prepare.component == kComponentRefuse ? Json("refuse")
                                                                : Json(job.prepare.component)},
      {"ascii", job.ascii},
      {"structure",
       {{"model", job.structure.model},
        {"chains", job.structure.chains},
        {"keep_hydrogens", job.structure.keep_hydrogens},
        {"keep_waters", job.structure.keep_waters},
        {"keep_hetero", job.structure.keep_hetero},
        {"radii", radii}}},
      {"surface",
       {{"probe", job.surface.probe},
        {"grid", job.surface.grid},
        {"carve_cavities", job.surface.carve_cavities},
        {"contour_minimum_fraction", job.surface.contour_minimum_fraction}}},
      {"keep_topology", job.keep_topology},
      {"simplify",
       {{"target_edge_length", job.simplify.target_edge_length},
        {"max_error", job.simplify.max_error},
        {"mesh_files", job.simplify_mesh_files}}},
  };
}

namespace {

// "grid 0.5 (was 2.5), weights [...] (was [...])": the options that differ, for the refusal message.
std::string option_differences(const Json& now, const Json& before, const std::string& prefix = "") {
  std::string text;
  auto add = [&](const std::string& part) { text += (text.empty() ? "" : ", ") + part; };
  if (!now.is_object() || !before.is_object()) {
    if (now != before) add(fmt::format("{} {} (was {})", prefix.empty() ? "options" : prefix, dump(now), dump(before)));
    return text;
  }
  for (const auto& [key, value] : now.items()) {
    const std::string name = prefix.empty() ? key : prefix + "." + key;
    const auto it = before.find(key);
    if (it == before.end()) add(fmt::format("{} {} (not set before)", name, dump(value)));
    else if (value.is_object() && it->is_object()) {
      const auto inner = option_differences(value, *it, name);
      if (!inner.empty()) add(inner);
    } else if (value != *it) add(fmt::format("{} {} (was {})", name, dump(value), dump(*it)));
  }
  for (const auto& [key, value] : before.items())
    if (now.find(key) == now.end()) add(fmt::format("{} no longer set (was {})", prefix.empty() ? key : prefix + "." + key, dump(value)));
  return text;
}

// Throws unless root/batch.json is absent, or has the same options, or options.force. Returns whether
// it must be (re)written, which run_batch does only after --force has cleared the old outputs: a batch
// killed in between must not find old outputs under new options.
bool check_manifest(const fs::path& root, const BatchOptions& options) {
  const fs::path path = root / "batch.json";
  const Json options_now = batch_options_json(options);
  std::error_code ec;
  if (fs::exists(path, ec)) {
    std::string differences;
    try {
      const auto text = read_text(path);
      if (!text) throw std::runtime_error("cannot read it");
      const Json before = Json::parse(*text);
      if (before.value("options", Json()) == options_now) return false;  // same options: nothing to write
      differences = option_differences(options_now, before.value("options", Json::object()));
    } catch (const std::exception& e) {
      differences = fmt::format("its batch.json is unreadable ({})", e.what());
    }
    if (!options.force)
      throw InputError(fmt::format("{}: this folder holds a batch made with other options: {}. Use another -o folder, "
                                   "or --force to redo every input with the new options",
                                   root.string(), differences));
  }
  return true;
}

void write_manifest(const fs::path& root, const BatchOptions& options) {
  const Json manifest = {{"spheremap_version", "0.1.0"}, {"options", batch_options_json(options)}};
  write_file_atomically(root / "batch.json", dump(manifest, 2) + "\n");
}

double seconds_since(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

struct Failure {
  int exit_code = 0;
  std::string message;
};

// Runs the given callable, turning every exception into a Failure (the batch never stops for one input).
template <typename F>
std::optional<Failure> capture(F&& f) {
  try {
    f();
    return std::nullopt;
  } catch (const Error& e) {
    return Failure{static_cast<int>(e.code()), e.what()};
  } catch (const std::bad_alloc&) {
    return Failure{4, "internal error: out of memory; run fewer inputs at once (--jobs) or use a coarser --grid"};
  } catch (const std::exception& e) {
    return Failure{4, fmt::format("internal error: {}", e.what())};
  } catch (...) {
    return Failure{4, "internal error: unknown exception"};
  }
}

}  // namespace

BatchResult run_batch(const fs::path& root, const std::vector<BatchInput>& inputs, const BatchOptions& options,
                      const BatchCallbacks& callbacks) {
  const auto& weights = options.weights;
  if (weights.empty()) throw std::invalid_argument("run_batch: no weights");
  for (std::size_t a = 0; a < weights.size(); ++a)
    for (std::size_t b = a + 1; b < weights.size(); ++b)
      if (weights[a] == weights[b]) throw std::invalid_argument(fmt::format("run_batch: weights {} twice", to_string(weights[a])));
  if (options.jobs < 1) throw std::invalid_argument("run_batch: jobs < 1");
  {
    std::set<std::string> names;
    for (const auto& input : inputs)
      if (!names.insert(lower(input.name)).second)
        throw std::invalid_argument(fmt::format("run_batch: output name '{}' twice", input.name));
  }

  const BatchLock lock(root);
  const bool new_manifest = check_manifest(root, options);
  remove_leftover_temporaries(root, root_file_names());
  for (const auto& input : inputs)
    for (const auto& folder : all_input_folders(root, input)) remove_leftover_temporaries(folder, run_file_names());
  if (options.force) {
    for (const auto& input : inputs)
      for (const auto& folder : all_input_folders(root, input)) clear_run_folder(folder);
  } else if (options.retry_errors) {
    for (const auto& input : inputs)
      for (std::size_t k = 0; k < weights.size(); ++k) {
        const auto folder = batch_run_folder(root, input, weights, k);
        if (run_status(folder) == RunStatus::kError) clear_run_folder(folder);
      }
  }
  if (new_manifest) write_manifest(root, options);

  // From here on the folders say what is to do: the inputs with a pending run.
  const auto started = std::chrono::steady_clock::now();
  BatchProgress progress;
  progress.inputs = inputs.size();
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    bool pending = false, error = false, not_certified = false;
    for (std::size_t k = 0; k < weights.size(); ++k) {
      const auto status = run_status(batch_run_folder(root, inputs[i], weights, k));
      pending |= status == RunStatus::kPending;
      error |= status == RunStatus::kError;
      not_certified |= status == RunStatus::kNotCertified;
    }
    if (pending) {
      todo.push_back(i);
    } else {
      ++progress.already_done;
      progress.errors += error;
      progress.not_certified += not_certified;
    }
  }

  // The work of one input: its pending runs mapped and written, or error.json in each. Never throws;
  // what happened is on disk (the parent of an isolated run reads it from there).
  auto map_input = [&](const BatchInput& input, const std::vector<std::size_t>& pending) {
    std::vector<Weights> pending_weights;
    for (const auto k : pending) pending_weights.push_back(weights[k]);
    std::optional<Failure> failure = capture([&] {
      for (const auto k : pending) clear_run_folder(batch_run_folder(root, input, weights, k));
    });
    std::vector<MapJobResult> results;
    if (!failure) failure = capture([&] { results = run_map_jobs(input.path, options.job, pending_weights); });
    auto record_error = [&](std::size_t k, const Failure& f) {
      // If even error.json cannot be written, the run stays pending (and the batch exits 4).
      capture([&] { write_run_error(batch_run_folder(root, input, weights, k), input.path, f.exit_code, f.message); });
    };
    for (std::size_t j = 0; j < pending.size(); ++j) {
      if (failure) {
        record_error(pending[j], *failure);
        continue;
      }
      MapJobOptions weighted = options.job;
      weighted.map.weights = pending_weights[j];
      const auto written = capture(
          [&] { write_map_outputs(batch_run_folder(root, input, weights, pending[j]), results[j], weighted); });
      results[j] = MapJobResult{};  // free the mesh and the map early
      if (written) record_error(pending[j], *written);
    }
    // Peak memory of the process that mapped this input (meaningful with isolation: one input per process).
    if (!failure && options.isolate) {
      rusage usage{};
      ::getrusage(RUSAGE_SELF, &usage);
      const double megabytes = std::round(static_cast<double>(usage.ru_maxrss) / 1024.0 * 10) / 10;
      for (const auto k : pending) {
        const auto folder = batch_run_folder(root, input, weights, k);
        if (run_status(folder) == RunStatus::kPending || run_status(folder) == RunStatus::kError) continue;
        capture([&] { write_file_atomically(folder / kRunResourcesFile, Json{{"peak_rss_mb", megabytes}}.dump() + "\n"); });
      }
    }
  };

  // In a child process: the forked image has only this thread; it maps, writes and leaves with _exit
  // (no atexit handlers, no flushing of the parent's buffers). It dies with the batch (PDEATHSIG), and
  // ignores Ctrl-C, which the terminal sends to the whole process group: the batch decides.
  auto map_input_in_child = [&](const BatchInput& input, const std::vector<std::size_t>& pending) {
    const pid_t parent = ::getpid();
    const pid_t pid = ::fork();
    if (pid == 0) {
      // A batch killed at once is resumed at once: its lock must not outlive it in a child still dying.
      lock.forget_in_child();
      ::prctl(PR_SET_PDEATHSIG, SIGKILL);
      if (::getppid() != parent) ::_exit(0);
      ::signal(SIGINT, SIG_IGN);
      ::signal(SIGTERM, SIG_DFL);
      map_input(input, pending);
      ::_exit(0);
    }
    if (pid < 0) {
      const Failure f{4, fmt::format("internal error: cannot start a process for this input ({})", std::strerror(errno))};
      for (const auto k : pending)
        capture([&] { write_run_error(batch_run_folder(root, input, weights, k), input.path, f.exit_code, f.message); });
      return;
    }
    int status = 0;
    while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {
    }
    if (!WIFSIGNALED(status)) return;
    // A crash, or the out-of-memory killer (SIGKILL), is this input's error; a termination or interrupt
    // sent to the process group leaves its runs pending, to be redone on resume.
    const int signal = WTERMSIG(status);
    if (signal == SIGTERM || signal == SIGINT || signal == SIGHUP || signal == SIGQUIT) return;
    const Failure f{4, fmt::format("internal error: the process mapping this input died of signal {} ({}){}", signal,
                                   ::strsignal(signal),
                                   signal == SIGKILL ? "; out of memory? run fewer inputs at once (--jobs) or use a "
                                                       "coarser --grid"
                                                     : "")};
    for (const auto k : pending) {
      const auto folder = batch_run_folder(root, input, weights, k);
      if (run_status(folder) == RunStatus::kPending)
        capture([&] { write_run_error(folder, input.path, f.exit_code, f.message); });
    }
  };

  auto run_input = [&](std::size_t index) {
    const BatchInput& input = inputs[index];
    BatchInputOutcome outcome;
    outcome.index = index;
    const auto start = std::chrono::steady_clock::now();
    std::vector<std::size_t> pending;
    for (std::size_t k = 0; k < weights.size(); ++k)
      if (run_status(batch_run_folder(root, input, weights, k)) == RunStatus::kPending) pending.push_back(k);
    if (options.isolate) map_input_in_child(input, pending);
    else map_input(input, pending);
    for (std::size_t k = 0; k < weights.size(); ++k) {
      const FolderState state = read_folder(batch_run_folder(root, input, weights, k));
      outcome.statuses.push_back(state.status);
      if (state.status == RunStatus::kError && outcome.message.empty()) {
        outcome.exit_code = state.exit_code;
        outcome.message = state.message;
      }
    }
    outcome.seconds = seconds_since(start);
    return outcome;
  };

  std::mutex mutex;
  std::condition_variable changed;
  std::deque<BatchInputOutcome> finished;
  std::size_t running = 0, workers_done = 0;
  std::atomic<std::size_t> next{0};
  std::atomic<bool> stopping{false};
  const std::size_t worker_count = std::min<std::size_t>(static_cast<std::size_t>(options.jobs), todo.size());
  auto worker = [&] {
    for (;;) {
      if (stopping.load()) break;
      const std::size_t slot = next.fetch_add(1);
      if (slot >= todo.size()) break;
      {
        const std::lock_guard guard(mutex);
        ++running;
      }
      BatchInputOutcome outcome = run_input(todo[slot]);
      {
        const std::lock_guard guard(mutex);
        --running;
        finished.push_back(std::move(outcome));
      }
      changed.notify_one();
    }
    {
      const std::lock_guard guard(mutex);
      ++workers_done;
    }
    changed.notify_one();
  };

  std::vector<std::thread> threads;
  BatchResult result;
  auto last_summary = std::chrono::steady_clock::now();
  bool finished_since_summary = false;
  try {
    threads.reserve(worker_count);
    for (std::size_t t = 0; t < worker_count; ++t) threads.emplace_back(worker);
    const auto tick = std::chrono::duration<double>(std::max(0.01, callbacks.tick_seconds));
    if (callbacks.on_tick) callbacks.on_tick(progress);
    for (;;) {
      std::deque<BatchInputOutcome> ready;
      bool all_done = false;
      {
        std::unique_lock guard(mutex);
        changed.wait_for(guard, tick, [&] { return !finished.empty() || workers_done == worker_count; });
        ready.swap(finished);
        progress.running = running;
        all_done = workers_done == worker_count;
      }
      progress.elapsed_seconds = seconds_since(started);
      for (const auto& outcome : ready) {
        ++progress.finished;
        finished_since_summary = true;
        progress.errors += std::count(outcome.statuses.begin(), outcome.statuses.end(), RunStatus::kError) > 0;
        progress.not_certified +=
            std::count(outcome.statuses.begin(), outcome.statuses.end(), RunStatus::kNotCertified) > 0;
        if (callbacks.on_finished) callbacks.on_finished(outcome, progress);
      }
      if (!stopping.load() && callbacks.stop && callbacks.stop() == BatchStop::kFinishRunning) {
        stopping.store(true);
        progress.stopping = true;
      }
      if (all_done) break;
      if (callbacks.on_tick) callbacks.on_tick(progress);
      if (finished_since_summary && seconds_since(last_summary) >= 30) {
        capture([&] { write_batch_summary(root, inputs, weights); });
        last_summary = std::chrono::steady_clock::now();
        finished_since_summary = false;
      }
    }
  } catch (...) {
    stopping.store(true);
    for (auto& thread : threads) thread.join();
    throw;
  }
  for (auto& thread : threads) thread.join();
  progress.running = 0;
  progress.elapsed_seconds = seconds_since(started);

  result.rows = write_batch_summary(root, inputs, weights);
  result.exit_code = batch_exit_code(result.rows);
  result.stopped = stopping.load() && std::any_of(result.rows.begin(), result.rows.end(), [](const Json& row) {
                     return row.at("status") == "pending";
                   });
  result.progress = progress;
  return result;
}

}  // namespace spheremap
