#include "spheremap/topology/simplify.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

#include "../../src/topology/simplify_tuning.hpp"
#include "../test_support.hpp"
#include "spheremap/attributes.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap {
namespace {

// Distance from p to the triangle abc, by brute force over a fine barycentric sampling refined by
// projection: exact enough (1e-9) for the checks below, and independent of the code under test.
double distance_to_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 n = normalized(cross(b - a, c - a));
  const Vec3 q = p - dot(p - a, n) * n;  // projection onto the plane
  auto inside = [&](const Vec3& x) {
    return dot(cross(b - a, x - a), n) >= 0 && dot(cross(c - b, x - b), n) >= 0 && dot(cross(a - c, x - c), n) >= 0;
  };
  if (inside(q)) return std::abs(dot(p - a, n));
  auto segment = [&](const Vec3& s, const Vec3& t) {
    const Vec3 d = t - s;
    const double u = std::clamp(dot(p - s, d) / dot(d, d), 0.0, 1.0);
    return norm(p - (s + u * d));
  };
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

double distance_to_mesh(const Vec3& p, const Mesh& mesh) {
  double nearest = INFINITY;
  for (const auto& t : mesh.triangles)
    nearest =
        std::min(nearest, distance_to_triangle(p, mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]));
  return nearest;
}

// A torus with major radius R and minor radius r, n x m quads split into triangles, outward.
Mesh make_torus(double major, double minor, int n, int m) {
  Mesh mesh;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      const double u = 2 * std::numbers::pi * i / n, v = 2 * std::numbers::pi * j / m;
      mesh.positions.push_back({(major + minor * std::cos(v)) * std::cos(u),
                                (major + minor * std::cos(v)) * std::sin(u), minor * std::sin(v)});
    }
  auto index = [&](int i, int j) { return static_cast<std::int32_t>(((i + n) % n) * m + (j + m) % m); };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < m; ++j) {
      mesh.triangles.push_back({index(i, j), index(i + 1, j), index(i + 1, j + 1)});
      mesh.triangles.push_back({index(i, j), index(i + 1, j + 1), index(i, j + 1)});
    }
  return mesh;
}

Mesh scaled(Mesh mesh, double factor) {
  for (auto& p : mesh.positions) p = factor * p;
  return mesh;
}

int total_genus(const Mesh& mesh) {
  int genus = 0;
  for (const auto& c : mesh_components(mesh)) genus += c.genus;
  return genus;
}

TEST(Simplify, ReducesASphereToTheTargetEdgeKeepingVerticesAndAttributes) {
  Mesh sphere = scaled(make_icosphere(5), 10.0);  // 10,242 vertices, edges about 0.4
  std::vector<std::int32_t> ids(sphere.vertex_count());
  for (std::size_t i = 0; i < ids.size(); ++i) ids[i] = static_cast<std::int32_t>(i) * 3;
  sphere.integer_attributes["id"] = ids;
  SimplifyOptions options;
  options.target_edge_length = 1.5;
  options.max_error = 0.1;
  SimplifyReport report;
  const Mesh out = simplify_surface(sphere, options, &report);
  testing_support::expect_closed_oriented_manifold(out);
  EXPECT_EQ(total_genus(out), 0);
  ASSERT_EQ(mesh_components(out).size(), 1u);
  EXPECT_LT(out.vertex_count(), sphere.vertex_count() / 5);
  EXPECT_EQ(report.vertices_after, static_cast<std::int64_t>(out.vertex_count()));
  EXPECT_EQ(report.triangles_after, static_cast<std::int64_t>(out.triangle_count()));
  EXPECT_EQ(out.triangle_count(), 2 * out.vertex_count() - 4);
  EXPECT_GT(report.mean_edge_after, 0.8 * options.target_edge_length);
  EXPECT_LT(report.mean_edge_after, 4.0 / 3 * options.target_edge_length);
  EXPECT_GE(report.min_angle_after_degrees, 20.0);
  // Vertices are a subset at their input positions, ascending, with their attributes.
  ASSERT_EQ(report.kept_vertex.size(), out.vertex_count());
  for (std::size_t i = 0; i < out.vertex_count(); ++i) {
    const auto v = static_cast<std::size_t>(report.kept_vertex[i]);
    if (i > 0) EXPECT_LT(report.kept_vertex[i - 1], report.kept_vertex[i]);
    EXPECT_EQ(out.positions[i], sphere.positions[v]);
    EXPECT_EQ(out.integer_attributes.at("id")[i], ids[v]);
  }
  // The reported distance bounds the true distance of every input vertex from the result.
  double largest = 0;
  for (const auto& p : sphere.positions) largest = std::max(largest, distance_to_mesh(p, out));
  EXPECT_LE(largest, report.max_vertex_distance + 1e-12);
  EXPECT_LT(report.max_vertex_distance, 0.15);
  EXPECT_NEAR(report.area_after, 4 * std::numbers::pi * 100, 0.02 * 4 * std::numbers::pi * 100);
}

