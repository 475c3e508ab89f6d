// A finished map output folder read back (stage: pipeline): surface.ply, sphere.ply and report.json as
// `spheremap map` wrote them, for the commands that work on a folder without mapping again (render, view,
// locate).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spheremap/mesh.hpp"

namespace spheremap {

struct MapFolder {
  std::filesystem::path folder;
  Mesh surface;              // surface.ply with its per-vertex attributes
  std::vector<Vec3> sphere;  // sphere.ply's positions: the globe superposed on the surface
  nlohmann::json report;     // report.json
  std::string name;          // the input's name without folder and extensions (e.g. "1crn"), for titles
};

/// Reads `folder`. Throws InputError naming the file and the fix if the folder or one of its three files is
/// missing or unreadable, or if surface.ply and sphere.ply do not have the same vertices and triangles.
MapFolder read_map_folder(const std::filesystem::path& folder);

}  // namespace spheremap
