// The subcommands of the spheremap CLI, one file each; main.cpp only registers and dispatches them.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "spheremap/pipeline/map_job.hpp"

namespace spheremap::cli {

/// A registered subcommand and what runs it after parsing; `run` returns the process exit code and may
/// throw spheremap::Error (main turns it into a message and the error's exit code).
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

Command add_map_command(CLI::App& app);
Command add_surface_command(CLI::App& app);
Command add_generate_command(CLI::App& app);
Command add_batch_command(CLI::App& app);
Command add_table_command(CLI::App& app);

/// Structure and surface options shared by map, surface and batch. Call add() before parsing and
/// apply() after: apply() fills `options` (chains, hetero, radius table, --preset).
struct StructureCliOptions {
  std::string chains, radii_file, preset;
  bool no_hetero = false, cavities = false;
  double mesh_edge = -1, mesh_tolerance = -1;  // -1: not given
  CLI::App* command = nullptr;
  /// `for_map`: map and batch (simplification before the map, on by default for structures); otherwise
  /// the surface command (simplification only when --mesh-edge is given).
  void add(CLI::App* command, MapJobOptions& options, bool for_map = true);
  void apply(MapJobOptions& options) const;
};

/// The paper's settings for reproduction (--preset paper): probe 1.8 Å, Bondi radii, grid 2.5 Å
/// (3,000-8,000 triangles for the paper's proteins with our contouring).
inline constexpr double kPaperProbe = 1.8;
inline constexpr double kPaperGrid = 2.5;
// The paper contours the binary inside/outside grid at 1/2: every vertex at the midpoint of its edge.
inline constexpr double kPaperContourFraction = 0.5;

/// A quick look (--preset fast): an 8k-atom structure to a certified map in under a second on two cores
/// (BENCHMARKS.md). A 1 Å grid (areas 1-1.5% below MSMS's; see BENCHMARKS.md), about 2 Å edges on the
/// mapped mesh (a 40,000 Å² surface: about 23,000 vertices) and at most 4 equalizing rounds: on the 16 of
/// the 88 structures whose plain map collapses (the others are not re-weighted), they take the median
/// area distortion from 134% to 57% for at most 0.42 s more (GroEL 1.6 s; BENCHMARKS.md, "Ninth session").
inline constexpr double kFastGrid = 1.0;
inline constexpr double kFastMeshEdge = 2.0;
inline constexpr int kFastEqualizingRounds = 4;

/// --equalizing-rounds (map and batch): MapOptions::max_equalizing_rounds, 0 or more.
void add_equalizing_rounds_option(CLI::App* command, MapOptions& options);

/// Harmonic weights by their CLI name (uniform, cotan, mean-value).
Weights parse_weights(const std::string& name);

}  // namespace spheremap::cli
