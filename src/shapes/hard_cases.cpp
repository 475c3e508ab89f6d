#include "spheremap/shapes/hard_cases.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <vector>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

constexpr double kPi = std::numbers::pi;

// Uniform in [0, 1) from the generator's raw output (fixed by the standard, unlike the distributions),
// so the meshes are the same with every standard library.
double unit_draw(std::mt19937& generator) { return static_cast<double>(generator() >> 8) / 16777216.0; }

// A uniform index in [0, count) (count > 0), from raw output as above.
std::size_t index_draw(std::mt19937& generator, std::size_t count) {
  return static_cast<std::size_t>(unit_draw(generator) * static_cast<double>(count)) % count;
}

Mesh regular_tetrahedron() {
  Mesh mesh;
  mesh.positions = {{1, 1, 1}, {1, -1, -1}, {-1, 1, -1}, {-1, -1, 1}};
  mesh.triangles = {{0, 1, 2}, {0, 2, 3}, {0, 3, 1}, {1, 3, 2}};  // outward: det of each corner set > 0
  return mesh;
}

}  // namespace

Mesh make_stacked_triangulation(int vertices, double nesting, std::uint32_t seed, double height) {
  if (vertices < 4) throw std::invalid_argument("make_stacked_triangulation: at least 4 vertices");
  if (!(nesting >= 0 && nesting <= 1))
    throw std::invalid_argument("make_stacked_triangulation: nesting must be in [0, 1]");
  if (!(std::isfinite(height) && height >= 0))
    throw std::invalid_argument("make_stacked_triangulation: height must be finite and >= 0");
  Mesh mesh = regular_tetrahedron();
  mesh.positions.reserve(static_cast<std::size_t>(vertices));
  mesh.triangles.reserve(2 * static_cast<std::size_t>(vertices) - 4);
  std::mt19937 generator(seed);
  std::size_t newest = 0;  // the three triangles made by the last insertion: newest, and the last two
  bool any_insertion = false;
  while (static_cast<int>(mesh.positions.size()) < vertices) {
    const bool nested = any_insertion && unit_draw(generator) < nesting;
    const std::size_t pick = index_draw(generator, nested ? 3 : mesh.triangles.size());
    const std::size_t t = nested ? (pick == 0 ? newest : mesh.triangles.size() - pick) : pick;
    const Triangle tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
    double w[3];
    for (auto& x : w) x = 0.1 + 0.9 * unit_draw(generator);
    const double sum = w[0] + w[1] + w[2];
    const Vec3 normal = cross(b - a, c - a);  // outward, length twice the area
    const double area = 0.5 * norm(normal);
    if (!(area > 1e-250))
      throw std::invalid_argument(
          "make_stacked_triangulation: the nesting is too deep for double precision (a triangle "
          "of zero area); use fewer vertices or less nesting");
    const Vec3 inside = (w[0] / sum) * a + (w[1] / sum) * b + (w[2] / sum) * c;
    const Vec3 lifted = inside + (height * std::sqrt(area) / (2 * area)) * normal;
    const auto v = static_cast<std::int32_t>(mesh.positions.size());
    mesh.positions.push_back(lifted);
    mesh.triangles[t] = {tri[0], tri[1], v};
    mesh.triangles.push_back({tri[1], tri[2], v});
    mesh.triangles.push_back({tri[2], tri[0], v});
    newest = t;
    any_insertion = true;
  }
  return mesh;
}

