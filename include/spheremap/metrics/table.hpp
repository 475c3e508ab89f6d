// The paper's Table 1 and Figure 4 from a folder of map runs (stage: metrics). Reads only the
// report.json files (and one surface.ply) written by `spheremap map` / `spheremap batch`.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "spheremap/render/plot.hpp"

namespace spheremap {

/// One mapped surface under one weighting: the figures Table 1 needs, from its report.json.
struct RunRecord {
  std::filesystem::path report;  // the report.json it came from
  std::string input;             // report "input": the structure or mesh file
  std::string weights;           // report "options.weights": uniform, cotan or mean-value
  bool repair = true;            // report "options.repair" (false: the run used --no-repair)
  std::int64_t triangles = 0;    // mesh.triangles
  // The final map (after repair, unless --no-repair): certificate.*
  bool certified = false;
  std::int64_t folded = 0, collapsed = 0;
  // The paper's algorithm alone: plain_algorithm_certificate.*
  bool plain_certified = false;
  std::int64_t plain_folded = 0, plain_collapsed = 0;
  // distortion.* of the final map (README, "What the report means")
  double area_distortion_mean_percent = 0, area_distortion_max_percent = 0;
  double angle_distortion_mean_degrees = 0, angle_distortion_rms_degrees = 0, angle_distortion_max_degrees = 0;
  std::array<double, 8> octant_area_percent{};
  double octant_rms_deviation_percent = 0;
};

/// The record of a parsed report. `source` names the file in messages.
/// Throws InputError naming `source` and the first missing or mistyped field.
RunRecord run_record_from_json(const nlohmann::json& report, const std::filesystem::path& source);

/// Reads and parses one report.json. Throws InputError if the file cannot be read, is not JSON, or
/// lacks a field (as run_record_from_json).
RunRecord read_run_record(const std::filesystem::path& report_json);

/// Every file named exactly `name` under `runs_dir`, at any depth (directory symlinks are not
/// followed), sorted by path (byte order), so the result does not depend on the file system's order.
/// Throws InputError if `runs_dir` does not exist or is not a folder, or cannot be listed.
std::vector<std::filesystem::path> find_files_named(const std::filesystem::path& runs_dir, const std::string& name);

/// find_files_named(runs_dir, "report.json"): the runs that produced a map (a failed batch run has
/// `error.json` instead, a folder being written has neither yet).
std::vector<std::filesystem::path> find_reports(const std::filesystem::path& runs_dir);

/// Table 1's figures for one weighting ("protocol"). Surfaces are the records of that weighting.
/// The paper's columns are read as follows (its text, section 3: "the average area distortion is about
/// 100%, with a maximum ... of about fourfold"; "the root mean square change in angle is ... 25°"; "most
/// octants have area 12.5±5%"):
/// - area: per surface the mean over triangles of |r - 1| (report area_distortion_mean_percent); Mean
///   and Max are the mean and the maximum of that over the surfaces;
/// - angle: per surface the RMS over corners of the angle change (angle_distortion_rms_degrees); Mean
///   and Max over the surfaces (a maximum over corners could not be the paper's 29.3°);
/// - octants: RMS of (octant % - 12.5) over all 8 x surfaces octants pooled.
struct ProtocolSummary {
  std::string weights;
  std::int64_t surfaces = 0;
  std::int64_t triangles_total = 0, triangles_min = 0, triangles_max = 0;
  // Final map.
  std::int64_t folded_total = 0, collapsed_total = 0;
  std::int64_t surfaces_without_folds = 0, surfaces_without_collapse = 0, surfaces_certified = 0;
  // Plain algorithm (the paper's "# inverted triangles (% surfaces correct)").
  std::int64_t plain_folded_total = 0, plain_collapsed_total = 0;
  std::int64_t plain_surfaces_without_folds = 0, plain_surfaces_certified = 0;
  // Distortion of the final maps.
  double area_mean_of_means_percent = 0;  // Table 1 "Mean"
  double area_max_of_means_percent = 0;   // Table 1 "(Max)"
  double area_mean_of_maxima_percent = 0; // mean over surfaces of the per-surface max over triangles
  double area_max_percent = 0;            // max over all triangles of all surfaces
  double angle_mean_of_rms_degrees = 0;   // Table 1 "Mean"
  double angle_max_of_rms_degrees = 0;    // Table 1 "(Max)"
  double angle_mean_of_means_degrees = 0; // mean over surfaces of the per-surface mean |Δangle|
  double angle_max_degrees = 0;           // max over all corners of all surfaces
  double octant_rms_pooled_percent = 0;   // Table 1 last column
  double octant_rms_mean_percent = 0;     // mean over surfaces of the per-surface octant RMS
  double octant_min_percent = 0, octant_max_percent = 0;
};

/// Protocol order: uniform, cotan, mean-value, then any other name alphabetically.
/// Records are summed in the order given (give them sorted for reproducible last digits).
std::vector<ProtocolSummary> summarize_protocols(const std::vector<RunRecord>& records);

/// The paper's Table 1 rows (77 surfaces, 3,000-6,000 triangles each).
struct PaperRow {
  std::string weights;  // "uniform" or "cotan"
  std::int64_t inverted = 0;
  double percent_correct = 0;
  double area_mean_percent = 0, area_max_percent = 0;
  double angle_mean_degrees = 0, angle_max_degrees = 0;
  double octant_rms_percent = 0;
};
const std::vector<PaperRow>& paper_table1();

/// A histogram with its bins as chart categories.
struct Histogram {
  std::vector<double> edges;          // bins [edges[i], edges[i+1]); the last one may be +inf (overflow)
  std::vector<std::int64_t> counts;   // one per bin
  std::vector<std::string> labels;    // one per bin, as drawn under the bar
};

/// Figure 4a: octant areas (%) of every record in `records` (8 each), in bins 3% wide centred on
/// 12.5 ± 3k like the paper's (labelled by their centres: ..., 6.5, 9.5, 12.5, ...), from the bin of
/// the smallest value (at least [-1, 2)) to that of the largest, and at least 5-8 to 32-35 % as in the paper.
Histogram octant_histogram(const std::vector<RunRecord>& records);

/// Figure 4b: each triangle's area as % of the surface's mean triangle area, in bins 10% wide labelled by
/// their upper edge as in the paper (the bar "10" holds [0, 10) %), up to 230% or beyond to the largest
/// value, with one overflow bar "≥300" when a value reaches 300%.
/// Precondition: areas non-empty with a positive sum; throws std::invalid_argument otherwise.
Histogram triangle_area_histogram(const std::vector<double>& triangle_areas);

/// The areas of the triangles of a mesh file (polygons must be triangles). Throws InputError as
/// read_polygon_soup does, or if a face is not a triangle.
std::vector<double> triangle_areas_of_file(const std::filesystem::path& mesh_file);

/// The surface Figure 4b shows: among the distinct inputs (the first record of each, in the order
/// given), the one with the median triangle count (ties by input name; with an even count the lower of
/// the two middle ones). Returns the index of its record. Throws std::invalid_argument if records is empty.
std::size_t typical_surface(const std::vector<RunRecord>& records);

/// Figure 4a as a chart: `histogram` from octant_histogram of the `surfaces` runs with `weights`.
BarChart figure4a_chart(const Histogram& histogram, const std::string& weights, std::int64_t surfaces);

/// Figure 4b as a chart: `histogram` from triangle_area_histogram of the surface `name` (`triangles`
/// triangles), the typical one of `distinct_surfaces`.
BarChart figure4b_chart(const Histogram& histogram, const std::string& name, std::int64_t triangles,
                        std::size_t distinct_surfaces);

/// 12345 -> "12,345" (the paper's style for counts).
std::string with_thousands(std::int64_t n);

/// What Table 1's markdown says besides the protocol summaries.
struct Table1Context {
  std::string runs_dir;                          // as the user gave it
  std::int64_t reports_found = 0;
  std::int64_t error_runs = 0;                   // error.json files found (failed runs, not in the table)
  std::vector<std::string> figure_notes;         // one bullet each, e.g. which surface Figure 4b shows
  std::vector<std::string> warnings;             // e.g. an input repeated under one weighting
};

/// table1.md: Table 1 with the paper's rows beside ours, the footnotes stating how each column is
/// computed, a details table, and one line per run. Deterministic (fixed decimals).
std::string table1_markdown(const std::vector<ProtocolSummary>& summaries, const std::vector<RunRecord>& records,
                            const Table1Context& context);

/// Inputs that appear more than once under the same weighting (a rerun in the same tree), as messages.
std::vector<std::string> duplicate_runs(const std::vector<RunRecord>& records);

}  // namespace spheremap
