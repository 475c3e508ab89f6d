// Table 1 and Figure 4 from report.json files: hand-made reports with numbers checked by hand.
#include "spheremap/reproduction/table1.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "../test_support.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/pipeline/report.hpp"
#include "spheremap/reproduction/figure4.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

struct Fake {
  std::string input, weights;
  std::int64_t triangles;
  bool certified;
  std::int64_t folded, collapsed;
  bool plain_certified;
  std::int64_t plain_folded, plain_collapsed;
  double area_mean, area_max, angle_mean, angle_rms, angle_max;
  std::array<double, 8> octants;
};

// A complete report (make_report's schema, of an empty result) with the figures the table reads set.
nlohmann::json fake_report(const Fake& f) {
  double square = 0;
  for (const double a : f.octants) square += (a - 12.5) * (a - 12.5);
  nlohmann::json report = make_report(MapJobResult{}, MapJobOptions{});
  report["input"] = f.input;
  report["options"]["weights"] = f.weights;
  report["mesh"]["vertices"] = f.triangles / 2 + 2;
  report["mesh"]["triangles"] = f.triangles;
  report["certificate"].update({{"certified", f.certified}, {"folded", f.folded}, {"collapsed", f.collapsed}});
  report["plain_algorithm_certificate"].update(
      {{"certified", f.plain_certified}, {"folded", f.plain_folded}, {"collapsed", f.plain_collapsed}});
  report["distortion"].update({{"area_distortion_mean_percent", f.area_mean},
                               {"area_distortion_max_percent", f.area_max},
                               {"angle_distortion_mean_degrees", f.angle_mean},
                               {"angle_distortion_rms_degrees", f.angle_rms},
                               {"angle_distortion_max_degrees", f.angle_max},
                               {"octant_area_percent", std::vector<double>(f.octants.begin(), f.octants.end())},
                               {"octant_rms_deviation_percent", std::sqrt(square / 8)}});
  return report;
}

using testing_support::run_cli;
using testing_support::slurp;
using testing_support::write_text;

// Three surfaces under uniform weights, one under cotan, a folder without report and a temporary file.
//   a: 100 triangles, plain 2 folded, final certified; area 100 (400); angle mean 20, RMS 25, max 90;
//      octants 10, 15, 12.5 x 6
//   b: 300 triangles, everything clean; area 50 (200); angle 10, 15, 60; octants 12.5 x 8
//   c: 200 triangles, plain 1 folded 3 collapsed, final 1 folded 3 collapsed (not certified); area 30
//      (900); angle 30, 35, 120; octants 20, 5, 12.5 x 6
class Table : public testing_support::FolderTest {
 protected:
  void SetUp() override {
    FolderTest::SetUp();
    root_ = folder_;
    runs_ = root_ / "runs";
    const std::array<double, 8> clean{12.5, 12.5, 12.5, 12.5, 12.5, 12.5, 12.5, 12.5};
    write_report("c/uniform", {"/data/c.pdb",
                               "uniform",
                               200,
                               false,
                               1,
                               3,
                               false,
                               1,
                               3,
                               30,
                               900,
                               30,
                               35,
                               120,
                               {20, 5, 12.5, 12.5, 12.5, 12.5, 12.5, 12.5}});
    write_report("a/uniform", {"/data/a.pdb",
                               "uniform",
                               100,
                               true,
                               0,
                               0,
                               false,
                               2,
                               0,
                               100,
                               400,
                               20,
                               25,
                               90,
                               {10, 15, 12.5, 12.5, 12.5, 12.5, 12.5, 12.5}});
    write_report("b/uniform", {"/data/b.pdb", "uniform", 300, true, 0, 0, true, 0, 0, 50, 200, 10, 15, 60, clean});
    write_report("a/cotan", {"/data/a.pdb", "cotan", 100, true, 0, 0, false, 7, 1, 80, 300, 8, 9, 50, clean});
    fs::create_directories(runs_ / "failed" / "uniform");             // an error run: no report.json
    write_text(runs_ / "b" / "uniform" / "report.json.tmp-99", "{");  // a write in progress
    // The typical surface (median triangle count: a 100, c 200, b 300) is c: triangle areas 1, 1, 2, 4
    // (mean 2): 50%, 50%, 100%, 200% of the mean.
    // Right triangles at the origin with legs (1, 2), (1, 2), (2, 2), (4, 2).
    Mesh surface;
    surface.positions = {{0, 0, 0}, {1, 0, 0}, {0, 2, 0}, {0, 0, 2}, {0, 0, 4}};
    surface.triangles = {{0, 1, 2}, {0, 1, 3}, {0, 2, 3}, {0, 4, 2}};
    write_ply(runs_ / "c" / "uniform" / "surface.ply", surface);
  }

