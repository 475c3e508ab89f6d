// Table 1 of Rahi & Sharp from report.json files: collection, aggregation, markdown.
#include "spheremap/reproduction/table1.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <system_error>

#include <fmt/format.h>

#include "spheremap/error.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

int protocol_rank(const std::string& weights) {
  if (weights == "uniform") return 0;
  if (weights == "cotan") return 1;
  if (weights == "mean-value") return 2;
  return 3;
}

std::string protocol_title(const std::string& weights) {
  if (weights == "uniform") return "Uniform weighting";
  if (weights == "cotan") return "Cotangent weighting";
  if (weights == "mean-value") return "Mean-value weighting";
  return weights + " weighting";
}

std::string percent_of(std::int64_t part, std::int64_t whole) {
  if (whole == 0) return "–";
  // Never "100%" unless all, never "0%" unless none.
  double percent = std::round(100.0 * static_cast<double>(part) / static_cast<double>(whole));
  if (part < whole) percent = std::min(percent, 99.0);
  if (part > 0) percent = std::max(percent, 1.0);
  return fmt::format("{:.0f}%", percent);
}

std::string sorted_key(const std::string& weights) { return fmt::format("{}:{}", protocol_rank(weights), weights); }

}  // namespace

std::string with_thousands(std::int64_t n) {
  const std::string digits = std::to_string(n < 0 ? -n : n);
  std::string out;
  const auto len = static_cast<int>(digits.size());
  for (int i = 0; i < len; ++i) {
    if (i > 0 && (len - i) % 3 == 0) out += ',';
    out += digits[static_cast<std::size_t>(i)];
  }
  return n < 0 ? "-" + out : out;
}

std::vector<fs::path> find_reports(const fs::path& runs_dir) { return find_files_named(runs_dir, kReportFile); }

std::vector<fs::path> find_files_named(const fs::path& runs_dir, const std::string& name) {
  std::error_code error;
  const auto status = fs::status(runs_dir, error);
  if (!fs::exists(status))
    throw InputError(
        fmt::format("{}: the folder does not exist; give the output folder of spheremap batch (or a "
                    "folder holding outputs of spheremap map)",
                    runs_dir.string()));
  if (!fs::is_directory(status))
    throw InputError(fmt::format("{}: not a folder; give the output folder of spheremap batch", runs_dir.string()));
  std::vector<fs::path> found;
  fs::recursive_directory_iterator it(runs_dir, fs::directory_options::none, error);
  if (error) throw InputError(fmt::format("{}: cannot list the folder ({})", runs_dir.string(), error.message()));
  for (const fs::recursive_directory_iterator end; it != end; it.increment(error)) {
    if (error) throw InputError(fmt::format("{}: cannot list the folder ({})", runs_dir.string(), error.message()));
    if (it->path().filename() == name && it->is_regular_file(error)) found.push_back(it->path());
  }
  if (error) throw InputError(fmt::format("{}: cannot list the folder ({})", runs_dir.string(), error.message()));
  std::sort(found.begin(), found.end(), [](const fs::path& a, const fs::path& b) { return a.string() < b.string(); });
  return found;
}

