// Reading a map output folder back (see map_folder.hpp).
#include "spheremap/pipeline/map_folder.hpp"

#include <fstream>
#include <sstream>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/pipeline/map_job.hpp"

namespace spheremap {
namespace {

const char* const kFix = "give the folder that `spheremap map INPUT -o FOLDER` wrote (or map again)";

std::string input_name(const std::string& input) {
  std::filesystem::path name = std::filesystem::path(input).filename();
  if (name.extension() == ".gz") name = name.stem();
  return name.stem().string();
}

}  // namespace

MapFolder read_map_folder(const std::filesystem::path& folder) {
  std::error_code error;
  if (!std::filesystem::is_directory(folder, error))
    throw InputError(fmt::format("{}: no such folder; {}", folder.string(), kFix));
  for (const char* file : {kSurfaceFile, kSphereFile, kReportFile})
    if (!std::filesystem::is_regular_file(folder / file, error))
      throw InputError(fmt::format("{}: the folder has no {}, so it is not a finished map; {}", folder.string(), file,
                                   kFix));
  MapFolder map;
  map.folder = folder;
  map.surface = read_ply_mesh(folder / kSurfaceFile);
  const Mesh sphere = read_ply_mesh(folder / kSphereFile);
  if (sphere.vertex_count() != map.surface.vertex_count() || sphere.triangles != map.surface.triangles)
    throw InputError(fmt::format("{}: {} and {} do not have the same vertices and triangles (from two runs?); {}",
                                 folder.string(), kSurfaceFile, kSphereFile, kFix));
  map.sphere = sphere.positions;
  std::ifstream in(folder / kReportFile);
  std::stringstream text;
  text << in.rdbuf();
  try {
    map.report = nlohmann::json::parse(text.str());
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON ({}); {}", (folder / kReportFile).string(), e.what(), kFix));
  }
  const auto input = map.report.find("input");
  map.name = input != map.report.end() && input->is_string() ? input_name(input->get<std::string>())
                                                             : folder.filename().string();
  if (map.name.empty()) map.name = "map";
  return map;
}

}  // namespace spheremap
