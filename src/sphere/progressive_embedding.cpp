// The progressive embedding (embedding.hpp: progressive_embedding): a hierarchy of vertex removals,
// a convex embedding of its base, and re-insertion level by level with optimization on the sphere.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <unordered_set>
#include <vector>

#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/sphere/embedding.hpp"

namespace spheremap {
namespace {

// Removing a vertex of high degree leaves a wide fan of thin triangles: they are left for later levels.
constexpr std::int32_t kMaxRemovedDegree = 8;
// A rest angle no triangle exceeds in all three corners: every rest triangle counts as equilateral.
constexpr double kEquilateral = 1.1;

// A removed vertex and the polygon its star leaves (its neighbours, counter-clockwise seen from outside).
struct Removal {
  std::int32_t vertex;
  std::vector<std::int32_t> link;
  std::size_t apex;  // the link corner its fan starts from (the vertex collapsed into)
};

// The levels of removals and the triangles of each level: meshes[0] is the input, meshes[L + 1] what
// is left after levels[L].
struct Hierarchy {
  std::vector<std::vector<Removal>> levels;
  std::vector<std::vector<Triangle>> meshes;
};

// A closed triangulation that loses vertices: each removal deletes a star and fills its hole with a fan.
class ShrinkingTriangulation {
 public:
  ShrinkingTriangulation(std::int32_t vertex_count, const std::vector<Triangle>& triangles)
      : triangles_(triangles), alive_(triangles.size(), 1), incident_(vertex_count) {
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (int k = 0; k < 3; ++k) {
        incident_[triangles[t][k]].push_back(static_cast<std::int32_t>(t));
        edges_.insert(key(triangles[t][k], triangles[t][(k + 1) % 3]));
      }
  }

  [[nodiscard]] std::int32_t degree(std::int32_t v) const { return static_cast<std::int32_t>(incident_[v].size()); }
  [[nodiscard]] bool has_edge(std::int32_t a, std::int32_t b) const { return edges_.count(key(a, b)) > 0; }

  // v's neighbours counter-clockwise: each triangle (v, x, y) gives the step x -> y.
  [[nodiscard]] std::vector<std::int32_t> link(std::int32_t v) const {
    std::vector<std::pair<std::int32_t, std::int32_t>> step;
    for (const auto t : incident_[v]) {
      const auto& tri = triangles_[t];
      const int k = tri[0] == v ? 0 : (tri[1] == v ? 1 : 2);
      step.emplace_back(tri[(k + 1) % 3], tri[(k + 2) % 3]);
    }
    std::vector<std::int32_t> ring{step.front().first};
    while (ring.size() < step.size()) {
      const auto from = ring.back();
      const auto found = std::find_if(step.begin(), step.end(), [&](const auto& s) { return s.first == from; });
      if (found == step.end()) throw std::logic_error("progressive_embedding: a vertex's triangles are not one fan");
      ring.push_back(found->second);
    }
    return ring;
  }

  // Deletes v's star and fills the polygon `ring` (v's link) with the fan from ring[apex].
  void remove(std::int32_t v, const std::vector<std::int32_t>& ring, std::size_t apex) {
    for (const auto t : incident_[v]) {
      alive_[t] = 0;
      for (const auto w : triangles_[t]) {
        if (w == v) continue;
        auto& list = incident_[w];
        list.erase(std::find(list.begin(), list.end(), t));
      }
    }
    incident_[v].clear();
    for (const auto w : ring) edges_.erase(key(v, w));
    const auto k = ring.size();
    for (std::size_t i = 1; i + 1 < k; ++i) {
      const Triangle tri{ring[apex], ring[(apex + i) % k], ring[(apex + i + 1) % k]};
      const auto t = static_cast<std::int32_t>(triangles_.size());
      triangles_.push_back(tri);
      alive_.push_back(1);
      for (const auto w : tri) incident_[w].push_back(t);
      if (i >= 2) edges_.insert(key(tri[0], tri[1]));
    }
  }

  [[nodiscard]] std::vector<Triangle> triangles() const {
    std::vector<Triangle> out;
    for (std::size_t t = 0; t < triangles_.size(); ++t)
      if (alive_[t]) out.push_back(triangles_[t]);
    return out;
  }