std::vector<ProtocolSummary> summarize_protocols(const std::vector<ReportSummary>& reports) {
  std::map<std::string, std::vector<const ReportSummary*>> by_protocol;
  for (const auto& r : reports) by_protocol[sorted_key(r.weights)].push_back(&r);
  std::vector<ProtocolSummary> out;
  for (const auto& [key, runs] : by_protocol) {
    ProtocolSummary s;
    s.weights = runs.front()->weights;
    s.surfaces = static_cast<std::int64_t>(runs.size());
    s.triangles_min = std::numeric_limits<std::int64_t>::max();
    s.octant_min_percent = std::numeric_limits<double>::infinity();
    s.octant_max_percent = -std::numeric_limits<double>::infinity();
    double octant_square_sum = 0;
    for (const ReportSummary* r : runs) {
      s.triangles_total += r->triangles;
      s.triangles_min = std::min(s.triangles_min, r->triangles);
      s.triangles_max = std::max(s.triangles_max, r->triangles);
      s.folded_total += r->certificate.folded;
      s.collapsed_total += r->certificate.collapsed;
      s.surfaces_without_folds += r->certificate.folded == 0;
      s.surfaces_without_collapse += r->certificate.collapsed == 0;
      s.surfaces_certified += r->certificate.certified;
      s.plain_folded_total += r->plain_certificate.folded;
      s.plain_collapsed_total += r->plain_certificate.collapsed;
      s.plain_surfaces_without_folds += r->plain_certificate.folded == 0;
      s.plain_surfaces_certified += r->plain_certificate.certified;
      s.area_mean_of_means_percent += r->distortion.area_distortion_mean_percent;
      s.area_max_of_means_percent = std::max(s.area_max_of_means_percent, r->distortion.area_distortion_mean_percent);
      s.area_mean_of_maxima_percent += r->distortion.area_distortion_max_percent;
      s.area_max_percent = std::max(s.area_max_percent, r->distortion.area_distortion_max_percent);
      s.angle_mean_of_rms_degrees += r->distortion.angle_distortion_rms_degrees;
      s.angle_max_of_rms_degrees = std::max(s.angle_max_of_rms_degrees, r->distortion.angle_distortion_rms_degrees);
      s.angle_mean_of_means_degrees += r->distortion.angle_distortion_mean_degrees;
      s.angle_max_degrees = std::max(s.angle_max_degrees, r->distortion.angle_distortion_max_degrees);
      s.octant_rms_mean_percent += r->distortion.octant_rms_deviation_percent;
      for (const double a : r->distortion.octant_area_percent) {
        octant_square_sum += (a - 12.5) * (a - 12.5);
        s.octant_min_percent = std::min(s.octant_min_percent, a);
        s.octant_max_percent = std::max(s.octant_max_percent, a);
      }
    }
    const auto n = static_cast<double>(s.surfaces);
    s.area_mean_of_means_percent /= n;
    s.area_mean_of_maxima_percent /= n;
    s.angle_mean_of_rms_degrees /= n;
    s.angle_mean_of_means_degrees /= n;
    s.octant_rms_mean_percent /= n;
    s.octant_rms_pooled_percent = std::sqrt(octant_square_sum / (8 * n));
    out.push_back(s);
  }
  return out;
}

const std::vector<PaperRow>& paper_table1() {
  static const std::vector<PaperRow> rows = {
      {"uniform", 0, 100, 104, 470, 25.0, 29.3, 4.9},
      {"cotan", 204, 55, 86, 446, 10.6, 19.6, 4.3},
  };
  return rows;
}

std::vector<std::string> duplicate_runs(const std::vector<ReportSummary>& reports) {
  std::map<std::pair<std::string, std::string>, std::vector<std::string>> seen;
  for (const auto& r : reports) seen[{sorted_key(r.weights), r.input}].push_back(r.source.string());
  std::vector<std::string> out;
  for (const auto& [key, reports] : seen)
    if (reports.size() > 1)
      out.push_back(fmt::format("{} appears {} times under weights {} ({}): each counts as a surface", key.second,
                                reports.size(), key.first.substr(key.first.find(':') + 1), fmt::join(reports, ", ")));
  return out;
}

