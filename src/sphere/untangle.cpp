#include "untangle.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include "../util/parallel.hpp"
#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/certify.hpp"

namespace spheremap::detail {

std::vector<double> target_solid_angles(const Mesh& surface) {
  std::vector<double> target(surface.triangles.size());
  double total = 0;
  for (std::size_t t = 0; t < target.size(); ++t) {
    const auto& tri = surface.triangles[t];
    target[t] = triangle_area(surface.positions[tri[0]], surface.positions[tri[1]], surface.positions[tri[2]]);
    total += target[t];
  }
  for (auto& a : target) a = std::max(a / total * 4 * std::numbers::pi, 1e-300);
  return target;
}

namespace {

struct Star {
  std::vector<std::int32_t> ring;       // neighbours, counter-clockwise
  std::vector<std::int32_t> triangles;  // triangle k = (v, ring[k], ring[k+1])
};

// A convex polygon clipped by half-planes a·p + b >= 0 (Sutherland–Hodgman), in a gnomonic chart, into
// `out` (whose memory is reused: a move clips its star's polygon thousands of times).
using Point2 = std::array<double, 2>;
void clip(const std::vector<Point2>& polygon, double ax, double ay, double b, std::vector<Point2>& out) {
  out.clear();
  const auto size = polygon.size();
  for (std::size_t k = 0; k < size; ++k) {
    const auto& p = polygon[k];
    const auto& q = polygon[(k + 1) % size];
    const double fp = ax * p[0] + ay * p[1] + b, fq = ax * q[0] + ay * q[1] + b;
    if (fp >= 0) out.push_back(p);
    if ((fp >= 0) != (fq >= 0)) {
      const double s = fp / (fp - fq);
      out.push_back({p[0] + s * (q[0] - p[0]), p[1] + s * (q[1] - p[1])});
    }
  }
}

class Untangler {
 public:
  Untangler(const Mesh& surface, const VertexRings& rings, const UntanglingFrame& frame, std::vector<Vec3>& sphere,
            double floor)
      : surface_(surface),
        rings_(rings),
        sphere_(sphere),
        floor_(floor),
        target_(frame.target),
        star_triangle_(frame.star_triangle) {}

  // Smallest quality of the triangles around v if v were at p: solid angle / target, where a triangle
  // the exact predicate calls folded counts as negative whatever the rounded solid angle says.
  double star_quality(std::int32_t v, const Vec3& p) const {
    const auto ring = rings_.ring(v);
    double worst = INFINITY;
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const auto& a = sphere_[ring[k]];
      const auto& b = sphere_[ring[(k + 1) % ring.size()]];
      const auto t = star_triangle_[rings_.offsets[v] + static_cast<std::int64_t>(k)];
      double quality = signed_solid_angle(p, a, b) / target_[t];
      if (orientation_sign(p, a, b) <= 0) quality = std::min(quality, 0.0) - 1e-300;
      worst = std::min(worst, quality);
    }
    return worst;
  }

  bool triangle_is_bad(std::int32_t t) const {
    const auto& tri = surface_.triangles[t];
    const auto &a = sphere_[tri[0]], &b = sphere_[tri[1]], &c = sphere_[tri[2]];
    if (orientation_sign(a, b, c) <= 0) return true;
    return signed_solid_angle(a, b, c) / target_[t] < floor_;
  }