 private:
  static std::uint64_t key(std::int32_t a, std::int32_t b) {
    const auto low = static_cast<std::uint64_t>(std::min(a, b)), high = static_cast<std::uint64_t>(std::max(a, b));
    return low << 32 | high;
  }
  std::vector<Triangle> triangles_;
  std::vector<char> alive_;
  std::vector<std::vector<std::int32_t>> incident_;
  std::unordered_set<std::uint64_t> edges_;
};

// The fan apex for removing a vertex with link `ring` whose diagonals are not edges already and do not
// join the poles, preferring short diagonals on the surface; -1 if there is none. A fan from a corner
// (the removal is a half-edge collapse into that corner) keeps the polygon star-shaped on any valid map:
// points near the apex see the whole polygon, whatever its number of corners.
int choose_fan(const ShrinkingTriangulation& mesh, const std::vector<std::int32_t>& ring,
               const std::vector<Vec3>& positions, std::int32_t north, std::int32_t south) {
  const auto k = ring.size();
  if (k == 3) return 0;
  int best = -1;
  double best_length = std::numeric_limits<double>::infinity();
  const std::size_t apexes = k == 4 ? 2 : k;  // a quadrilateral's two fans, each from two apexes
  for (std::size_t apex = 0; apex < apexes; ++apex) {
    double length = 0;
    bool usable = true;
    for (std::size_t i = 2; i + 1 < k && usable; ++i) {
      const auto a = ring[apex], b = ring[(apex + i) % k];
      usable = !mesh.has_edge(a, b) && !((a == north && b == south) || (a == south && b == north));
      length += std::sqrt(squared_distance(positions[a], positions[b]));
    }
    if (usable && length < best_length) best = static_cast<int>(apex), best_length = length;
  }
  return best;
}

// Removes independent sets of vertices (never the poles), lowest degree first, until none can be removed.
Hierarchy build_hierarchy(const Mesh& mesh, std::int32_t north, std::int32_t south) {
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  ShrinkingTriangulation shrinking(n, mesh.triangles);
  Hierarchy hierarchy;
  hierarchy.meshes.push_back(mesh.triangles);
  std::vector<char> removed(n, 0);
  while (true) {
    std::vector<std::pair<std::int32_t, std::int32_t>> candidates;  // (degree, vertex)
    for (std::int32_t v = 0; v < n; ++v)
      if (!removed[v] && v != north && v != south && shrinking.degree(v) <= kMaxRemovedDegree)
        candidates.emplace_back(shrinking.degree(v), v);
    std::sort(candidates.begin(), candidates.end());
    std::vector<char> blocked(n, 0);
    std::vector<Removal> level;
    for (const auto& [degree, v] : candidates) {
      if (blocked[v]) continue;
      auto ring = shrinking.link(v);
      const int apex = choose_fan(shrinking, ring, mesh.positions, north, south);
      if (apex < 0) continue;
      shrinking.remove(v, ring, static_cast<std::size_t>(apex));
      removed[v] = blocked[v] = 1;
      for (const auto w : ring) blocked[w] = 1;
      level.push_back({v, std::move(ring), static_cast<std::size_t>(apex)});
    }
    if (level.empty()) break;
    hierarchy.levels.push_back(std::move(level));
    hierarchy.meshes.push_back(shrinking.triangles());
  }
  return hierarchy;
}

// Sutherland–Hodgman: the part of the convex polygon where a·p + b >= 0.
using Point2 = std::array<double, 2>;
std::vector<Point2> clip_half_plane(const std::vector<Point2>& polygon, double ax, double ay, double b) {
  std::vector<Point2> out;
  for (std::size_t k = 0; k < polygon.size(); ++k) {
    const auto& p = polygon[k];
    const auto& q = polygon[(k + 1) % polygon.size()];
    const double fp = ax * p[0] + ay * p[1] + b, fq = ax * q[0] + ay * q[1] + b;
    if (fp >= 0) out.push_back(p);
    if ((fp >= 0) != (fq >= 0)) {
      const double s = fp / (fp - fq);
      out.push_back({p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])});
    }
  }
  return out;
}

