// Run folders: where each run of a batch writes, and what a folder says about its run.
#include "spheremap/pipeline/run_folder.hpp"

#include <algorithm>
#include <cctype>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "detail.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"

namespace spheremap {
namespace {

using namespace pipeline_detail;

constexpr Weights kAllWeights[] = {Weights::kUniform, Weights::kCotangent, Weights::kMeanValue};

// `name` is `<one of known>.tmp-<digits>`: what write_file_atomically leaves behind when killed.
bool is_leftover_temporary(const std::string& name, const std::vector<std::string>& known) {
  const auto marker = name.rfind(".tmp-");
  if (marker == std::string::npos || marker + 5 == name.size()) return false;
  if (!std::all_of(name.begin() + static_cast<std::ptrdiff_t>(marker) + 5, name.end(),
                   [](unsigned char c) { return std::isdigit(c); }))
    return false;
  return std::find(known.begin(), known.end(), name.substr(0, marker)) != known.end();
}

RunFolder error_state(std::string message) {
  RunFolder state;
  state.status = RunStatus::kError;
  state.exit_code = 4;
  state.message = std::move(message);
  return state;
}

RunFolder read_report_of(const fs::path& folder) {
  const fs::path path = folder / kRunReportFile;
  RunFolder state;
  try {
    const auto text = read_text(path);
    if (!text) throw std::runtime_error("cannot read it");
    state.report = read_report(nlohmann::json::parse(*text), path);
  } catch (const InputError& e) {
    return error_state(fmt::format("{}; rerun with --force", e.what()));
  } catch (const std::exception& e) {
    return error_state(fmt::format("{}: unreadable ({}); rerun with --force", path.string(), e.what()));
  }
  const bool certified = state.report->certificate.certified;
  state.status = certified ? RunStatus::kOk : RunStatus::kNotCertified;
  state.exit_code = certified ? 0 : static_cast<int>(ExitCode::kNotCertified);
  // Optional: its column is empty without it.
  if (const auto resources = read_text(folder / kRunResourcesFile)) {
    const Json parsed = Json::parse(*resources, nullptr, false);
    if (parsed.is_object() && parsed.contains("peak_rss_mb") && parsed["peak_rss_mb"].is_number())
      state.peak_rss_mb = parsed["peak_rss_mb"].get<double>();
  }
  return state;
}

RunFolder read_error_of(const fs::path& folder) {
  const fs::path path = folder / kRunErrorFile;
  RunFolder state;
  state.status = RunStatus::kError;
  try {
    const auto text = read_text(path);
    if (!text) throw std::runtime_error("cannot read it");
    const Json error = Json::parse(*text);
    state.exit_code = error.at("exit_code").get<int>();
    state.message = error.at("message").get<std::string>();
  } catch (const std::exception& e) {
    state.exit_code = 4;
    state.message = fmt::format("{}: unreadable ({}); rerun with --retry-errors", path.string(), e.what());
  }
  return state;
}

}  // namespace

fs::path batch_run_folder(const fs::path& root, const BatchInput& input, const std::vector<Weights>& weights,
                          std::size_t weighting) {
  if (weights.size() == 1) return root / input.name;
  return root / input.name / to_string(weights.at(weighting));
}

std::vector<fs::path> all_input_folders(const fs::path& root, const BatchInput& input) {
  std::vector<fs::path> folders = {root / input.name};
  for (const Weights w : kAllWeights) folders.push_back(root / input.name / to_string(w));
  return folders;
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

const std::vector<std::string>& run_file_names() {
  static const std::vector<std::string> names = [] {
    std::vector<std::string> all = map_output_names();
    all.insert(all.end(), {kRunErrorFile, kRunResourcesFile});
    return all;
  }();
  return names;
}

RunFolder read_run_folder(const fs::path& folder) {
  std::error_code ec;
  if (fs::exists(folder / kRunReportFile, ec)) return read_report_of(folder);
  if (fs::exists(folder / kRunErrorFile, ec)) return read_error_of(folder);
  return {};
}

RunStatus run_status(const fs::path& folder) { return read_run_folder(folder).status; }

void write_run_error(const fs::path& folder, const fs::path& input, int exit_code, const std::string& message) {
  std::error_code ec;
  fs::create_directories(folder, ec);
  if (ec) throw InputError(fmt::format("{}: cannot create the output folder: {}", folder.string(), ec.message()));
  const Json error = {{"status", "error"}, {"exit_code", exit_code}, {"message", message}, {"input", input.string()}};
  write_file_atomically(folder / kRunErrorFile, dump(error, 2) + "\n");
}

void write_run_resources(const fs::path& folder, double peak_rss_mb) {
  write_file_atomically(folder / kRunResourcesFile, Json{{"peak_rss_mb", peak_rss_mb}}.dump() + "\n");
}

void remove_leftover_temporaries(const fs::path& folder, const std::vector<std::string>& known) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  std::vector<fs::path> doomed;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec))
    if (is_leftover_temporary(it->path().filename().string(), known)) doomed.push_back(it->path());
  for (const auto& path : doomed) fs::remove(path, ec);
}

void clear_run_folder(const fs::path& folder) {
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return;
  remove_leftover_temporaries(folder, run_file_names());
  // report.json first: from then on the folder is pending whatever happens next.
  std::vector<std::string> names = run_file_names();
  std::stable_partition(names.begin(), names.end(), [](const std::string& name) { return name == kRunReportFile; });
  for (const auto& name : names) {
    fs::remove(folder / name, ec);
    if (ec)
      throw InputError(fmt::format("{}: cannot remove it ({}); check the permissions of the output folder",
                                   (folder / name).string(), ec.message()));
  }
}

}  // namespace spheremap