TEST(Simplify, KeepsTheGenusAndTheComponents) {
  Mesh two = make_torus(5, 1.5, 80, 30);  // genus 1, edges about 0.3-0.5
  const Mesh ball = scaled(make_icosphere(4), 2.0);
  const auto offset = static_cast<std::int32_t>(two.vertex_count());
  for (const auto& p : ball.positions) two.positions.push_back(p + Vec3{20, 0, 0});
  for (const auto& t : ball.triangles) two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  SimplifyOptions options;
  options.target_edge_length = 2.0;
  options.max_error = 0.5;
  const Mesh out = simplify_surface(two, options);
  testing_support::expect_closed_oriented_manifold(out);
  const auto components = mesh_components(out);
  ASSERT_EQ(components.size(), 2u);
  EXPECT_EQ(components[0].genus + components[1].genus, 1);
  EXPECT_LT(out.vertex_count(), two.vertex_count() / 3);
}

// The pipeline takes the outer component of a contour in place (extract_component(Mesh&&)): it must be
// exactly what the copying extract_component gives, attributes included, for every component.
TEST(Simplify, ExtractComponentInPlaceMatchesTheCopy) {
  Mesh three = make_torus(5, 1.5, 40, 20);
  for (const double x : {20.0, -20.0}) {
    const Mesh ball = scaled(make_icosphere(2), 2.0);
    const auto offset = static_cast<std::int32_t>(three.vertex_count());
    for (const auto& p : ball.positions) three.positions.push_back(p + Vec3{x, 0, 0});
    for (const auto& t : ball.triangles) three.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  }
  // Interleave the components' triangles so that compacting moves entries across the whole arrays.
  std::rotate(three.triangles.begin(), three.triangles.begin() + 7, three.triangles.end());
  const auto n = three.vertex_count();
  auto& ids = three.integer_attributes[attributes::kAtomId];
  auto& heights = three.real_attributes["height"];
  auto& names = three.text_attributes["name"];
  names.dictionary = {"a", "b", "c"};
  for (std::size_t v = 0; v < n; ++v) {
    ids.push_back(static_cast<std::int32_t>(3 * v + 1));
    heights.push_back(three.positions[v][2]);
    names.codes.push_back(static_cast<std::int32_t>(v % 3));
  }
  const auto components = mesh_components(three);
  ASSERT_EQ(components.size(), 3u);
  for (const auto& component : components) {
    const Mesh copied = extract_component(three, component);
    Mesh taken = extract_component(Mesh(three), component);
    EXPECT_EQ(taken.positions, copied.positions);
    EXPECT_EQ(taken.triangles, copied.triangles);
    EXPECT_EQ(taken.integer_attributes, copied.integer_attributes);
    EXPECT_EQ(taken.real_attributes, copied.real_attributes);
    ASSERT_EQ(taken.text_attributes.size(), 1u);
    EXPECT_EQ(taken.text_attributes["name"].codes, copied.text_attributes.at("name").codes);
    EXPECT_EQ(taken.text_attributes["name"].dictionary, copied.text_attributes.at("name").dictionary);
    EXPECT_EQ(taken.positions.capacity(), taken.positions.size());
  }
}

TEST(Simplify, NeverShrinksAComponentBelowATetrahedronOrRemovesKeptVertices) {
  SimplifyOptions options;
  options.target_edge_length = 100;  // collapse everything it may
  options.max_error = 100;
  const Mesh small = simplify_surface(make_icosphere(2), options);
  testing_support::expect_closed_oriented_manifold(small);
  EXPECT_GE(small.vertex_count(), 4u);
  EXPECT_EQ(total_genus(small), 0);

  options.kept_vertices = {7, 100};
  SimplifyReport report;
  simplify_surface(make_icosphere(3), options, &report);
  EXPECT_NE(std::find(report.kept_vertex.begin(), report.kept_vertex.end(), 7), report.kept_vertex.end());
  EXPECT_NE(std::find(report.kept_vertex.begin(), report.kept_vertex.end(), 100), report.kept_vertex.end());
}

