// Batch inputs: arguments (files, folders, glob patterns, lists) expanded into files, and their output names.
#include "spheremap/pipeline/batch_inputs.hpp"

#include <glob.h>

#include <algorithm>
#include <map>
#include <set>
#include <sstream>
#include <system_error>

#include <fmt/format.h>

#include "detail.hpp"
#include "spheremap/error.hpp"
#include "spheremap/pipeline/molecular_surface.hpp"

namespace spheremap {
namespace {

using namespace pipeline_detail;

constexpr int kMaxListDepth = 8;

bool has_glob_characters(const std::string& text) { return text.find_first_of("*?[") != std::string::npos; }

void expand_argument(const std::string& argument, const fs::path& base, int depth, std::vector<fs::path>& out);

void expand_list(const fs::path& list, int depth, std::vector<fs::path>& out) {
  if (depth >= kMaxListDepth)
    throw InputError(
        fmt::format("{}: lists include lists more than {} levels deep (a list including itself?); "
                    "flatten the lists",
                    list.string(), kMaxListDepth));
  const auto text = read_text(list);
  std::error_code ec;
  if (!text || fs::is_directory(list, ec))
    throw InputError(fmt::format(
        "{}: cannot read this list of inputs; check the path (a list holds one input per line)", list.string()));
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
  if (ec)
    throw InputError(
        fmt::format("{}: cannot list this folder ({}); check its permissions", folder.string(), ec.message()));
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
    if (lower(path.extension().string()) == ".txt")
      expand_list(path, depth, out);
    else
      out.push_back(path);
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
      if (fs::is_directory(match, ec))
        expand_folder(match, out);
      else if (lower(match.extension().string()) == ".txt")
        expand_list(match, depth, out);
      else
        out.push_back(match);
    }
  } else {
    out.push_back(path);
  }
}

void expand_argument(const std::string& argument, const fs::path& base, int depth, std::vector<fs::path>& out) {
  if (argument.empty()) return;
  fs::path path = argument[0] == '@' ? fs::path(argument.substr(1)) : fs::path(argument);
  if (path.is_relative()) path = base / path;
  if (argument[0] == '@')
    expand_list(path, depth, out);
  else
    expand_path(path, depth, out);
}

}  // namespace

const std::vector<std::string>& batch_root_file_names() {
  static const std::vector<std::string> names = {kSummaryCsvFile, kSummaryJsonlFile, kBatchManifestFile};
  return names;
}

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
    throw InputError(
        fmt::format("no input files in '{}': folders give their .obj .off .ply .stl .pdb .ent .cif "
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
  for (const auto& name : batch_root_file_names()) ++stem_count[name];
  for (const auto& path : paths) ++stem_count[lower(stem_of(path))];
  std::vector<BatchInput> inputs;
  std::set<std::string> taken(batch_root_file_names().begin(), batch_root_file_names().end());
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

}  // namespace spheremap
