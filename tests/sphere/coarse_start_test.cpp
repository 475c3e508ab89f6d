// The area objective's coarse start (src/sphere/coarse_start.hpp) and the simplification that keeps a
// map valid, which it rests on.
#include "../../src/sphere/coarse_start.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/sphere/optimize.hpp"
#include "spheremap/topology/prepare.hpp"
#include "spheremap/topology/simplify.hpp"

namespace spheremap {
namespace {

Mesh prepared(const Mesh& mesh) { return prepare_mesh(mesh).mesh; }

int folded(const std::vector<Triangle>& triangles, const std::vector<Vec3>& points) {
  int count = 0;
  for (const auto& t : triangles) count += orientation_sign(points[t[0]], points[t[1]], points[t[2]]) <= 0;
  return count;
}

double mean_edge(const Mesh& mesh) {
  double sum = 0;
  for (const auto& t : mesh.triangles) sum += norm(mesh.positions[t[1]] - mesh.positions[t[0]]);
  return sum / static_cast<double>(mesh.triangles.size());
}

// The kept vertices' points of a map, as a map of the simplified mesh.
std::vector<Vec3> kept_points(const std::vector<Vec3>& points, const SimplifyReport& report) {
  std::vector<Vec3> kept;
  for (const auto v : report.kept_vertex) kept.push_back(points[v]);
  return kept;
}

// The paper's map of a dumbbell crushes one bulb: simplified by the surface's edge lengths alone, the
// kept vertices' points fold a triangle; with oriented_on, none.
TEST(SimplifyOnAMap, KeepsTheMapOfTheKeptVerticesValid) {
  const Mesh mesh = prepared(make_dumbbell(3.0, 0.4, 40, 30));
  const SphereMap paper = map_to_sphere(mesh);
  ASSERT_TRUE(paper.certificate.certified());
  SimplifyOptions options;
  options.target_edge_length = 4 * mean_edge(mesh);
  options.max_error = 1e30;
  options.min_angle_degrees = 5;
  SimplifyReport plain_report, guarded_report;
  const Mesh plain = simplify_surface(mesh, options, &plain_report);
  // The premise: without the guard this case folds (else it would not test the guard).
  EXPECT_GT(folded(plain.triangles, kept_points(paper.sphere, plain_report)), 0);
  options.oriented_on = paper.sphere;
  const Mesh guarded = simplify_surface(mesh, options, &guarded_report);
  EXPECT_LT(guarded.vertex_count(), mesh.vertex_count() / 4);
  EXPECT_EQ(folded(guarded.triangles, kept_points(paper.sphere, guarded_report)), 0);
}

TEST(SimplifyOnAMap, RefusesPointsThatAreNotAValidMap) {
  const Mesh mesh = prepared(make_dumbbell(3.0, 0.4, 12, 10));
  const SphereMap paper = map_to_sphere(mesh);
  SimplifyOptions options;
  options.oriented_on = paper.sphere;
  options.oriented_on.pop_back();
  EXPECT_THROW(simplify_surface(mesh, options), std::invalid_argument);
  options.oriented_on = paper.sphere;
  for (auto& p : options.oriented_on) p[0] = -p[0];  // a mirror image: every triangle negative
  EXPECT_THROW(simplify_surface(mesh, options), std::invalid_argument);
}

struct Start {
  Mesh mesh;
  SphereMap paper;
  std::vector<char> fixed;
};

Start papers_map(const Mesh& shape) {
  Start start{prepared(shape), {}, {}};
  start.paper = map_to_sphere(start.mesh);
  start.fixed.assign(start.mesh.vertex_count(), 0);
  start.fixed[start.paper.poles.north] = start.fixed[start.paper.poles.south] = 1;
  return start;
}

SphereOptimizeOptions area_options() {
  SphereOptimizeOptions options;
  options.energy = SphereEnergy::kLogAreaRatio;
  options.relative_tolerance = 1e-3;
  return options;
}

// On a 20k-vertex dumbbell (the paper's map gives one bulb most of the globe) the coarse start moves the
// area between the bulbs on a mesh ten times coarser: the optimization from it needs far fewer steps
// than from the paper's map and ends as low.
TEST(CoarseStart, LeavesTheFineStepsOnlyTheDetail) {
  const Start start = papers_map(make_dumbbell(3.0, 0.4, 160, 126));
  ASSERT_GE(static_cast<std::int64_t>(start.mesh.vertex_count()), detail::kCoarseStartMinVertices);
  ASSERT_TRUE(start.paper.certificate.certified());
  const auto north = start.paper.poles.north, south = start.paper.poles.south;
  std::vector<Vec3> coarse = start.paper.sphere;
  detail::CoarseStart report;
  ASSERT_TRUE(detail::coarse_start(start.mesh, coarse, north, south, area_options(), report));
  EXPECT_EQ(report.levels, 1);
  EXPECT_GT(report.iterations, 0);
  EXPECT_LT(report.coarse_vertices, static_cast<std::int64_t>(start.mesh.vertex_count()) / 4);
  EXPECT_EQ(folded(start.mesh.triangles, coarse), 0);
  EXPECT_EQ(coarse[north], start.paper.sphere[north]);
  EXPECT_EQ(coarse[south], start.paper.sphere[south]);

  std::vector<Vec3> direct = start.paper.sphere;
  const auto from_paper =
      optimize_on_sphere(start.mesh.positions, start.mesh.triangles, direct, start.fixed, area_options());
  const auto from_coarse =
      optimize_on_sphere(start.mesh.positions, start.mesh.triangles, coarse, start.fixed, area_options());
  EXPECT_LT(from_coarse.energy_before, 0.1 * from_paper.energy_before);
  EXPECT_LE(2 * from_coarse.iterations, from_paper.iterations);
  EXPECT_LT(from_coarse.energy_after, 1.01 * from_paper.energy_after);
  EXPECT_TRUE(certify_sphere_map(start.mesh, coarse).certified());

  // Deterministic: the same start again gives the same points.
  std::vector<Vec3> again = start.paper.sphere;
  detail::CoarseStart again_report;
  ASSERT_TRUE(detail::coarse_start(start.mesh, again, north, south, area_options(), again_report));
  std::vector<Vec3> first = start.paper.sphere;
  detail::coarse_start(start.mesh, first, north, south, area_options(), report);
  EXPECT_EQ(again, first);
}

TEST(CoarseStart, LeavesSmallMeshesAlone) {
  const Start start = papers_map(make_dumbbell(3.0, 0.4, 60, 50));
  std::vector<Vec3> points = start.paper.sphere;
  detail::CoarseStart report;
  EXPECT_FALSE(detail::coarse_start(start.mesh, points, start.paper.poles.north, start.paper.poles.south,
                                    area_options(), report));
  EXPECT_EQ(points, start.paper.sphere);
  EXPECT_EQ(report.levels, 0);
}

// A start that is not a valid map (here: mirrored, every triangle negative) gets no coarse start and is
// left as it was, instead of an exception from the simplification it could not guard.
TEST(CoarseStart, LeavesAStartThatIsNotValidAlone) {
  const Start start = papers_map(make_dumbbell(3.0, 0.4, 160, 126));
  std::vector<Vec3> mirrored = start.paper.sphere;
  for (auto& p : mirrored) p[0] = -p[0];
  const std::vector<Vec3> before = mirrored;
  detail::CoarseStart report;
  EXPECT_FALSE(detail::coarse_start(start.mesh, mirrored, start.paper.poles.north, start.paper.poles.south,
                                    area_options(), report));
  EXPECT_EQ(mirrored, before);
  EXPECT_EQ(report.levels, 0);
}

// Through map_to_sphere: the area objective on the large dumbbell starts from the coarse map, says so,
// and its map is certified and equal-area within the goal.
TEST(CoarseStart, IsWhereTheAreaObjectiveStartsOnLargeMeshes) {
  MapOptions options;
  options.objective = MapObjective::kArea;
  const SphereMap map = map_to_sphere(prepared(make_dumbbell(3.0, 0.4, 160, 126)), options);
  const auto& objective = map.diagnostics.objective;
  EXPECT_EQ(objective.outcome, ObjectiveOutcome::kOptimized);
  EXPECT_TRUE(map.certificate.certified());
  EXPECT_EQ(objective.coarse_levels, 1);
  EXPECT_GT(objective.coarse_vertices, 0);
  EXPECT_GT(objective.coarse_iterations, 0);
  // The energy before is the paper's map's, not the coarse start's.
  EXPECT_GT(objective.optimization.energy_before, 10 * objective.optimization.energy_after);
  EXPECT_LE(objective.optimization.iterations, 8);
}

}  // namespace
}  // namespace spheremap