  void write_report(const std::string& folder, const Fake& fake) {
    write_text(runs_ / folder / "report.json", fake_report(fake).dump(2));
  }

  std::vector<ReportSummary> records() {
    std::vector<ReportSummary> out;
    for (const auto& path : find_reports(runs_)) out.push_back(read_report_file(path));
    return out;
  }

  fs::path root_, runs_;
};

TEST_F(Table, FindsEveryReportSortedAndIgnoresTheRest) {
  const auto found = find_reports(runs_);
  ASSERT_EQ(found.size(), 4u);
  EXPECT_EQ(found[0], runs_ / "a" / "cotan" / "report.json");
  EXPECT_EQ(found[1], runs_ / "a" / "uniform" / "report.json");
  EXPECT_EQ(found[2], runs_ / "b" / "uniform" / "report.json");
  EXPECT_EQ(found[3], runs_ / "c" / "uniform" / "report.json");
}

TEST_F(Table, MissingFolderOrFileIsRefusedEmptyFolderHasNone) {
  EXPECT_THROW(find_reports(root_ / "nowhere"), InputError);
  EXPECT_THROW(find_reports(runs_ / "a" / "cotan" / "report.json"), InputError);
  EXPECT_TRUE(find_reports(runs_ / "failed").empty());
}

TEST_F(Table, ReadsTheFieldsOfAReport) {
  const ReportSummary c = read_report_file(runs_ / "c" / "uniform" / "report.json");
  EXPECT_EQ(c.source, runs_ / "c" / "uniform" / "report.json");
  EXPECT_EQ(c.input, "/data/c.pdb");
  EXPECT_EQ(c.weights, "uniform");
  EXPECT_TRUE(c.repair);
  EXPECT_EQ(c.triangles, 200);
  EXPECT_FALSE(c.certificate.certified);
  EXPECT_EQ(c.certificate.folded, 1);
  EXPECT_EQ(c.certificate.collapsed, 3);
  EXPECT_EQ(c.plain_certificate.folded, 1);
  EXPECT_EQ(c.plain_certificate.collapsed, 3);
  EXPECT_DOUBLE_EQ(c.distortion.area_distortion_max_percent, 900);
  EXPECT_DOUBLE_EQ(c.distortion.angle_distortion_rms_degrees, 35);
  EXPECT_DOUBLE_EQ(c.distortion.octant_area_percent[1], 5);
  EXPECT_DOUBLE_EQ(c.distortion.octant_rms_deviation_percent, 3.75);
}

TEST_F(Table, BrokenReportsNameTheFileAndTheField) {
  auto report = fake_report({"x.pdb", "uniform", 10, true, 0, 0, true, 0, 0, 1, 2, 3, 4, 5, {}});
  report["distortion"].erase("angle_distortion_rms_degrees");
  write_text(runs_ / "x" / "report.json", report.dump());
  try {
    read_report_file(runs_ / "x" / "report.json");
    FAIL() << "no throw";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("distortion.angle_distortion_rms_degrees"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find((runs_ / "x" / "report.json").string()), std::string::npos) << e.what();
  }
  report = fake_report({"x.pdb", "uniform", 10, true, 0, 0, true, 0, 0, 1, 2, 3, 4, 5, {}});
  report["mesh"]["triangles"] = "many";
  write_text(runs_ / "x" / "report.json", report.dump());
  EXPECT_THROW(read_report_file(runs_ / "x" / "report.json"), InputError);
  write_text(runs_ / "x" / "report.json", "{\"input\": ");
  EXPECT_THROW(read_report_file(runs_ / "x" / "report.json"), InputError);
}

