// report.json: what make_report writes, read_report reads back, field for field; and what it refuses.
#include "spheremap/pipeline/report.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "spheremap/error.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

// A real map of a small mesh and its report.
class Report : public testing::Test {
 protected:
  static void SetUpTestSuite() {
    result_ = new MapJobResult(run_map_job(make_dumbbell(3.0, 0.4, 24, 16), "dumbbell", MapJobOptions{}));
  }
  static void TearDownTestSuite() {
    delete result_;
    result_ = nullptr;
  }
  static nlohmann::json report() { return make_report(*result_, MapJobOptions{}); }
  static MapJobResult* result_;
};
MapJobResult* Report::result_ = nullptr;

std::string refusal(const nlohmann::json& report) {
  try {
    read_report(report, "runs/x/report.json");
  } catch (const InputError& e) {
    return e.what();
  }
  return "no throw";
}

TEST_F(Report, ReadsBackWhatMakeReportWrote) {
  const MapJobResult& m = *result_;
  const ReportSummary r = read_report(report(), "runs/x/report.json");
  EXPECT_EQ(r.source, "runs/x/report.json");
  EXPECT_EQ(r.input, "dumbbell");
  EXPECT_EQ(r.weights, "uniform");
  EXPECT_TRUE(r.repair);
  EXPECT_EQ(r.vertices, static_cast<std::int64_t>(m.prepared.mesh.vertex_count()));
  EXPECT_EQ(r.triangles, static_cast<std::int64_t>(m.prepared.mesh.triangle_count()));
  EXPECT_EQ(r.input_vertices, m.prepared.report.input_vertices);
  EXPECT_EQ(r.input_faces, m.prepared.report.input_faces);
  EXPECT_EQ(r.components, 1);
  EXPECT_EQ(r.genus, 0);
  EXPECT_FALSE(r.structure.has_value());
  EXPECT_FALSE(r.simplification.has_value());
  const auto& diagnostics = m.map.diagnostics;
  EXPECT_EQ(r.map_method, to_string(diagnostics.construction.method));
  EXPECT_EQ(r.solver, to_string(diagnostics.solve.solver));
  EXPECT_EQ(r.north_pole, m.map.poles.north);
  EXPECT_EQ(r.south_pole, m.map.poles.south);
  EXPECT_EQ(r.pole_graph_distance, m.map.poles.graph_distance);
  EXPECT_EQ(r.split_edges, static_cast<std::int64_t>(diagnostics.construction.split_edges.size()));
  EXPECT_EQ(r.reweighting_rounds, diagnostics.repair.reweighting_rounds);
  EXPECT_EQ(r.untangling_moves, diagnostics.repair.untangling_moves);
  EXPECT_EQ(r.superposition_rmsd, m.map.superposition.rmsd);
  EXPECT_EQ(r.certificate.certified, m.map.certificate.certified());
  EXPECT_EQ(r.certificate.folded, m.map.certificate.folded);
  EXPECT_EQ(r.certificate.coverage, m.map.certificate.coverage);
  EXPECT_EQ(r.certificate.decided_exactly, m.map.certificate.decided_exactly);
  EXPECT_EQ(r.plain_certificate.collapsed, diagnostics.repair.plain_certificate.collapsed);
  EXPECT_EQ(r.plain_certificate.min_area_ratio, diagnostics.repair.plain_certificate.min_area_ratio);
  EXPECT_EQ(r.distortion.area_log_ratio_mean, m.metrics.area_log_ratio_mean);
  EXPECT_EQ(r.distortion.dilatation_max, m.metrics.dilatation_max);
  EXPECT_EQ(r.distortion.octant_area_percent, m.metrics.octant_area_percent);
  // Every stage timed, in key order; the map's own stages among them.
  ASSERT_FALSE(r.timings.empty());
  EXPECT_TRUE(std::is_sorted(r.timings.begin(), r.timings.end(),
                             [](const StageTime& a, const StageTime& b) { return a.stage < b.stage; }));
  EXPECT_EQ(std::count_if(r.timings.begin(), r.timings.end(), [](const StageTime& t) { return t.stage == "read"; }), 1);
  EXPECT_EQ(r.timings.size(), diagnostics.timings.size() + 4);  // read, prepare, metrics, properties
}