// The most central point of the part of a polygon's spherical kernel {p : p·n_i > 0} (n_i the unit
// normals of its edges P_i x P_i+1) that the gnomonic chart around `centre` shows: there the kernel is an
// intersection of half-planes, and bisection on their common margin t finds its middle. Returns the
// margin min_i p·n_i of the point found (normalized), or 0 if that part of the kernel is empty.
double kernel_point_in_chart(const std::vector<Vec3>& normal, const Vec3& centre, Vec3& point) {
  const Vec3 helper = std::abs(centre[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  const Vec3 e1 = normalized(cross(helper, centre));
  const Vec3 e2 = cross(centre, e1);
  constexpr double kReach = 20;  // the chart up to about 87° from the centre
  auto region = [&](double t) {
    std::vector<Point2> area{{-kReach, -kReach}, {kReach, -kReach}, {kReach, kReach}, {-kReach, kReach}};
    for (std::size_t i = 0; i < normal.size() && area.size() >= 3; ++i)
      area = clip_half_plane(area, dot(normal[i], e1), dot(normal[i], e2), dot(normal[i], centre) - t);
    return area;
  };
  if (region(0).size() < 3) return 0;
  double low = 0, high = 30;  // p·n <= |p| <= sqrt(1 + 2 kReach²) < 30
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double middle = 0.5 * (low + high);
    (region(middle).size() >= 3 ? low : high) = middle;
  }
  const auto area = region(0.5 * low);
  if (area.size() < 3) return 0;
  Point2 mean{0, 0};
  for (const auto& q : area)
    mean[0] += q[0] / static_cast<double>(area.size()), mean[1] += q[1] / static_cast<double>(area.size());
  point = normalized(centre + mean[0] * e1 + mean[1] * e2);
  double margin = INFINITY;
  for (const auto& n : normal) margin = std::min(margin, dot(point, n));
  return std::max(margin, 0.0);
}

// A point deep inside the spherical kernel of the polygon (unit vectors, counter-clockwise) whose fan from
// corner `apex` is valid. The kernel lies in the hemisphere around the sum of the edge normals, but for a
// thin polygon near that hemisphere's rim; near the apex it is never empty (the fan's triangles are
// positively oriented), but a polygon wider than a hemisphere may have it there only. So the charts
// around the mean of the corners, the sum of the normals and the apex are tried, the best point kept.
// False if the kernel is empty in doubles.
bool kernel_point(const std::vector<Vec3>& polygon, std::size_t apex, Vec3& point) {
  const auto k = polygon.size();
  std::vector<Vec3> normal(k);
  Vec3 normal_sum{0, 0, 0}, corner_sum{0, 0, 0};
  for (std::size_t i = 0; i < k; ++i) {
    normal[i] = normalized(cross(polygon[i], polygon[(i + 1) % k]));
    if (norm(normal[i]) == 0) return false;
    normal_sum = normal_sum + normal[i];
    corner_sum = corner_sum + polygon[i];
  }
  double best = 0;
  for (const Vec3& centre : {corner_sum, normal_sum, polygon[apex]}) {
    if (!(norm(centre) > 1e-9)) continue;
    Vec3 candidate{};
    const double margin = kernel_point_in_chart(normal, normalized(centre), candidate);
    if (margin > best) best = margin, point = candidate;
  }
  return best > 0;
}

// The vertices of `triangles` in increasing order, and each one's index among them.
struct LocalIndex {
  std::vector<std::int32_t> vertices;
  std::vector<std::int32_t> local;  // -1 for vertices not in the mesh
};
LocalIndex local_index(std::int32_t vertex_count, const std::vector<Triangle>& triangles) {
  LocalIndex index{{}, std::vector<std::int32_t>(vertex_count, -1)};
  for (const auto& tri : triangles)
    for (const auto v : tri) index.local[v] = 0;
  for (std::int32_t v = 0; v < vertex_count; ++v)
    if (index.local[v] == 0)
      index.local[v] = static_cast<std::int32_t>(index.vertices.size()), index.vertices.push_back(v);
  return index;
}

// optimize_on_sphere on one level's mesh (its vertices only), with the poles fixed.
SphereOptimizeReport optimize_level(const Mesh& mesh, const std::vector<Triangle>& triangles, std::int32_t north,
                                    std::int32_t south, std::vector<Vec3>& sphere, SphereOptimizeOptions options,
                                    int iterations) {
  const auto index = local_index(static_cast<std::int32_t>(mesh.positions.size()), triangles);
  const auto count = index.vertices.size();
  std::vector<Vec3> rest(count), points(count);
  std::vector<char> fixed(count, 0);
  for (std::size_t i = 0; i < count; ++i) {
    const auto v = index.vertices[i];
    rest[i] = mesh.positions[v];
    points[i] = sphere[v];
    fixed[i] = v == north || v == south;
  }
  std::vector<Triangle> local(triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) local[t][k] = index.local[triangles[t][k]];
  // Rest positions that are not finite give no energy to descend (optimize_on_sphere refuses them): such
  // a level keeps the points insertion gave it, which are a valid map.
  for (const auto& p : rest)
    if (!std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2])) return {};
  options.max_iterations = iterations;
  const auto report = optimize_on_sphere(rest, local, points, fixed, options);
  for (std::size_t i = 0; i < count; ++i) sphere[index.vertices[i]] = points[i];
  return report;
}

bool star_is_valid(const std::vector<Vec3>& sphere, const Removal& removal) {
  const auto k = removal.link.size();
  for (std::size_t i = 0; i < k; ++i)
    if (orientation_sign(sphere[removal.vertex], sphere[removal.link[i]], sphere[removal.link[(i + 1) % k]]) <= 0)
      return false;
  return true;
}

