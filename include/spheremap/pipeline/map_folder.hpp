// A finished map output folder read back (stage: pipeline): surface.ply, sphere.ply and report.json as
// `spheremap map` wrote them, for the commands that work on a folder without mapping again (render, view,
// locate).
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spheremap/mesh.hpp"
#include "spheremap/properties/property.hpp"

namespace spheremap {

struct MapFolder {
  std::filesystem::path folder;
  /// surface.ply with its per-vertex attributes; for a structure, also the text provenance of each vertex's
  /// atom joined from atoms.csv by `atomid` (attributes::kChain, kResidueNumber, kInsertionCode, kResidueName,
  /// kAtomName, kElement, kAtomSerial, kModel), as the surface carried it in memory.
  Mesh surface;
  std::vector<Vec3> sphere;  // sphere.ply's positions: the globe superposed on the surface
  nlohmann::json report;     // report.json
  std::string name;          // the input's name without folder and extensions (e.g. "1crn"), for titles
  /// The PLY's `vertex_<name>` values of every property report.json lists, registry order first, each with
  /// the registry's PropertyInfo (a --values column: the report's) and the report's categories and source.
  /// Empty for folders of spheremap before 0.2 (no `properties` block).
  std::vector<SurfaceProperty> properties;
  /// Why the surface has no residues although it is a structure's (atoms.csv missing); empty otherwise.
  std::string no_residues_reason;
};

/// Reads `folder`. Throws InputError naming the file and the fix if the folder or one of its three files is
/// missing or unreadable, if surface.ply and sphere.ply do not have the same vertices and triangles, if
/// atoms.csv (read when surface.ply has `atomid`) lacks a column or a row an `atomid` names, or if report.json
/// lists a property surface.ply does not carry. A structure's folder without atoms.csv reads, without residues
/// (no_residues_reason says why).
MapFolder read_map_folder(const std::filesystem::path& folder);

}  // namespace spheremap
