// The paper's Table 1 from a folder of map runs (stage: reproduction). Reads only the report.json files
// written by `spheremap map` / `spheremap batch`, through pipeline/report.hpp. Figure 4's histograms:
// reproduction/figure4.hpp; its charts: render/figure4.hpp.
#pragma once

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/pipeline/report.hpp"

namespace spheremap {

/// Every file named exactly `name` under `runs_dir`, at any depth (directory symlinks are not
/// followed), sorted by path (byte order), so the result does not depend on the file system's order.
/// Throws InputError if `runs_dir` does not exist or is not a folder, or cannot be listed.
std::vector<std::filesystem::path> find_files_named(const std::filesystem::path& runs_dir, const std::string& name);

/// find_files_named(runs_dir, "report.json"): the runs that produced a map (a failed batch run has
/// `error.json` instead, a folder being written has neither yet). Throws as find_files_named.
std::vector<std::filesystem::path> find_reports(const std::filesystem::path& runs_dir);

/// Table 1's figures for one weighting ("protocol"). Surfaces are the reports of that weighting.
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
  double area_mean_of_means_percent = 0;   // Table 1 "Mean"
  double area_max_of_means_percent = 0;    // Table 1 "(Max)"
  double area_mean_of_maxima_percent = 0;  // mean over surfaces of the per-surface max over triangles
  double area_max_percent = 0;             // max over all triangles of all surfaces
  double angle_mean_of_rms_degrees = 0;    // Table 1 "Mean"
  double angle_max_of_rms_degrees = 0;     // Table 1 "(Max)"
  double angle_mean_of_means_degrees = 0;  // mean over surfaces of the per-surface mean |Δangle|
  double angle_max_degrees = 0;            // max over all corners of all surfaces
  double octant_rms_pooled_percent = 0;    // Table 1 last column
  double octant_rms_mean_percent = 0;      // mean over surfaces of the per-surface octant RMS
  double octant_min_percent = 0, octant_max_percent = 0;
};

/// One summary per weighting, in protocol order: uniform, cotan, mean-value, then any other name
/// alphabetically. Reports are summed in the order given (give them sorted for reproducible last
/// digits). Does not throw (but std::bad_alloc); no reports, no summaries.
std::vector<ProtocolSummary> summarize_protocols(const std::vector<ReportSummary>& reports);

/// The paper's Table 1 rows (77 surfaces, 3,000-6,000 triangles each).
struct PaperRow {
  std::string weights;  // "uniform" or "cotan"
  std::int64_t inverted = 0;
  double percent_correct = 0;
  double area_mean_percent = 0, area_max_percent = 0;
  double angle_mean_degrees = 0, angle_max_degrees = 0;
  double octant_rms_percent = 0;
};
/// The paper's two rows (uniform, cotan), copied verbatim. Does not throw.
const std::vector<PaperRow>& paper_table1();

/// 12345 -> "12,345" (the paper's style for counts). Does not throw (but std::bad_alloc).
std::string with_thousands(std::int64_t n);

/// What Table 1's markdown says besides the protocol summaries.
struct Table1Context {
  std::string runs_dir;  // as the user gave it
  std::int64_t reports_found = 0;
  std::int64_t error_runs = 0;            // error.json files found (failed runs, not in the table)
  std::vector<std::string> figure_notes;  // one bullet each, e.g. which surface Figure 4b shows
  std::vector<std::string> warnings;      // e.g. an input repeated under one weighting
};

/// table1.md: Table 1 with the paper's rows beside ours, the footnotes stating how each column is
/// computed, a details table, and one line per run. Deterministic (fixed decimals).
/// Precondition: `summaries` are summarize_protocols(reports). Does not throw (but std::bad_alloc).
std::string table1_markdown(const std::vector<ProtocolSummary>& summaries, const std::vector<ReportSummary>& reports,
                            const Table1Context& context);

/// Inputs that appear more than once under the same weighting (a rerun in the same tree), as messages.
std::vector<std::string> duplicate_runs(const std::vector<ReportSummary>& reports);

}  // namespace spheremap