TEST(Simplify, IsDeterministicAndTargetZeroKeepsTheMesh) {
  const Mesh bumpy = perturb_vertices(random_edge_flips(scaled(make_icosphere(4), 5.0), 0.2, 7), 0.05, 11);
  SimplifyOptions options;
  options.target_edge_length = 1.0;
  options.max_error = 0.1;
  const Mesh a = simplify_surface(bumpy, options), b = simplify_surface(bumpy, options);
  EXPECT_EQ(a.positions, b.positions);
  EXPECT_EQ(a.triangles, b.triangles);
  for (const int threads : {1, 2, 3}) {  // two zones worked on in parallel: the same result on any count
    options.threads = threads;
    const Mesh c = simplify_surface(bumpy, options);
    EXPECT_EQ(c.positions, a.positions);
    EXPECT_EQ(c.triangles, a.triangles);
  }
  options.target_edge_length = 0;
  SimplifyReport report;
  const Mesh same = simplify_surface(bumpy, options, &report);
  EXPECT_EQ(same.positions, bumpy.positions);
  EXPECT_EQ(same.triangles, bumpy.triangles);
  EXPECT_EQ(report.max_vertex_distance, 0);
}

// The flip passes skip edges that failed their angle test while neither triangle on them changed: that
// must give what testing every edge on every pass gives, on a mesh where collapses and flips interleave
// over many rounds (a triangle changed by either must make its edges, seen from both sides, count again).
TEST(Simplify, SkippingEdgesKnownUnflippableChangesNothing) {
  const Mesh bumpy = perturb_vertices(random_edge_flips(scaled(make_icosphere(5), 8.0), 0.3, 5), 0.1, 3);
  SimplifyOptions options;
  options.target_edge_length = 1.0;
  options.max_error = 0.1;
  SimplifyReport skipping, testing_all;
  const Mesh fast = simplify_surface(bumpy, options, &skipping);
  detail::simplify_skips_known_unflippable_edges() = false;
  const Mesh plain = simplify_surface(bumpy, options, &testing_all);
  detail::simplify_skips_known_unflippable_edges() = true;
  EXPECT_GT(testing_all.flips, 500);
  EXPECT_GE(testing_all.rounds, 3);
  EXPECT_EQ(skipping.flips, testing_all.flips);
  EXPECT_EQ(fast.positions, plain.positions);
  EXPECT_EQ(fast.triangles, plain.triangles);
}

TEST(Simplify, ImprovesSliversWithoutLeavingTheSurface) {
  // Random flips make many thin triangles; flips and collapses must raise the smallest angle. (Within a
  // tolerance below the sagitta of the chords, 0.064 here, some slivers cannot go: 0.05 leaves 4.6°.)
  const Mesh slivers = random_edge_flips(scaled(make_icosphere(4), 5.0), 0.5, 3);
  SimplifyOptions options;
  options.target_edge_length = 0.8;
  options.max_error = 0.1;
  SimplifyReport report;
  const Mesh out = simplify_surface(slivers, options, &report);
  testing_support::expect_closed_oriented_manifold(out);
  EXPECT_LT(report.min_angle_before_degrees, 5);
  EXPECT_GT(report.min_angle_after_degrees, 15);
  EXPECT_GT(report.flips, 0);
  for (const auto& p : out.positions) EXPECT_NEAR(norm(p), 5.0, 1e-9);  // vertices never move
}

TEST(Simplify, RefusesOpenMeshesAndBadOptions) {
  Mesh open = make_icosphere(2);
  open.triangles.pop_back();
  EXPECT_THROW(simplify_surface(open, {}), std::invalid_argument);
  SimplifyOptions bad;
  bad.max_error = -1;
  EXPECT_THROW(simplify_surface(make_icosphere(1), bad), std::invalid_argument);
  bad = {};
  bad.max_normal_change_degrees = 90;
  EXPECT_THROW(simplify_surface(make_icosphere(1), bad), std::invalid_argument);
  bad = {};
  bad.kept_vertices = {1000};
  EXPECT_THROW(simplify_surface(make_icosphere(1), bad), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
