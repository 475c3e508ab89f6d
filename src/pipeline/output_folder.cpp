// The output folder of a map run: earlier outputs found, refused or removed.
#include "spheremap/pipeline/output_folder.hpp"

#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <system_error>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/pipeline/map_job.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

bool all_digits(std::string_view text) {
  return !text.empty() && std::all_of(text.begin(), text.end(), [](unsigned char c) { return std::isdigit(c); });
}

bool is_component_folder(const std::string& name) {
  return name.rfind("component-", 0) == 0 && all_digits(name.substr(10));
}

// `NAME.tmp-PID` for a NAME of the outputs: what an atomic write leaves when its process is killed.
bool is_output_temporary(const std::string& name) {
  const auto marker = name.rfind(".tmp-");
  if (marker == std::string::npos || !all_digits(std::string_view(name).substr(marker + 5))) return false;
  const auto& names = map_output_names();
  return std::find(names.begin(), names.end(), name.substr(0, marker)) != names.end();
}

bool is_output_file(const std::string& name) {
  const auto& names = map_output_names();
  return std::find(names.begin(), names.end(), name) != names.end() || is_output_temporary(name);
}

// The nearest existing folder at or above `path` ("." for a relative path with none).
fs::path nearest_existing(const fs::path& path) {
  std::error_code ec;
  for (fs::path p = path; !p.empty(); p = p.parent_path()) {
    if (fs::exists(p, ec)) return p;
    if (p == p.parent_path()) break;
  }
  return ".";
}

}  // namespace

std::vector<std::string> earlier_map_outputs(const fs::path& folder) {
  std::vector<std::string> found;
  std::error_code ec;
  if (!fs::is_directory(folder, ec)) return found;
  for (fs::directory_iterator it(folder, ec), end; !ec && it != end; it.increment(ec)) {
    const std::string name = it->path().filename().string();
    std::error_code type_error;
    if (it->is_directory(type_error) && (is_component_folder(name) || name == kPicturesFolder))
      found.push_back(name + "/");
    else if (is_output_file(name))
      found.push_back(name);
  }
  std::sort(found.begin(), found.end());
  return found;
}

void check_map_output_folder(const fs::path& folder, bool force) {
  std::error_code ec;
  if (fs::exists(folder, ec) && !fs::is_directory(folder, ec))
    throw InputError(
        fmt::format("{}: the output exists and is not a folder (-o names the folder for surface.ply, "
                    "sphere.ply and report.json); give a folder name",
                    folder.string()));
  const fs::path existing = nearest_existing(folder);
  if (!fs::is_directory(existing, ec))
    throw InputError(fmt::format("{}: cannot create the output folder: {} is not a folder; give another -o",
                                 folder.string(), existing.string()));
  if (::access(existing.c_str(), W_OK | X_OK) != 0)
    throw InputError(
        fmt::format("{}: cannot write the output folder: {} is not writable; give another -o or "
                    "check its permissions",
                    folder.string(), existing.string()));
  const auto found = earlier_map_outputs(folder);
  if (found.empty() || force) return;
  constexpr std::size_t kNamed = 6;
  std::string names;
  for (std::size_t k = 0; k < std::min(found.size(), kNamed); ++k) names += (k ? ", " : "") + found[k];
  if (found.size() > kNamed) names += fmt::format(" and {} more", found.size() - kNamed);
  throw InputError(
      fmt::format("{}: the folder already holds the outputs of an earlier run ({}), which would mix "
                  "with this run's. Give another -o folder, or --force to replace them: the earlier "
                  "outputs are removed once the new map is made (other files are kept)",
                  folder.string(), names));
}

void remove_map_outputs(const fs::path& folder) {
  auto found = earlier_map_outputs(folder);
  // report.json first: a folder without it is never taken for a complete run.
  std::stable_partition(found.begin(), found.end(), [](const std::string& name) { return name == kReportFile; });
  for (const auto& name : found) {
    std::error_code ec;
    fs::remove_all(folder / name, ec);
    if (ec)
      throw InputError(fmt::format("{}: cannot remove it ({}); check the permissions of the output folder",
                                   (folder / name).string(), ec.message()));
  }
}

}  // namespace spheremap
