// spheremap table RUNS_DIR: the paper's Table 1 (table1.md) and Figure 4 (PNG and SVG) from map runs.
#include <algorithm>
#include <cctype>
#include <iostream>
#include <limits>
#include <set>

#include <fmt/format.h>

#include "commands.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/atomic_file.hpp"
#include "spheremap/pipeline/run_folder.hpp"
#include "spheremap/render/figure4.hpp"
#include "spheremap/render/plot.hpp"
#include "spheremap/reproduction/figure4.hpp"
#include "spheremap/reproduction/table1.hpp"

namespace spheremap::cli {
namespace {

namespace fs = std::filesystem;

struct TableCommand {
  std::string runs_dir, output;
  bool quiet = false;

  static constexpr const char* kName = "table";
  static constexpr const char* kDescription =
      "The paper's Table 1 (table1.md) and Figure 4 (figure4a-WEIGHTS and figure4b, PNG and SVG) from every "
      "report.json under RUNS_DIR (output of spheremap batch, or of several spheremap map runs)";

  void add(CLI::App* command) {
    command->add_option("runs_dir", runs_dir, "Folder searched recursively for report.json")->required();
    command->add_option("-o,--output", output, "Folder for table1.md and the figures (default: RUNS_DIR)");
    add_quiet_flag(command, quiet);
  }
  int run() const;
};

// Protocol names become file names: keep letters, digits and '-'.
std::string file_safe(const std::string& name) {
  std::string out;
  for (const char c : name) out += (std::isalnum(static_cast<unsigned char>(c)) || c == '-') ? c : '_';
  return out.empty() ? "unnamed" : out;
}

void write_chart(const fs::path& output, const std::string& stem, const BarChart& chart) {
  write_file_atomically(output / (stem + ".svg"), bar_chart_svg(chart));
  write_png(output / (stem + ".png"), render_bar_chart(chart));
}

// Figure 4a, one per protocol. Returns the files written.
std::vector<std::string> write_figure4a(const fs::path& output, const std::vector<ReportSummary>& reports,
                                        const std::vector<ProtocolSummary>& summaries, Table1Context& context) {
  std::vector<std::string> written;
  for (const auto& summary : summaries) {
    std::vector<ReportSummary> of_protocol;
    for (const auto& r : reports)
      if (r.weights == summary.weights) of_protocol.push_back(r);
    const std::string stem = "figure4a-" + file_safe(summary.weights);
    write_chart(output, stem, figure4a_chart(octant_histogram(of_protocol), summary.weights, summary.surfaces));
    written.push_back(stem + ".png/.svg");
    context.figure_notes.push_back(fmt::format(
        "`{}.png` / `.svg` (Figure 4a): frequency distribution of the octant areas of the {} surfaces mapped "
        "with {} weights ({} octants), in bins 3% wide centred on 12.5 ± 3k as the paper's axis labels "
        "(6.5, 9.5, ... 33.5) suggest; the bar labelled 12.5 holds [11, 14)%.",
        stem, summary.surfaces, summary.weights, 8 * summary.surfaces));
  }
  return written;
}

// Figure 4b: the triangle areas of the surface with the median triangle count. Returns the files written.
std::vector<std::string> write_figure4b(const fs::path& output, const std::vector<ReportSummary>& reports,
                                        Table1Context& context) {
  const ReportSummary& typical = reports[typical_surface(reports)];
  const fs::path surface_file = typical.source.parent_path() / kSurfaceFile;
  std::set<std::string> inputs;
  for (const auto& r : reports) inputs.insert(r.input);
  const std::size_t distinct = inputs.size();
  if (!fs::exists(surface_file)) {
    context.warnings.push_back(
        fmt::format("Figure 4b not drawn: {} is missing (the typical surface, median triangle count, is {})",
                    surface_file.string(), typical.input));
    return {};
  }
  const Histogram h = triangle_area_histogram(triangle_areas_of_file(surface_file));
  const std::string name = fs::path(typical.input).filename().string();
  write_chart(output, "figure4b", figure4b_chart(h, name, typical.triangles, distinct));
  context.figure_notes.push_back(fmt::format(
      "`figure4b.png` / `.svg` (Figure 4b): frequency distribution of the triangle areas of `{}` ({} "
      "triangles, from `{}`), as % of that surface's mean triangle area, in bins 10% wide labelled by "
      "their upper edge as in the paper (the bar labelled 10 holds [0, 10)%, i.e. triangles at least "
      "ten-fold smaller than the mean){}. It is the surface with the median triangle count among the {} "
      "distinct inputs (lower median; ties by name); the surface does not depend on the weighting.",
      typical.input, with_thousands(typical.triangles), surface_file.string(),
      h.edges.back() == std::numeric_limits<double>::infinity() ? "; the last bar holds every triangle of 300% or more"
                                                                : "",
      distinct));
  return {"figure4b.png/.svg"};
}

void print_summaries(const fs::path& runs_dir, const fs::path& output, std::size_t reports,
                     const std::vector<ProtocolSummary>& summaries, const Table1Context& context,
                     const std::vector<std::string>& written) {
  std::string per_protocol;
  for (const auto& summary : summaries)
    per_protocol += fmt::format("{}{}: {}", per_protocol.empty() ? "" : ", ", summary.weights, summary.surfaces);
  std::cout << fmt::format(
      "{}: {} report.json found ({}); {} error.json (failed runs) and folders "
      "without report.json are not in the table\n",
      runs_dir.string(), reports, per_protocol, context.error_runs);
  for (const auto& summary : summaries)
    std::cout << fmt::format(
        "  {}: plain algorithm {} folded ({} of {} surfaces correct); final {} folded, {} of {} certified; "
        "area {:.0f}% ({:.0f}%), angle RMS {:.1f}° ({:.1f}°), octant RMS {:.1f}%\n",
        summary.weights, summary.plain_folded_total, summary.plain_surfaces_without_folds, summary.surfaces,
        summary.folded_total, summary.surfaces_certified, summary.surfaces, summary.area_mean_of_means_percent,
        summary.area_max_of_means_percent, summary.angle_mean_of_rms_degrees, summary.angle_max_of_rms_degrees,
        summary.octant_rms_pooled_percent);
  std::cout << fmt::format("  wrote {} and {}\n", (output / "table1.md").string(), fmt::join(written, ", "));
}

int TableCommand::run() const {
  const fs::path runs = runs_dir;
  const std::vector<fs::path> found = find_reports(runs);
  if (found.empty())
    throw InputError(
        fmt::format("{}: no report.json found (searched every subfolder); run spheremap batch "
                    "or spheremap map into this folder first",
                    runs.string()));
  std::vector<ReportSummary> reports;
  reports.reserve(found.size());
  for (const auto& report : found) reports.push_back(read_report_file(report));

  const fs::path output_dir = output.empty() ? runs : fs::path(output);
  std::error_code error;
  fs::create_directories(output_dir, error);
  if (error)
    throw InputError(fmt::format("{}: cannot create the output folder: {}", output_dir.string(), error.message()));

  const auto summaries = summarize_protocols(reports);
  Table1Context context;
  context.runs_dir = runs.string();
  context.reports_found = static_cast<std::int64_t>(found.size());
  context.error_runs = static_cast<std::int64_t>(find_files_named(runs, kRunErrorFile).size());
  context.warnings = duplicate_runs(reports);
  std::vector<std::string> written = write_figure4a(output_dir, reports, summaries, context);
  for (auto& file : write_figure4b(output_dir, reports, context)) written.push_back(std::move(file));

  write_file_atomically(output_dir / "table1.md", table1_markdown(summaries, reports, context));
  for (const auto& w : context.warnings) std::cerr << "spheremap: warning: " << w << "\n";
  if (!quiet) print_summaries(runs, output_dir, found.size(), summaries, context, written);
  return 0;
}

}  // namespace

Command add_table_command(CLI::App& app) { return make_command<TableCommand>(app); }

}  // namespace spheremap::cli