TEST_F(Report, ReadsTheStructurePartsAndCountsTheChangesByKind) {
  nlohmann::json with = report();
  with["structure"] = {{"atoms", 1234}, {"probe", 1.4}, {"grid", 0.5}};
  with["structure"]["topology_repair"] = {
      {"method", "per-handle"}, {"rounds", 2},        {"samples_changed", 40},        {"volume_changed", 5.0},
      {"area_before", 100.0},   {"area_after", 99.0}, {"area_changed_percent", -1.0}, {"genus_before", 3}};
  with["structure"]["topology_repair"]["changes"] = {{{"kind", "cut"}}, {{"kind", "fill"}}, {{"kind", "cut"}}};
  with["simplification"] = {
      {"vertices_before", 5000}, {"area_before", 100.0}, {"area_after", 99.5}, {"max_vertex_distance", 0.1}};
  const ReportSummary r = read_report(with, "x");
  ASSERT_TRUE(r.structure.has_value());
  EXPECT_EQ(r.structure->atoms, 1234);
  EXPECT_EQ(r.structure->topology_repair.method, "per-handle");
  EXPECT_EQ(r.structure->topology_repair.genus_before, 3);
  EXPECT_EQ(r.structure->topology_repair.handles_cut, 2);
  EXPECT_EQ(r.structure->topology_repair.tunnels_filled, 1);
  ASSERT_TRUE(r.simplification.has_value());
  EXPECT_EQ(r.simplification->vertices_before, 5000);
  EXPECT_EQ(r.simplification->max_vertex_distance, 0.1);
}

TEST_F(Report, RefusesAMissingOrMistypedFieldByName) {
  nlohmann::json missing = report();
  missing["map"].erase("solver");
  EXPECT_NE(refusal(missing).find("runs/x/report.json: field 'map.solver' is missing"), std::string::npos)
      << refusal(missing);
  nlohmann::json mistyped = report();
  mistyped["certificate"]["folded"] = "none";
  EXPECT_NE(refusal(mistyped).find("field 'certificate.folded' has the wrong type (string)"), std::string::npos)
      << refusal(mistyped);
  nlohmann::json octants = report();
  octants["distortion"]["octant_area_percent"] = {12.5, 12.5};
  EXPECT_NE(refusal(octants).find("has 2 values instead of 8"), std::string::npos) << refusal(octants);
  nlohmann::json empty = report();
  empty["mesh"]["triangles"] = 0;
  EXPECT_NE(refusal(empty).find("mesh.triangles is 0"), std::string::npos) << refusal(empty);
  EXPECT_NE(refusal(nlohmann::json::array()).find("field 'input' is missing"), std::string::npos);
}

// JSON has no NaN or infinity: nlohmann writes them as null, and they read back as NaN.
TEST_F(Report, NullNumbersReadAsNaN) {
  nlohmann::json with_null = report();
  with_null["distortion"]["dilatation_max"] = nullptr;
  EXPECT_TRUE(std::isnan(read_report(with_null, "x").distortion.dilatation_max));
  with_null["certificate"]["folded"] = nullptr;  // not a number that could be non-finite
  EXPECT_NE(refusal(with_null).find("certificate.folded"), std::string::npos);
}

// The paper's map (the default) writes no objective keys; another objective writes its option, what the
// optimization did, and its time.
TEST_F(Report, WritesTheObjectiveOnlyWhenOneIsChosen) {
  const nlohmann::json plain = report();
  EXPECT_FALSE(plain["options"].contains("objective"));
  EXPECT_FALSE(plain["map"].contains("objective"));
  EXPECT_FALSE(plain["timings_seconds"].contains("objective"));
  MapJobOptions options;
  options.map.objective = MapObjective::kArea;
  const MapJobResult area = run_map_job(make_dumbbell(3.0, 0.4, 24, 16), "dumbbell", options);
  const nlohmann::json json = make_report(area, options);
  EXPECT_EQ(json["options"]["objective"], "area");
  EXPECT_EQ(json["options"]["objective_max_iterations"], options.map.objective_max_iterations);
  const auto& objective = json["map"]["objective"];
  const auto& o = area.map.diagnostics.objective.optimization;
  EXPECT_EQ(objective["objective"], "area");
  EXPECT_EQ(objective["energy"], "log-area-ratio");
  EXPECT_EQ(objective["outcome"], "optimized");
  EXPECT_EQ(objective["iterations"], o.iterations);
  EXPECT_EQ(objective["stop_reason"], to_string(o.stop_reason));
  EXPECT_EQ(objective["energy_before"], o.energy_before);
  EXPECT_EQ(objective["energy_after"], o.energy_after);
  EXPECT_LT(o.energy_after, o.energy_before);
  EXPECT_TRUE(json["timings_seconds"].contains("objective"));
  EXPECT_TRUE(json["certificate"]["certified"]);
  // read_report still reads it (the objective's keys are extra).
  EXPECT_EQ(read_report(json, "x").input, "dumbbell");
}

}  // namespace
}  // namespace spheremap