namespace {

// The protocols of our summaries and of the paper's rows, in protocol order.
std::vector<std::string> protocol_order(const std::vector<ProtocolSummary>& summaries) {
  std::vector<std::string> order;
  for (const auto& s : summaries) order.push_back(s.weights);
  for (const auto& p : paper_table1())
    if (std::find(order.begin(), order.end(), p.weights) == order.end()) order.push_back(p.weights);
  std::stable_sort(order.begin(), order.end(),
                   [](const std::string& a, const std::string& b) { return sorted_key(a) < sorted_key(b); });
  return order;
}

std::string paper_row(const PaperRow& p) {
  return fmt::format(
      "| {} | Rahi & Sharp | 77 | 3,000–6,000 | {} ({:.0f}%) | – | {:.0f}% ({:.0f}%) | {:.1f}° "
      "({:.1f}°) | {:.1f}% |\n",
      protocol_title(p.weights), with_thousands(p.inverted), p.percent_correct, p.area_mean_percent, p.area_max_percent,
      p.angle_mean_degrees, p.angle_max_degrees, p.octant_rms_percent);
}

std::string our_row(const ProtocolSummary& s) {
  return fmt::format(
      "| {} | **spheremap** | {} | {}–{} | {} ({}) | {} ({}) | {:.0f}% ({:.0f}%) | {:.1f}° "
      "({:.1f}°) | {:.1f}% |\n",
      protocol_title(s.weights), s.surfaces, with_thousands(s.triangles_min), with_thousands(s.triangles_max),
      with_thousands(s.plain_folded_total), percent_of(s.plain_surfaces_without_folds, s.surfaces),
      with_thousands(s.folded_total), percent_of(s.surfaces_certified, s.surfaces), s.area_mean_of_means_percent,
      s.area_max_of_means_percent, s.angle_mean_of_rms_degrees, s.angle_max_of_rms_degrees,
      s.octant_rms_pooled_percent);
}

std::string table1_section(const std::vector<ProtocolSummary>& summaries) {
  std::string md = "## Table 1\n\n";
  md +=
      "| Mapping protocol | Source | Surfaces | Triangles per surface | # inverted triangles, plain algorithm "
      "(% surfaces correct) <sup>a</sup> | # inverted triangles, final map (% surfaces certified) <sup>b</sup> | "
      "Triangle area distortion, mean (max) <sup>c</sup> | Triangle angle distortion, mean (max) <sup>d</sup> | "
      "RMS deviation in octant area from ideal of 12.5% <sup>e</sup> |\n";
  md += "|---|---|--:|--:|--:|--:|--:|--:|--:|\n";
  for (const auto& weights : protocol_order(summaries)) {
    for (const auto& p : paper_table1())
      if (p.weights == weights) md += paper_row(p);
    for (const auto& s : summaries)
      if (s.weights == weights) md += our_row(s);
  }
  return md + "\n";
}

std::string footnotes() {
  std::string md;
  md +=
      "How each column is computed (our reading of the paper, whose Table 1 gives no formulas; its rows are "
      "copied verbatim, its 77 surfaces had 3,000–6,000 triangles each):\n\n";
  md +=
      "- <sup>a</sup> **Plain algorithm**: `plain_algorithm_certificate` of each report, i.e. the paper's "
      "algorithm without spheremap's repair — the figure comparable with the paper's. Inverted = folded "
      "triangles (orientation of the three image points ≤ 0, decided exactly), summed over the surfaces; "
      "% correct = share of surfaces with none.\n";
  md +=
      "- <sup>b</sup> **Final map**: `certificate` of each report, after re-weighting and untangling (unless "
      "the run used `--no-repair`). Certified = no folded triangle, no collapsed triangle and coverage 1; "
      "collapsed counts are in the details below.\n";
  md +=
      "- <sup>c</sup> **Area distortion**: per triangle |r − 1| with r = (solid angle / 4π) / (surface area / "
      "total area); per surface the mean over its triangles (`area_distortion_mean_percent`); **mean** = mean "
      "over the surfaces, **(max)** = largest per-surface mean. The paper's text (\"the average area "
      "distortion is about 100%, with a maximum triangle area distortion of about fourfold\") also allows "
      "(max) = mean over surfaces of each surface's worst triangle: that figure, and the worst triangle of "
      "all, are in the details.\n";
  md +=
      "- <sup>d</sup> **Angle distortion**: per triangle corner |angle on the sphere − angle on the surface|; "
      "per surface the RMS over its corners (`angle_distortion_rms_degrees`: the paper's text calls its figure "
      "\"the root mean square change in angle ... 25°\" and \"a rms angle distortion of 10.6° (Table 1)\"); "
      "**mean** = mean over surfaces, **(max)** = largest per-surface RMS. (Max) cannot be a maximum over "
      "corners, which is far above the paper's 29.3°.\n";
  md +=
      "- <sup>e</sup> **Octant area**: per surface, the % of the surface area whose image (triangle centroid "
      "direction, after superposition) lies in each octant of the sphere; the column is the RMS of (octant % − "
      "12.5) over all 8 × surfaces octants pooled (\"most octants have area 12.5 ± 5%\").\n";
  md +=
      "- Distortion columns describe the final map; where repair changed nothing they are those of the plain "
      "algorithm's map.\n\n";
  return md;
}

std::string details_section(const std::vector<ProtocolSummary>& summaries) {
  std::string md = "## Details\n\n";
  md +=
      "| Protocol | Triangles (total) | Plain: folded / surfaces with folds / collapsed / certified | "
      "Final: folded / collapsed / certified | Area: mean of per-surface max (max triangle) | "
      "Angle: mean of per-surface mean (max corner) | Octants: mean per-surface RMS (min–max octant) |\n";
  md += "|---|--:|--:|--:|--:|--:|--:|\n";
  for (const auto& s : summaries)
    md += fmt::format(
        "| {} | {} | {} / {} / {} / {} of {} | {} / {} / {} of {} | {:.0f}% ({:.0f}%) | {:.1f}° "
        "({:.1f}°) | {:.1f}% ({:.1f}–{:.1f}%) |\n",
        protocol_title(s.weights), with_thousands(s.triangles_total), with_thousands(s.plain_folded_total),
        s.surfaces - s.plain_surfaces_without_folds, with_thousands(s.plain_collapsed_total),
        s.plain_surfaces_certified, s.surfaces, with_thousands(s.folded_total), with_thousands(s.collapsed_total),
        s.surfaces_certified, s.surfaces, s.area_mean_of_maxima_percent, s.area_max_percent,
        s.angle_mean_of_means_degrees, s.angle_max_degrees, s.octant_rms_mean_percent, s.octant_min_percent,
        s.octant_max_percent);
  return md + "\n";
}

// A section of bullets, or nothing without any.
std::string bullets_section(const std::string& title, const std::vector<std::string>& bullets) {
  if (bullets.empty()) return {};
  std::string md = "## " + title + "\n\n";
  for (const auto& b : bullets) md += "- " + b + "\n";
  return md + "\n";
}

std::string runs_section(const std::vector<ReportSummary>& reports, const std::string& runs_dir) {
  std::string md = "## Runs\n\n";
  md +=
      "| Report | Input | Weights | Repair | Triangles | Plain folded | Plain collapsed | Folded | Collapsed | "
      "Certified | Area mean (max) | Angle RMS (max) | Octant RMS |\n";
  md += "|---|---|---|---|--:|--:|--:|--:|--:|---|--:|--:|--:|\n";
  std::vector<const ReportSummary*> sorted;
  for (const auto& r : reports) sorted.push_back(&r);
  std::stable_sort(sorted.begin(), sorted.end(), [](const ReportSummary* a, const ReportSummary* b) {
    return sorted_key(a->weights) < sorted_key(b->weights);
  });
  for (const ReportSummary* r : sorted) {
    const fs::path relative = r->source.lexically_relative(runs_dir);
    const DistortionMetrics& d = r->distortion;
    md += fmt::format(
        "| `{}` | {} | {} | {} | {} | {} | {} | {} | {} | {} | {:.0f}% ({:.0f}%) | {:.1f}° ({:.1f}°) "
        "| {:.1f}% |\n",
        (relative.empty() ? r->source : relative).string(), fs::path(r->input).filename().string(), r->weights,
        r->repair ? "yes" : "no", with_thousands(r->triangles), r->plain_certificate.folded,
        r->plain_certificate.collapsed, r->certificate.folded, r->certificate.collapsed,
        r->certificate.certified ? "yes" : "**no**", d.area_distortion_mean_percent, d.area_distortion_max_percent,
        d.angle_distortion_rms_degrees, d.angle_distortion_max_degrees, d.octant_rms_deviation_percent);
  }
  return md;
}

}  // namespace

std::string table1_markdown(const std::vector<ProtocolSummary>& summaries, const std::vector<ReportSummary>& reports,
                            const Table1Context& context) {
  std::string md = "# Table 1 and Figure 4 (Rahi & Sharp), reproduced by spheremap\n\n";
  md += fmt::format(
      "Runs: every `report.json` under `{}` ({} found), grouped by `options.weights`{}. "
      "Written by `spheremap table`.\n\n",
      context.runs_dir, context.reports_found,
      context.error_runs == 0
          ? std::string()
          : fmt::format("; {} failed run(s) (`error.json`, no map) not counted", context.error_runs));
  md += table1_section(summaries);
  md += footnotes();
  md += details_section(summaries);
  md += bullets_section("Figure 4", context.figure_notes);
  md += bullets_section("Warnings", context.warnings);
  md += runs_section(reports, context.runs_dir);
  return md;
}

}  // namespace spheremap