TEST_F(Table, AggregatesTable1ByHand) {
  const auto summaries = summarize_protocols(records());
  ASSERT_EQ(summaries.size(), 2u);
  EXPECT_EQ(summaries[0].weights, "uniform");  // uniform before cotan, whatever the paths
  EXPECT_EQ(summaries[1].weights, "cotan");
  const ProtocolSummary& u = summaries[0];
  EXPECT_EQ(u.surfaces, 3);
  EXPECT_EQ(u.triangles_total, 600);
  EXPECT_EQ(u.triangles_min, 100);
  EXPECT_EQ(u.triangles_max, 300);
  EXPECT_EQ(u.plain_folded_total, 3);
  EXPECT_EQ(u.plain_surfaces_without_folds, 1);
  EXPECT_EQ(u.plain_collapsed_total, 3);
  EXPECT_EQ(u.plain_surfaces_certified, 1);
  EXPECT_EQ(u.folded_total, 1);
  EXPECT_EQ(u.collapsed_total, 3);
  EXPECT_EQ(u.surfaces_without_folds, 2);
  EXPECT_EQ(u.surfaces_certified, 2);
  EXPECT_DOUBLE_EQ(u.area_mean_of_means_percent, 60);  // (100 + 50 + 30) / 3
  EXPECT_DOUBLE_EQ(u.area_max_of_means_percent, 100);
  EXPECT_DOUBLE_EQ(u.area_mean_of_maxima_percent, 500);  // (400 + 200 + 900) / 3
  EXPECT_DOUBLE_EQ(u.area_max_percent, 900);
  EXPECT_DOUBLE_EQ(u.angle_mean_of_rms_degrees, 25);  // (25 + 15 + 35) / 3
  EXPECT_DOUBLE_EQ(u.angle_max_of_rms_degrees, 35);
  EXPECT_DOUBLE_EQ(u.angle_mean_of_means_degrees, 20);
  EXPECT_DOUBLE_EQ(u.angle_max_degrees, 120);
  // Pooled over 24 octants: 2.5² + 2.5² + 7.5² + 7.5² = 125.
  EXPECT_NEAR(u.octant_rms_pooled_percent, std::sqrt(125.0 / 24), 1e-12);
  EXPECT_NEAR(u.octant_rms_mean_percent, (1.25 + 0 + 3.75) / 3, 1e-12);
  EXPECT_DOUBLE_EQ(u.octant_min_percent, 5);
  EXPECT_DOUBLE_EQ(u.octant_max_percent, 20);
  const ProtocolSummary& c = summaries[1];
  EXPECT_EQ(c.surfaces, 1);
  EXPECT_EQ(c.plain_folded_total, 7);
  EXPECT_EQ(c.plain_surfaces_without_folds, 0);
  EXPECT_DOUBLE_EQ(c.octant_rms_pooled_percent, 0);
}

TEST_F(Table, MarkdownHasThePaperRowsAndOurs) {
  const auto recs = records();
  Table1Context context;
  context.runs_dir = runs_.string();
  context.reports_found = 4;
  const std::string md = table1_markdown(summarize_protocols(recs), recs, context);
  EXPECT_NE(md.find("| Uniform weighting | Rahi & Sharp | 77 | 3,000–6,000 | 0 (100%) | – | 104% (470%) | 25.0° "
                    "(29.3°) | 4.9% |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| Cotangent weighting | Rahi & Sharp | 77 | 3,000–6,000 | 204 (55%) | – | 86% (446%) | 10.6° "
                    "(19.6°) | 4.3% |"),
            std::string::npos)
      << md;
  EXPECT_NE(md.find("| Uniform weighting | **spheremap** | 3 | 100–300 | 3 (33%) | 1 (67%) | 60% (100%) | 25.0° "
                    "(35.0°) | 2.3% |"),
            std::string::npos)
      << md;
  EXPECT_NE(
      md.find(
          "| Cotangent weighting | **spheremap** | 1 | 100–100 | 7 (0%) | 0 (100%) | 80% (80%) | 9.0° (9.0°) | 0.0% |"),
      std::string::npos)
      << md;
  EXPECT_NE(md.find("(4 found)"), std::string::npos);
  EXPECT_NE(md.find("`c/uniform/report.json` | c.pdb | uniform | yes | 200 | 1 | 3 | 1 | 3 | **no** |"),
            std::string::npos)
      << md;
  // Same input, same bytes.
  EXPECT_EQ(md, table1_markdown(summarize_protocols(recs), recs, context));
}

TEST_F(Table, OctantHistogramUsesThePapersBins) {
  std::vector<ReportSummary> uniform;
  for (const auto& r : records())
    if (r.weights == "uniform") uniform.push_back(r);
  const Histogram h = octant_histogram(uniform);
  // Bins [5, 8) ... [32, 35), labelled 6.5 ... 33.5 as in the paper.
  ASSERT_EQ(h.labels.size(), 10u);
  EXPECT_EQ(h.labels.front(), "6.5");
  EXPECT_EQ(h.labels[2], "12.5");
  EXPECT_EQ(h.labels.back(), "33.5");
  ASSERT_EQ(h.edges.size(), 11u);
  EXPECT_DOUBLE_EQ(h.edges.front(), 5);
  EXPECT_DOUBLE_EQ(h.edges.back(), 35);
  const std::vector<std::int64_t> expected{1, 1, 20, 1, 0, 1, 0, 0, 0, 0};  // 5 | 10 | 12.5 x 20 | 15 | 20
  EXPECT_EQ(h.counts, expected);
  // Values beyond the paper's range widen it.
  uniform[0].distortion.octant_area_percent[0] = 0.2;
  uniform[0].distortion.octant_area_percent[1] = 40;
  const Histogram wide = octant_histogram(uniform);
  EXPECT_EQ(wide.labels.front(), "0.5");
  EXPECT_EQ(wide.labels.back(), "39.5");
  EXPECT_EQ(wide.counts.front(), 1);
  EXPECT_EQ(wide.counts.back(), 1);
}

