// report.json (stage: pipeline): the only place that knows its keys. make_report writes it; read_report
// reads it back into ReportSummary, for the batch summary (pipeline/summary.hpp) and the reproduction of
// the paper's Table 1 (reproduction/table1.hpp).
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spheremap/metrics/distortion.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/properties/property.hpp"
#include "spheremap/sphere/map.hpp"

namespace spheremap {

/// The report as JSON (every figure defined in docs/report.md). Deterministic but for
/// `timings_seconds`. Precondition: `result` and `options` are those of one run_map_job*.
/// Does not throw (but std::bad_alloc).
nlohmann::json make_report(const MapJobResult& result, const MapJobOptions& options);

/// A certificate as report.json records it (`certificate`, `plain_algorithm_certificate`).
struct ReportCertificate {
  bool certified = false;
  std::int64_t folded = 0, collapsed = 0, decided_exactly = 0;
  double coverage = 0, min_area_ratio = 0;
};

/// `structure.topology_repair`, with its `changes` counted by kind.
struct ReportTopologyRepair {
  std::string method;
  std::int64_t rounds = 0, samples_changed = 0, genus_before = 0;
  double volume_changed = 0, area_before = 0, area_after = 0, area_changed_percent = 0;
  std::int64_t handles_cut = 0, tunnels_filled = 0;  // changes of kind "cut" and "fill"
};

/// `structure` (a structure file's molecular surface).
struct ReportStructure {
  std::int64_t atoms = 0;
  double probe = 0, grid = 0;
  std::vector<std::string> warnings;  // `structure.warnings`: about the input file
  ReportTopologyRepair topology_repair;
};

/// `simplification` (when the surface was simplified before the map).
struct ReportSimplification {
  std::int64_t vertices_before = 0;
  double area_before = 0, area_after = 0, max_vertex_distance = 0;
};

/// The figures of one report.json that the batch summary and Table 1 use.
struct ReportSummary {
  std::filesystem::path source;  // the report.json it came from (as given to read_report)
  std::string input;             // `input`: the structure or mesh file
  std::string weights;           // `options.weights`: uniform, cotan or mean-value
  bool repair = true;            // `options.repair` (false: the run used --no-repair)
  // `mesh`: the mapped mesh, and what preparation found in the input.
  std::int64_t vertices = 0, triangles = 0, input_vertices = 0, input_faces = 0, components = 0, genus = 0;
  std::optional<ReportStructure> structure;            // null for a mesh file
  std::optional<ReportSimplification> simplification;  // null when not simplified
  // `map`
  std::string map_method, solver;
  std::int64_t north_pole = 0, south_pole = 0, pole_graph_distance = 0;
  std::int64_t reweighting_rounds = 0, untangling_moves = 0;
  std::int64_t split_edges = 0;  // the length of `map.split_edges`
  double superposition_rmsd = 0;
  ReportCertificate certificate;        // the final map
  ReportCertificate plain_certificate;  // the paper's algorithm alone
  DistortionMetrics distortion;         // of the final map
  std::vector<std::string> properties;  // the keys of `properties`, in report order
  std::string electrostatics_source;    // `properties.electrostatics.source`; empty without electrostatics
  /// `timings_seconds`: its numbers in key order, as make_report writes them (`surface_stages`, an
  /// object, left out).
  std::vector<StageTime> timings;
};

/// The summary of a parsed report.json; `source` names it in messages. A number JSON could not hold
/// (NaN, infinite: written as null) reads as NaN.
/// Throws InputError naming `source` and the first field that is missing or of the wrong type (the file
/// is not a report of this version of spheremap map).
ReportSummary read_report(const nlohmann::json& report, const std::filesystem::path& source);

/// A property as report.json's `properties` block describes it: what a reader needs to show the PLY's
/// `vertex_<name>` values (the --values columns are in no registry, and categories such as the chain names
/// belong to one surface).
struct ReportProperty {
  PropertyInfo info;   // name (the key), unit, scale, default_range, categories
  std::string source;  // `source`
};

/// The `properties` block of a parsed report.json, in key order; empty when the report has none (spheremap
/// before 0.2). Throws InputError naming `source` and the field if an entry lacks `unit`, `scale` or `source`,
/// names an unknown scale, or has a `default_range` that is not null or two numbers.
std::vector<ReportProperty> read_report_properties(const nlohmann::json& report, const std::filesystem::path& source);

/// Reads, parses and summarizes one report.json.
/// Throws InputError if the file cannot be read, is not JSON, or lacks a field (as read_report).
ReportSummary read_report_file(const std::filesystem::path& report_json);

}  // namespace spheremap
