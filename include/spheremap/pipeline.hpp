// The `map` job end to end: file -> prepared mesh -> sphere map -> metrics -> outputs.
#pragma once

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "spheremap/metrics/distortion.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/prepare.hpp"

namespace spheremap {

struct MapJobOptions {
  PrepareOptions prepare;
  /// map.poles, if set, are vertex indices of the input (0-based, in file order), translated through
  /// welding; run_map_job throws InputError if one does not exist or was dropped.
  MapOptions map;
  bool ascii = false;  // ASCII PLY outputs (full precision) instead of binary
};

struct MapJobResult {
  std::filesystem::path input;
  PreparedMesh prepared;
  SphereMap map;
  DistortionMetrics metrics;
  double read_seconds = 0, prepare_seconds = 0, metrics_seconds = 0;
};

/// Reads, prepares, maps and measures. Throws InputError (unreadable input) or MeshRefused (a mesh that
/// cannot be mapped); a map that is not certified is returned normally (see map.certificate).
MapJobResult run_map_job(const std::filesystem::path& input, const MapJobOptions& options);

/// Same, from a mesh in memory (`name` is used in messages and the report).
MapJobResult run_map_job(const Mesh& mesh, const std::string& name, const MapJobOptions& options);

/// The report as JSON (every figure defined in the README).
nlohmann::json make_report(const MapJobResult& result, const MapJobOptions& options);

/// A few lines for a terminal.
std::string summary_text(const MapJobResult& result);

/// Writes `surface.ply`, `sphere.ply` and `report.json` into `directory` (created if missing), each
/// atomically. Both PLY files have the same vertices in the same order and the same triangles, with
/// per-vertex `theta`, `phi` and `input_vertex` (index in the input file) plus the input's attributes.
/// Throws InputError if a file cannot be written.
void write_map_outputs(const std::filesystem::path& directory, const MapJobResult& result,
                       const MapJobOptions& options);

}  // namespace spheremap
