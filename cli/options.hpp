// Command-line options shared by several subcommands, registered once: the map options (map, batch), the
// structure and surface options (map, batch, surface), and the small pieces every command has.
#pragma once

#include <string>
#include <vector>

#include <CLI/CLI.hpp>

#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/pipeline/presets.hpp"

namespace spheremap::cli {

/// Structure and surface options shared by map, surface and batch. Call add() before parsing and
/// apply() after: apply() fills `options` (chains, hetero, radius table, --preset, simplification).
struct StructureCliOptions {
  std::string chains, radii_file, preset;
  bool no_hetero = false, cavities = false, keep_hydrogens = false, no_hydrogens = false, strict = false;
  double mesh_edge = -1, mesh_tolerance = -1;  // -1: not given
  CLI::App* command = nullptr;
  /// `scope` kMap: map and batch (simplification before the map, on by default for structures);
  /// kSurface: the surface command (simplification only when --mesh-edge is given).
  void add(CLI::App* command, MapJobOptions& options, PresetScope scope = PresetScope::kMap);
  /// Throws InputError for an unreadable radius table.
  void apply(MapJobOptions& options) const;

 private:
  PresetScope scope_ = PresetScope::kMap;
};

/// How many weightings --weights takes: one (map) or a comma-separated list (batch).
enum class WeightingCount { kOne, kSeveral };

/// The options of a map job, shared by map and batch: --weights, --solver, --component,
/// --weld-tolerance, --collapse-floor, --ascii, --equalizing-rounds, --no-repair and the structure
/// options. Call add() before parsing and apply() after.
/// The surface properties' options (map and batch): --properties, --color, --values, and the electrostatics'
/// --charges, --potential-map, --apbs, --temperature, --dielectric, --potential-offset, --force-field.
struct PropertyCliOptions {
  std::string properties, charges, potential_map, dielectric, force_field = "amber";
  bool apbs = false;
  std::vector<std::string> values;
  void add(CLI::App* command, MapJobOptions& job);
  /// Fills job.properties. Throws InputError for a bad --dielectric, --charges or option combination.
  void apply(MapJobOptions& job) const;
};

struct MapCliOptions {
  MapJobOptions job;
  std::string weights = "uniform", solver = "direct", component, objective = "paper";
  bool no_repair = false;
  StructureCliOptions structure;
  PropertyCliOptions properties;
  void add(CLI::App* command, WeightingCount count);
  /// Fills `job` (with the first weighting of weightings()). Throws InputError for a bad --weights or
  /// --component, or an unreadable radius table.
  void apply();
  /// --weights as a list: each once. Throws InputError for an unknown or repeated name, or none.
  std::vector<Weights> weightings() const;
};

/// Harmonic weights by their CLI name (uniform, cotan, mean-value). Throws InputError for another name.
Weights parse_weights(const std::string& name);

/// --component: 'largest' or a component number. Throws InputError for anything else.
ComponentChoice parse_component(const std::string& text);

/// Bounds of a real option's range: whether the low end itself is allowed.
enum class LowEnd { kIncluded, kExcluded };

/// A validator for a real-valued option: a finite decimal number in [low, high] ((low, high] with
/// LowEnd::kExcluded); nan, inf and anything that is not a number are refused with a message that says
/// what is expected (`unit` is appended to the numbers, e.g. " Å"). Does not throw (its check returns the
/// message CLI11 shows).
CLI::Validator finite_number(double low, double high, LowEnd low_end = LowEnd::kIncluded, const std::string& unit = "");

/// -o,--output (required).
void add_output_option(CLI::App* command, std::string& output, const std::string& description);
/// -q,--quiet.
void add_quiet_flag(CLI::App* command, bool& quiet, const std::string& description = "Print nothing on success");

}  // namespace spheremap::cli
