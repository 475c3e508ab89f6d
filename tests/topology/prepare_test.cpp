#include "spheremap/topology/prepare.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "spheremap/error.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

PolygonSoup tetrahedron_soup() {
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  soup.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  return soup;
}

std::string refusal_message(const PolygonSoup& soup, PrepareOptions options = {}) {
  try {
    prepare_mesh(soup, options);
  } catch (const MeshRefused& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(Prepare, AcceptsTetrahedronAndKeepsOutwardOrientation) {
  const auto prepared = prepare_mesh(tetrahedron_soup());
  EXPECT_EQ(prepared.mesh.vertex_count(), 4u);
  EXPECT_EQ(prepared.mesh.triangle_count(), 4u);
  EXPECT_EQ(prepared.report.genus, 0);
  EXPECT_EQ(prepared.report.triangles_flipped, 0);
}

TEST(Prepare, ReorientsInconsistentAndInwardTriangles) {
  auto soup = tetrahedron_soup();
  for (auto& f : soup.faces) std::swap(f[1], f[2]);  // all inward
  std::swap(soup.faces[2][1], soup.faces[2][2]);     // and one inconsistent
  const auto prepared = prepare_mesh(soup);
  EXPECT_EQ(prepared.report.triangles_flipped, 3);
  // Outward: positive signed volume, i.e. every triangle's normal points away from the centroid.
  const Vec3 centroid{0.25, 0.25, 0.25};
  for (const auto& t : prepared.mesh.triangles) {
    const auto& p = prepared.mesh.positions;
    const Vec3 a = p[t[0]], b = p[t[1]], c = p[t[2]];
    const Vec3 ab{b[0] - a[0], b[1] - a[1], b[2] - a[2]}, ac{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
    const Vec3 n{ab[1] * ac[2] - ab[2] * ac[1], ab[2] * ac[0] - ab[0] * ac[2], ab[0] * ac[1] - ab[1] * ac[0]};
    const double outward = n[0] * (a[0] - centroid[0]) + n[1] * (a[1] - centroid[1]) + n[2] * (a[2] - centroid[2]);
    EXPECT_GT(outward, 0);
  }
}

TEST(Prepare, WeldsCoincidentVerticesAndDropsDegenerateAndDuplicateFaces) {
  // Each face with its own three vertices, like STL; plus a duplicate and a degenerate face.
  const auto base = tetrahedron_soup();
  PolygonSoup soup;
  for (const auto& f : base.faces) {
    std::vector<std::int32_t> face;
    for (auto v : f) {
      face.push_back(static_cast<std::int32_t>(soup.positions.size()));
      soup.positions.push_back(base.positions[v]);
    }
    soup.faces.push_back(face);
  }
  soup.faces.push_back(soup.faces[0]);
  soup.faces.push_back({0, 0, 1});
  const auto prepared = prepare_mesh(soup);
  EXPECT_EQ(prepared.mesh.vertex_count(), 4u);
  EXPECT_EQ(prepared.report.vertices_welded, 8);
  EXPECT_EQ(prepared.report.duplicate_faces_dropped, 1);
  EXPECT_EQ(prepared.report.degenerate_faces_dropped, 1);
}

TEST(Prepare, WeldToleranceMergesNearbyVertices) {
  auto soup = tetrahedron_soup();
  soup.positions.push_back({1 + 1e-9, 0, 0});
  soup.faces[3] = {4, 2, 3};
  EXPECT_NE(refusal_message(soup).find("boundary edges"), std::string::npos);
  PrepareOptions options;
  options.weld_tolerance = 1e-6;
  EXPECT_EQ(prepare_mesh(soup, options).mesh.vertex_count(), 4u);
}

TEST(Prepare, TriangulatesPolygons) {
  PolygonSoup cube;
  cube.positions = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  cube.faces = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  const auto prepared = prepare_mesh(cube);
  EXPECT_EQ(prepared.mesh.triangle_count(), 12u);
  EXPECT_EQ(prepared.report.polygons_triangulated, 6);
}

TEST(Prepare, QuadWhoseFirstDiagonalIsAnExistingEdgeIsSplitTheOtherWay) {
  // A tetrahedron written as one quad and two triangles; the quad's 1-3 diagonal is a triangle's edge.
  PolygonSoup soup;
  soup.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  soup.faces = {{0, 1, 2, 3}, {2, 1, 0}, {0, 3, 2}};
  const auto prepared = prepare_mesh(soup);
  EXPECT_EQ(prepared.mesh.triangle_count(), 4u);
  EXPECT_EQ(prepared.report.duplicate_faces_dropped, 0);
}

TEST(Prepare, OrientsOutwardFarFromTheOrigin) {
  Mesh far = make_ellipsoid(2, 1, 2, 3);
  for (auto& p : far.positions) p = {p[0] + 1e9, p[1] + 1e9, p[2] + 1e9};
  EXPECT_EQ(prepare_mesh(far).report.triangles_flipped, 0);
  Mesh inward = far;
  for (auto& t : inward.triangles) std::swap(t[1], t[2]);
  EXPECT_EQ(prepare_mesh(inward).report.triangles_flipped, static_cast<std::int64_t>(far.triangle_count()));
}

TEST(Prepare, KeepsTheInputVertexOrderAndMapsInputIndices) {
  const Mesh ico = make_icosphere(2);
  const auto prepared = prepare_mesh(ico);
  for (std::size_t i = 0; i < ico.vertex_count(); ++i) {
    EXPECT_EQ(prepared.report.original_vertex[i], static_cast<std::int32_t>(i));
    EXPECT_EQ(prepared.report.vertex_of_input[i], static_cast<std::int32_t>(i));
  }
  // A welded duplicate maps to its representative; an unused vertex to -1.
  auto soup = tetrahedron_soup();
  soup.positions.push_back({5, 5, 5});  // 4: unused
  soup.positions.push_back({1, 0, 0});  // 5: duplicate of 1
  soup.faces[1] = {0, 5, 3};
  const auto welded = prepare_mesh(soup);
  EXPECT_EQ(welded.report.vertex_of_input[4], -1);
  EXPECT_EQ(welded.report.vertex_of_input[5], welded.report.vertex_of_input[1]);
}

TEST(Prepare, RejectsAWeldToleranceBelowDoublePrecision) {
  auto soup = tetrahedron_soup();
  PrepareOptions options;
  options.weld_tolerance = 1e-300;
  EXPECT_THROW(prepare_mesh(soup, options), InputError);
}

TEST(Prepare, RefusesOpenMeshWithCount) {
  auto soup = tetrahedron_soup();
  soup.faces.pop_back();
  const auto message = refusal_message(soup);
  EXPECT_NE(message.find("3 boundary edges"), std::string::npos) << message;
  EXPECT_NE(message.find("mesh"), std::string::npos);
}

TEST(Prepare, RefusesNonManifoldEdge) {
  auto soup = tetrahedron_soup();
  soup.positions.push_back({-1, -1, -1});
  soup.faces.push_back({0, 1, 4});
  const auto message = refusal_message(soup);
  EXPECT_NE(message.find("non-manifold edge"), std::string::npos) << message;
}

TEST(Prepare, RefusesPinchedVertexAndSeveralComponents) {
  // Two tetrahedra sharing vertex 0.
  auto soup = tetrahedron_soup();
  soup.positions.push_back({0, 0, -1});
  soup.positions.push_back({0, -1, 0});
  soup.positions.push_back({-1, 0, 0});
  soup.faces.push_back({0, 5, 4});
  soup.faces.push_back({0, 4, 6});
  soup.faces.push_back({0, 6, 5});
  soup.faces.push_back({4, 5, 6});
  const auto pinched = refusal_message(soup);
  EXPECT_NE(pinched.find("1 pinched (non-manifold) vertex"), std::string::npos) << pinched;

  // Two separate tetrahedra.
  auto two = tetrahedron_soup();
  const auto first = tetrahedron_soup();
  for (auto p : first.positions) two.positions.push_back({p[0] + 5, p[1], p[2]});
  for (auto f : first.faces) two.faces.push_back({f[0] + 4, f[1] + 4, f[2] + 4});
  const auto components = refusal_message(two);
  EXPECT_NE(components.find("2 separate connected components"), std::string::npos) << components;
  EXPECT_NE(components.find("--component"), std::string::npos);
  PrepareOptions largest;
  largest.component = ComponentChoice::largest();
  EXPECT_EQ(prepare_mesh(two, largest).mesh.vertex_count(), 4u);
  PrepareOptions second;
  second.component = ComponentChoice::numbered(1);
  const auto kept = prepare_mesh(two, second);
  EXPECT_EQ(kept.report.component_kept, 1);
  EXPECT_DOUBLE_EQ(kept.mesh.positions[0][0], 5.0);
  // A component the mesh does not have is a command-line error (exit 1) that gives the count.
  PrepareOptions missing;
  missing.component = ComponentChoice::numbered(2);
  try {
    prepare_mesh(two, missing);
    ADD_FAILURE() << "--component 2 of 2 components accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("--component 2 does not exist: the mesh has 2 components"), std::string::npos)
        << e.what();
  }
  missing.component = ComponentChoice::numbered(1);
  EXPECT_THROW(prepare_mesh(tetrahedron_soup(), missing), InputError);
}

TEST(Prepare, RefusesTorusWithItsGenus) {
  // A coarse torus: 4 x 4 quads on a grid with both directions periodic.
  PolygonSoup torus;
  const int n = 4;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const double u = 2 * 3.14159265358979 * i / n, v = 2 * 3.14159265358979 * j / n;
      torus.positions.push_back({(2 + std::cos(v)) * std::cos(u), (2 + std::cos(v)) * std::sin(u), std::sin(v)});
    }
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      torus.faces.push_back({i * n + j, ((i + 1) % n) * n + j, ((i + 1) % n) * n + (j + 1) % n, i * n + (j + 1) % n});
  const auto message = refusal_message(torus);
  EXPECT_NE(message.find("genus 1"), std::string::npos) << message;
}

TEST(Prepare, KeepsAttributesOfTriangleMeshes) {
  Mesh mesh = make_icosphere(1);
  std::vector<double> values(mesh.vertex_count());
  for (std::size_t i = 0; i < values.size(); ++i) values[i] = static_cast<double>(i);
  mesh.real_attributes["charge"] = values;
  const auto prepared = prepare_mesh(mesh);
  ASSERT_EQ(prepared.mesh.real_attributes.at("charge").size(), prepared.mesh.vertex_count());
  for (std::size_t i = 0; i < prepared.mesh.vertex_count(); ++i)
    EXPECT_EQ(prepared.mesh.real_attributes.at("charge")[i], prepared.report.original_vertex[i]);
}

TEST(Connectivity, RingsAreCounterClockwiseAndDistancesAreBreadthFirst) {
  const Mesh ico = make_icosphere(0);
  const auto rings = build_vertex_rings(static_cast<std::int32_t>(ico.vertex_count()), ico.triangles);
  for (std::int32_t v = 0; v < rings.vertex_count(); ++v) {
    ASSERT_EQ(rings.degree(v), 5);
    // Consecutive ring neighbours form a triangle (v, a, b) of the mesh in that order.
    const auto ring = rings.ring(v);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const Triangle wanted{v, ring[k], ring[(k + 1) % ring.size()]};
      bool found = false;
      for (const auto& t : ico.triangles)
        for (int s = 0; s < 3; ++s)
          found |= t[s] == wanted[0] && t[(s + 1) % 3] == wanted[1] && t[(s + 2) % 3] == wanted[2];
      EXPECT_TRUE(found);
    }
  }
  const auto distance = graph_distances(rings, 0);
  EXPECT_EQ(*std::max_element(distance.begin(), distance.end()), 3);
}

}  // namespace
}  // namespace spheremap