  // Moves v to the best point of its kernel in a gnomonic chart; true if the star got better.
  bool move(std::int32_t v) {
    const auto ring = rings_.ring(v);
    const auto size = ring.size();
    Vec3 centre{0, 0, 0};
    for (auto w : ring) centre = centre + sphere_[w];
    centre = normalized(centre);
    if (norm(centre) == 0) return false;
    for (auto w : ring)
      if (dot(sphere_[w], centre) <= 1e-3) return false;  // the ring is not within a hemisphere chart
    // Orthonormal frame (e1, e2, centre), right-handed so orientations are kept.
    const Vec3 helper = std::abs(centre[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
    const Vec3 e1 = normalized(cross(helper, centre));
    const Vec3 e2 = cross(centre, e1);
    std::vector<Point2> chart(size);
    for (std::size_t k = 0; k < size; ++k) {
      const auto& w = sphere_[ring[k]];
      const double h = dot(w, centre);
      chart[k] = {dot(w, e1) / h, dot(w, e2) / h};
    }
    // Half-plane for triangle k: orient2d(p, A, B) >= t * scale_k, i.e. linear in p.
    std::vector<std::array<double, 3>> lines(size);  // ax, ay, b with orient2d = ax*px + ay*py + b
    std::vector<double> scale(size);
    for (std::size_t k = 0; k < size; ++k) {
      const auto& A = chart[k];
      const auto& B = chart[(k + 1) % size];
      lines[k] = {A[1] - B[1], B[0] - A[0], A[0] * B[1] - A[1] * B[0]};
      const auto t = star_triangle_[rings_.offsets[v] + static_cast<std::int64_t>(k)];
      scale[k] = target_[t];
    }
    double extent = 0;
    for (const auto& c : chart) extent = std::max({extent, std::abs(c[0]), std::abs(c[1])});
    const std::vector<Point2> box{
        {-2 * extent, -2 * extent}, {2 * extent, -2 * extent}, {2 * extent, 2 * extent}, {-2 * extent, 2 * extent}};
    auto region_for = [&](double t) -> const std::vector<Point2>& {
      polygon_ = box;
      for (std::size_t k = 0; k < size && !polygon_.empty(); ++k) {
        clip(polygon_, lines[k][0], lines[k][1], lines[k][2] - t * scale[k], clipped_);
        polygon_.swap(clipped_);
      }
      return polygon_;
    };
    // Bisection on t for the largest t with a non-empty region: the point whose worst triangle is best.
    // t may be negative: when the kernel is empty the move still makes the worst fold less bad.
    double current_t = INFINITY;
    {
      const Vec3& p = sphere_[v];
      const double h = dot(p, centre);
      if (h <= 0) return false;
      const Point2 here{dot(p, e1) / h, dot(p, e2) / h};
      for (std::size_t k = 0; k < size; ++k)
        current_t = std::min(current_t, (lines[k][0] * here[0] + lines[k][1] * here[1] + lines[k][2]) / scale[k]);
    }
    double low = current_t, high = std::max(current_t, 0.0) + 1;
    if (region_for(low).size() < 3) return false;
    while (region_for(high).size() >= 3 && high < 1e12) low = high, high *= 4;
    for (int iteration = 0; iteration < 50; ++iteration) {
      const double middle = 0.5 * (low + high);
      (region_for(middle).size() >= 3 ? low : high) = middle;
    }
    // Slightly inside the optimum, so that the region has an interior whose centroid is robust.
    const auto& region = region_for(low - 1e-3 * std::abs(low - current_t));
    if (region.size() < 3) return false;
    Point2 mean{0, 0};
    for (const auto& q : region)
      mean[0] += q[0] / static_cast<double>(region.size()), mean[1] += q[1] / static_cast<double>(region.size());
    const Vec3 candidate = normalized(centre + mean[0] * e1 + mean[1] * e2);
    if (star_quality(v, candidate) > star_quality(v, sphere_[v])) {
      sphere_[v] = candidate;
      return true;
    }
    return false;
  }

  std::int64_t run(int max_sweeps, const std::vector<char>& fixed) {
    std::int64_t moves = 0;
    int neighbourhood = 0;  // 0: vertices of bad triangles; k: plus their k-ring
    // Which triangles are bad, kept up to date: a triangle's badness depends on its corners only, so
    // after the first scan only the triangles around moved vertices are checked again (a sweep over a
    // million-triangle map with a few thousand bad ones re-checked every triangle: most of the time).
    const auto triangles = static_cast<std::int32_t>(surface_.triangles.size());
    std::vector<char> bad(static_cast<std::size_t>(triangles), 0);
    detail::parallel_ranges(triangles, 16384, detail::surface_threads(0), [&](std::int64_t first, std::int64_t last) {
      for (auto t = static_cast<std::int32_t>(first); t < last; ++t) bad[t] = triangle_is_bad(t) ? 1 : 0;
    });
    std::int64_t bad_count = std::count(bad.begin(), bad.end(), 1);
    std::vector<std::int32_t> moved_vertices;
    for (int sweep = 0; sweep < max_sweeps; ++sweep) {
      if (bad_count == 0) break;
      std::vector<char> active(sphere_.size(), 0);
      for (std::int32_t t = 0; t < triangles; ++t)
        if (bad[t])
          for (auto v : surface_.triangles[t]) active[v] = 1;
      for (int grow = 0; grow < neighbourhood; ++grow) {
        auto grown = active;
        for (std::int32_t v = 0; v < static_cast<std::int32_t>(active.size()); ++v)
          if (active[v])
            for (auto w : rings_.ring(v)) grown[w] = 1;
        active.swap(grown);
      }
      moved_vertices.clear();
      for (std::int32_t v = 0; v < static_cast<std::int32_t>(active.size()); ++v)
        if (active[v] && (fixed.empty() || !fixed[v]) && move(v)) moved_vertices.push_back(v);
      for (const auto v : moved_vertices)
        for (auto slot = rings_.offsets[v]; slot < rings_.offsets[v + 1]; ++slot) {
          const auto t = star_triangle_[static_cast<std::size_t>(slot)];
          const char now = triangle_is_bad(t) ? 1 : 0;
          bad_count += now - bad[t];
          bad[t] = now;
        }
      const auto moved = static_cast<std::int64_t>(moved_vertices.size());
      moves += moved;
      neighbourhood = moved == 0 ? std::min(neighbourhood + 1, 8) : 0;
    }
    return moves;
  }

 private:
  const Mesh& surface_;
  const VertexRings& rings_;
  std::vector<Vec3>& sphere_;
  double floor_;
  const std::vector<double>& target_;
  const std::vector<std::int32_t>& star_triangle_;
  std::vector<Point2> polygon_, clipped_;  // scratch of move's clipping
};

}  // namespace

UntanglingFrame untangling_frame(const Mesh& surface, const VertexRings& rings) {
  UntanglingFrame frame{target_solid_angles(surface), std::vector<std::int32_t>(rings.neighbors.size(), -1)};
  // Each slot (v, next) belongs to exactly one triangle, so the triangles fill their slots on any thread.
  const auto triangles = static_cast<std::int32_t>(surface.triangles.size());
  detail::parallel_ranges(triangles, 16384, detail::surface_threads(0), [&](std::int64_t first, std::int64_t last) {
    for (auto t = static_cast<std::int32_t>(first); t < last; ++t) {
      const auto& tri = surface.triangles[t];
      for (int s = 0; s < 3; ++s) {
        const auto v = tri[s], next = tri[(s + 1) % 3];
        const auto ring = rings.ring(v);
        for (std::size_t k = 0; k < ring.size(); ++k)
          if (ring[k] == next) frame.star_triangle[rings.offsets[v] + static_cast<std::int64_t>(k)] = t;
      }
    }
  });
  return frame;
}

std::int64_t untangle_on_sphere(const Mesh& surface, const VertexRings& rings, const UntanglingFrame& frame,
                                std::vector<Vec3>& sphere, double collapse_floor, int max_sweeps,
                                const std::vector<char>& fixed) {
  if (!fixed.empty() && fixed.size() != sphere.size())
    throw std::invalid_argument("untangle_on_sphere: " + std::to_string(fixed.size()) + " fixed flags for " +
                                std::to_string(sphere.size()) + " points");
  Untangler untangler(surface, rings, frame, sphere, collapse_floor);
  return untangler.run(max_sweeps, fixed);
}

}  // namespace spheremap::detail