Mesh make_bent_tube(TubeBend bend, int segments, int rings, double radius) {
  if (segments < 3 || segments > 1000) throw std::invalid_argument("make_bent_tube: segments must be in [3, 1000]");
  if (rings < 2 || rings > 100000) throw std::invalid_argument("make_bent_tube: rings must be in [2, 100000]");
  if (!(radius > 0 && radius <= 0.5)) throw std::invalid_argument("make_bent_tube: radius must be in (0, 0.5]");
  // Centre line by arc length s: point and unit tangent, in the plane z = 0.
  constexpr double kLeg = 1.5;
  const double length = bend == TubeBend::kU ? 2 * kLeg + kPi : 1.5 * kPi;
  auto centre = [&](double s, Vec3& point, Vec3& tangent) {
    if (bend == TubeBend::kC) {
      const double angle = 0.25 * kPi + s;
      point = {std::cos(angle), std::sin(angle), 0};
      tangent = {-std::sin(angle), std::cos(angle), 0};
    } else if (s < kLeg) {
      point = {-1, kLeg - s, 0};
      tangent = {0, -1, 0};
    } else if (s < kLeg + kPi) {
      const double angle = kPi + (s - kLeg);
      point = {std::cos(angle), std::sin(angle), 0};
      tangent = {-std::sin(angle), std::cos(angle), 0};
    } else {
      point = {1, s - kLeg - kPi, 0};
      tangent = {0, 1, 0};
    }
  };
  Mesh mesh;
  Vec3 first_point{}, first_tangent{}, last_point{}, last_tangent{};
  for (int i = 0; i < rings; ++i) {
    Vec3 point{}, tangent{};
    centre(length * i / (rings - 1), point, tangent);
    if (i == 0) first_point = point, first_tangent = tangent;
    if (i == rings - 1) last_point = point, last_tangent = tangent;
    const Vec3 normal{-tangent[1], tangent[0], 0};  // z x tangent: (normal, z, tangent) is right-handed
    for (int s = 0; s < segments; ++s) {
      const double angle = 2 * kPi * (s + 0.5 * (i % 2)) / segments;
      mesh.positions.push_back(point + radius * (std::cos(angle) * normal + std::sin(angle) * Vec3{0, 0, 1}));
    }
  }
  auto at = [&](int ring, int s) { return static_cast<std::int32_t>(ring * segments + s % segments); };
  for (int i = 0; i + 1 < rings; ++i)
    for (int s = 0; s < segments; ++s) {
      if (i % 2 == 0) {  // ring i + 1 is turned forward by half a segment
        mesh.triangles.push_back({at(i, s), at(i, s + 1), at(i + 1, s)});
        mesh.triangles.push_back({at(i, s + 1), at(i + 1, s + 1), at(i + 1, s)});
      } else {
        mesh.triangles.push_back({at(i, s), at(i, s + 1), at(i + 1, s + 1)});
        mesh.triangles.push_back({at(i, s), at(i + 1, s + 1), at(i + 1, s)});
      }
    }
  const auto start = static_cast<std::int32_t>(mesh.positions.size());
  mesh.positions.push_back(first_point - radius * first_tangent);
  mesh.positions.push_back(last_point + radius * last_tangent);
  for (int s = 0; s < segments; ++s) {
    mesh.triangles.push_back({start, at(0, s + 1), at(0, s)});
    mesh.triangles.push_back({start + 1, at(rings - 1, s), at(rings - 1, s + 1)});
  }
  return mesh;
}

Mesh make_spiky_sphere(int level, int spikes, double length, int rings, std::uint32_t seed) {
  if (level < 0 || level > 6) throw std::invalid_argument("make_spiky_sphere: level must be in [0, 6]");
  if (spikes < 0) throw std::invalid_argument("make_spiky_sphere: spikes must be >= 0");
  if (!(std::isfinite(length) && length > 0))
    throw std::invalid_argument("make_spiky_sphere: length must be finite and > 0");
  if (rings < 1 || rings > 10000) throw std::invalid_argument("make_spiky_sphere: rings must be in [1, 10000]");
  Mesh mesh = make_icosphere(level);
  const auto n = mesh.positions.size();
  // Each vertex's triangles, and its neighbours counter-clockwise (from the triangles' orientation).
  std::vector<std::vector<std::size_t>> star(n);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (const auto v : mesh.triangles[t]) star[v].push_back(t);
  auto link = [&](std::int32_t v) {
    std::vector<std::pair<std::int32_t, std::int32_t>> step;
    for (const auto t : star[v]) {
      const auto& tri = mesh.triangles[t];
      const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
      step.emplace_back(tri[(k + 1) % 3], tri[(k + 2) % 3]);
    }
    std::vector<std::int32_t> ring{step.front().first};
    while (ring.size() < step.size())
      for (const auto& [from, to] : step)
        if (from == ring.back()) {
          ring.push_back(to);
          break;
        }
    return ring;
  };
  std::mt19937 generator(seed);
  std::vector<char> blocked(n, 0);
  for (int spike = 0; spike < spikes; ++spike) {
    std::vector<std::int32_t> free;
    for (std::size_t v = 0; v < n; ++v)
      if (!blocked[v]) free.push_back(static_cast<std::int32_t>(v));
    if (free.empty()) break;
    const auto v = free[index_draw(generator, free.size())];
    const auto base = link(v);
    // Spikes two edges apart at least, so that no two tubes start from one vertex.
    blocked[v] = 1;
    for (const auto w : base) {
      blocked[w] = 1;
      for (const auto x : link(w)) blocked[x] = 1;
    }
    // The star of v becomes a tube of `rings` rings, a third as wide as the star, closed by v as its tip.
    const Vec3 apex = mesh.positions[v];
    const auto k = base.size();
    std::vector<std::int32_t> previous = base;
    for (int j = 1; j <= rings; ++j) {
      std::vector<std::int32_t> ring;
      const Vec3 centre = (1 + length * j / (rings + 1)) * apex;
      for (const auto w : base) {
        ring.push_back(static_cast<std::int32_t>(mesh.positions.size()));
        mesh.positions.push_back(centre + (1.0 / 3) * (mesh.positions[w] - apex));
      }
      for (std::size_t i = 0; i < k; ++i) {
        const auto a0 = previous[i], a1 = previous[(i + 1) % k], b0 = ring[i], b1 = ring[(i + 1) % k];
        mesh.triangles.push_back({a0, a1, b1});
        mesh.triangles.push_back({a0, b1, b0});
      }
      previous = ring;
    }
    mesh.positions[v] = (1 + length) * apex;
    for (std::size_t i = 0; i < k; ++i) mesh.triangles[star[v][i]] = {v, previous[i], previous[(i + 1) % k]};
  }
  return mesh;
}

}  // namespace spheremap