TEST_F(Table, TriangleAreaHistogramAndTheTypicalSurface) {
  const auto recs = records();
  const std::size_t typical = typical_surface(recs);
  EXPECT_EQ(recs[typical].input, "/data/c.pdb");
  const auto areas = triangle_areas_of_file(recs[typical].source.parent_path() / "surface.ply");
  ASSERT_EQ(areas.size(), 4u);
  EXPECT_DOUBLE_EQ(areas[0], 1);
  EXPECT_DOUBLE_EQ(areas[1], 1);
  EXPECT_DOUBLE_EQ(areas[2], 2);
  EXPECT_DOUBLE_EQ(areas[3], 4);
  const Histogram h = triangle_area_histogram(areas);
  ASSERT_EQ(h.counts.size(), 23u);  // 0-10 ... 220-230, labelled 10 ... 230 as in the paper
  EXPECT_EQ(h.labels.front(), "10");
  EXPECT_EQ(h.labels.back(), "230");
  EXPECT_EQ(h.counts[5], 2);   // 50%
  EXPECT_EQ(h.counts[10], 1);  // 100%
  EXPECT_EQ(h.counts[20], 1);  // 200%
  std::int64_t total = 0;
  for (const auto c : h.counts) total += c;
  EXPECT_EQ(total, 4);
  // Nine small triangles and a huge one: mean 10.9, 9.17% and 917%: overflow bar.
  std::vector<double> skewed(9, 1.0);
  skewed.push_back(100);
  const Histogram o = triangle_area_histogram(skewed);
  ASSERT_EQ(o.counts.size(), 31u);
  EXPECT_EQ(o.labels.back(), "≥300");
  EXPECT_EQ(o.counts.front(), 9);
  EXPECT_EQ(o.counts.back(), 1);
  EXPECT_THROW(triangle_area_histogram({}), std::invalid_argument);
  EXPECT_THROW(triangle_area_histogram({0.0, 0.0}), std::invalid_argument);
}

TEST_F(Table, DuplicateRunsAreReported) {
  write_report("rerun/a/uniform", {"/data/a.pdb", "uniform", 100, true, 0, 0, true, 0, 0, 1, 1, 1, 1, 1, {}});
  const auto warnings = duplicate_runs(records());
  ASSERT_EQ(warnings.size(), 1u);
  EXPECT_NE(warnings[0].find("/data/a.pdb appears 2 times under weights uniform"), std::string::npos) << warnings[0];
}

TEST_F(Table, ThousandsLikeThePaper) {
  EXPECT_EQ(with_thousands(0), "0");
  EXPECT_EQ(with_thousands(999), "999");
  EXPECT_EQ(with_thousands(3000), "3,000");
  EXPECT_EQ(with_thousands(1234567), "1,234,567");
  EXPECT_EQ(with_thousands(-4500), "-4,500");
}

// The command as a user runs it.
TEST_F(Table, CommandWritesTheTableAndFiguresDeterministically) {
  const testing_support::CliRun run = run_cli("table " + runs_.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("4 report.json found (uniform: 3, cotan: 1)"), std::string::npos) << run.output;
  for (const char* name : {"table1.md", "figure4a-uniform.png", "figure4a-uniform.svg", "figure4a-cotan.png",
                           "figure4a-cotan.svg", "figure4b.png", "figure4b.svg"})
    EXPECT_TRUE(fs::exists(runs_ / name)) << name;
  EXPECT_NE(slurp(runs_ / "table1.md").find("/data/c.pdb"), std::string::npos);
  // -o elsewhere: the same bytes.
  const testing_support::CliRun again = run_cli("table -q " + runs_.string() + " -o " + (root_ / "out").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_TRUE(again.output.empty()) << again.output;
  for (const char* name : {"table1.md", "figure4a-uniform.png", "figure4a-uniform.svg", "figure4b.png", "figure4b.svg"})
    EXPECT_EQ(slurp(runs_ / name), slurp(root_ / "out" / name)) << name;
}

TEST_F(Table, CommandRefusesMissingAndEmptyFolders) {
  const testing_support::CliRun missing = run_cli("table " + (root_ / "nowhere").string());
  EXPECT_EQ(missing.exit_code, 1);
  EXPECT_NE(missing.output.find("does not exist"), std::string::npos) << missing.output;
  const testing_support::CliRun empty = run_cli("table " + (runs_ / "failed").string());
  EXPECT_EQ(empty.exit_code, 1);
  EXPECT_NE(empty.output.find("no report.json found"), std::string::npos) << empty.output;
  EXPECT_FALSE(fs::exists(runs_ / "failed" / "table1.md"));
}

}  // namespace
}  // namespace spheremap