// Puts each removed vertex of one level inside the kernel of its link polygon (the polygons of one
// level do not overlap and their corners do not move, so the order does not matter). Returns how many
// could not be put where every triangle of their star is positively oriented.
std::int64_t insert_level(const std::vector<Removal>& level, std::vector<Vec3>& sphere) {
  std::int64_t failed = 0;
  std::vector<Vec3> polygon;
  for (const auto& removal : level) {
    polygon.clear();
    for (const auto w : removal.link) polygon.push_back(sphere[w]);
    Vec3 point{};
    if (kernel_point(polygon, removal.apex, point)) sphere[removal.vertex] = point;
    if (!star_is_valid(sphere, removal)) ++failed;
  }
  return failed;
}

// The base of the hierarchy on the sphere (convex_embedding, with its own indices); false if a triangle
// came out not positively oriented.
bool embed_base(std::int32_t vertex_count, const std::vector<Triangle>& base, std::int32_t north, std::int32_t south,
                std::vector<Vec3>& sphere, std::int32_t& base_vertices) {
  const auto index = local_index(vertex_count, base);
  base_vertices = static_cast<std::int32_t>(index.vertices.size());
  std::vector<Triangle> local(base.size());
  for (std::size_t t = 0; t < base.size(); ++t)
    for (int k = 0; k < 3; ++k) local[t][k] = index.local[base[t][k]];
  const auto base_sphere = convex_embedding(base_vertices, local, index.local[north], index.local[south]);
  sphere.assign(vertex_count, Vec3{0, 0, 0});
  for (std::size_t i = 0; i < index.vertices.size(); ++i) sphere[index.vertices[i]] = base_sphere[i];
  return positively_oriented(base, sphere);
}

}  // namespace

ProgressiveEmbeddingReport progressive_embedding(const Mesh& mesh, std::int32_t north, std::int32_t south,
                                                 std::vector<Vec3>& sphere,
                                                 const ProgressiveEmbeddingOptions& options) {
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  if (north < 0 || south < 0 || north >= n || south >= n || north == south)
    throw std::invalid_argument("progressive_embedding: poles " + std::to_string(north) + ", " + std::to_string(south) +
                                " must be two different vertices in [0, " + std::to_string(n) + ")");
  ProgressiveEmbeddingReport report;
  const Hierarchy hierarchy = build_hierarchy(mesh, north, south);
  report.levels = static_cast<int>(hierarchy.levels.size());
  if (!embed_base(n, hierarchy.meshes.back(), north, south, sphere, report.base_vertices)) return report;

  // Coarse levels aim at equilateral triangles of the surface's areas: what matters there is wide
  // kernels for the next insertions (thin fans would shrink every level's new triangles further).
  SphereOptimizeOptions coarse = options.optimize;
  coarse.relative_tolerance = options.level_tolerance;
  coarse.min_rest_angle = kEquilateral;
  report.optimizer_iterations +=
      optimize_level(mesh, hierarchy.meshes.back(), north, south, sphere, coarse, options.level_iterations).iterations;
  // Levels back from the coarsest: insert, then optimize. A level whose insertions fail (kernels too
  // thin for doubles) is tried once more after optimizing the level below it to convergence.
  for (auto level = static_cast<std::int64_t>(hierarchy.levels.size()) - 1; level >= 0; --level) {
    const auto& removals = hierarchy.levels[level];
    report.insertions += static_cast<std::int64_t>(removals.size());
    if (insert_level(removals, sphere) > 0) {
      SphereOptimizeOptions thorough = coarse;
      thorough.relative_tolerance = options.final_tolerance;
      report.optimizer_iterations +=
          optimize_level(mesh, hierarchy.meshes[level + 1], north, south, sphere, thorough, options.final_iterations)
              .iterations;
      report.failed_insertions = insert_level(removals, sphere);
      if (report.failed_insertions > 0) return report;
    }
    if (level > 0)
      report.optimizer_iterations +=
          optimize_level(mesh, hierarchy.meshes[level], north, south, sphere, coarse, options.level_iterations)
              .iterations;
  }
  // The input's own triangles, with their own shapes.
  SphereOptimizeOptions fine = options.optimize;
  fine.relative_tolerance = options.final_tolerance;
  const auto result = optimize_level(mesh, mesh.triangles, north, south, sphere, fine, options.final_iterations);
  report.optimizer_iterations += result.iterations;
  report.final_iterations = result.iterations;
  report.energy_before = result.energy_before;
  report.energy_after = result.energy_after;
  report.final_stop_reason = result.stop_reason;
  report.valid =
      sphere[north] == Vec3{0, 0, 1} && sphere[south] == Vec3{0, 0, -1} && positively_oriented(mesh.triangles, sphere);
  return report;
}

}  // namespace spheremap
