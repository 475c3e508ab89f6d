// Inputs that push the map's numerics: a 1:1000 needle, coordinates 1e6 from the origin, tiny and huge
// triangles side by side (area ratio 1e-9). Whatever the map does with them, it never folds silently: a
// map reported certified has no folded triangle by an independent check, and one that is not says how
// many triangles are folded or collapsed (the command then exits 3).
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

double det(const Vec3& a, const Vec3& b, const Vec3& c) {
  return a[0] * (b[1] * c[2] - b[2] * c[1]) - a[1] * (b[0] * c[2] - b[2] * c[0]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
}

// The map of `mesh` is certified with no clearly folded triangle, or not certified and says why.
void expect_never_silently_folded(const Mesh& mesh, const std::string& name) {
  const MapJobResult result = run_map_job(mesh, name, MapJobOptions{});
  const Mesh& mapped = result.prepared.mesh;
  ASSERT_EQ(result.map.sphere.size(), mapped.positions.size()) << name;
  std::int64_t clearly_folded = 0;
  for (const auto& t : mapped.triangles)
    clearly_folded += det(result.map.sphere[t[0]], result.map.sphere[t[1]], result.map.sphere[t[2]]) < -1e-12;
  const Certificate& c = result.map.certificate;
  EXPECT_EQ(c.triangle_count, static_cast<std::int64_t>(mapped.triangles.size())) << name;
  if (c.certified()) {
    EXPECT_EQ(clearly_folded, 0) << name << ": certified, but folded by an independent check";
    EXPECT_NEAR(c.coverage, 1.0, 1e-9) << name;
  } else {
    EXPECT_GT(c.folded + c.collapsed + (std::abs(c.coverage - 1) >= 1e-9), 0)
        << name << ": uncertified without a reason";
    EXPECT_GE(c.folded, clearly_folded) << name << ": folds the certificate does not count";
    EXPECT_NE(summary_text(result).find("NOT"), std::string::npos) << name << ": not said plainly";
  }
}

TEST(RobustNumerics, ANeedleOfAspectRatioOneThousand) {
  expect_never_silently_folded(make_ellipsoid(3, 1, 1, 1000), "needle");
}

TEST(RobustNumerics, CoordinatesAMillionFromTheOrigin) {
  Mesh mesh = perturb_vertices(make_icosphere(3), 0.1, 5);
  for (auto& p : mesh.positions) p = {p[0] + 1e6, p[1] - 1e6, p[2] + 1e6};
  expect_never_silently_folded(mesh, "offset");
}

// One triangle of an icosphere split at a point 1e-9 of an edge from its corner: two triangles of area
// ratio about 1e-9 beside ones of ordinary size.
TEST(RobustNumerics, TinyAndHugeTrianglesSideBySide) {
  Mesh mesh = make_icosphere(2);
  const auto t = mesh.triangles.front();
  const Vec3 a = mesh.positions[t[0]], b = mesh.positions[t[1]], c = mesh.positions[t[2]];
  Vec3 p;
  for (int k = 0; k < 3; ++k) p[k] = a[k] + 1e-9 * ((b[k] - a[k]) + (c[k] - a[k]));
  const auto v = static_cast<std::int32_t>(mesh.positions.size());
  mesh.positions.push_back(p);
  mesh.triangles.front() = {t[0], t[1], v};
  mesh.triangles.push_back({t[1], t[2], v});
  mesh.triangles.push_back({t[2], t[0], v});
  expect_never_silently_folded(mesh, "tiny-and-huge");
}

}  // namespace
}  // namespace spheremap
