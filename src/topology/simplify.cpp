#include "spheremap/topology/simplify.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <thread>
#include <utility>

#include "../util/parallel.hpp"
#include "simplify_tuning.hpp"
#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

constexpr std::int32_t kDead = -1;
// A triangle with a corner below 10 degrees (cosine above this) has a normal that a small move of one
// vertex turns a lot: a collapse is then judged against its fan's vector area, not against that normal.
constexpr double kSliverCosine = 0.98480775301220802;

inline int next_corner(int k) { return k == 2 ? 0 : k + 1; }
inline int previous_corner(int k) { return k == 0 ? 2 : k - 1; }

// Distance from p to the triangle abc (closest point by region, Ericson, Real-Time Collision Detection 5.1.5).
double point_triangle_distance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= 0 && d2 <= 0) return norm(ap);
  const Vec3 bp = p - b;
  const double d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= 0 && d4 <= d3) return norm(bp);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return norm(p - (a + (d1 / (d1 - d3)) * ab));
  const Vec3 cp = p - c;
  const double d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= 0 && d5 <= d6) return norm(cp);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return norm(p - (a + (d2 / (d2 - d6)) * ac));
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return norm(p - (b + ((d4 - d3) / ((d4 - d3) + (d5 - d6))) * (c - b)));
  const double denominator = 1 / (va + vb + vc);
  return norm(p - (a + (vb * denominator) * ab + (vc * denominator) * ac));
}

// Distance between the segments pq and rs (Ericson 5.1.9).
double segment_distance(const Vec3& p, const Vec3& q, const Vec3& r, const Vec3& s) {
  const Vec3 d1 = q - p, d2 = s - r, w = p - r;
  const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, w);
  double u = 0, v = 0;
  if (a <= 0 && e <= 0) return norm(w);
  if (a <= 0) {
    v = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = dot(d1, w);
    if (e <= 0) {
      u = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = dot(d1, d2), denominator = a * e - b * b;
      u = denominator > 0 ? std::clamp((b * f - c * e) / denominator, 0.0, 1.0) : 0.0;
      v = (b * u + f) / e;
      if (v < 0)
        v = 0, u = std::clamp(-c / a, 0.0, 1.0);
      else if (v > 1)
        v = 1, u = std::clamp((b - c) / a, 0.0, 1.0);
    }
  }
  return norm((p + u * d1) - (r + v * d2));
}

// The largest cosine of the three corner angles (the cosine of the smallest angle, which faces the
// shortest side; law of cosines): larger is worse. 1 for a degenerate triangle.
double worst_corner_cosine(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double ab = squared_distance(a, b), bc = squared_distance(b, c), ca = squared_distance(c, a);
  const double shortest = std::min({ab, bc, ca});
  const double product = ab * bc * ca / shortest;  // the other two sides, squared and multiplied
  if (!(product > 0)) return 1;
  return (ab + bc + ca - 2 * shortest) / (2 * std::sqrt(product));
}

// A closed oriented triangle 2-manifold as a corner table: half-edge h = 3t + k runs from tri[t][k] to
// tri[t][k+1]; opp[h] is the half-edge running the other way in the neighbouring triangle.
class Surface {
 public:
  // An edge to try to collapse; a < b unless it comes from a sliver. 8 bytes: a first round on a fine
  // molecular surface has tens of millions of them.
  struct Candidate {
    std::int32_t a, b;
  };
  // Scratch space of one thread, and what it did.
  struct Workspace {
    std::vector<std::int32_t> ring_a, ring_b, fan;
    std::vector<Vec3> points_a, points_b;
    std::vector<double> worst_a, worst_b;
    std::vector<Candidate> deferred;
    std::vector<std::int32_t> removed;     // vertices collapsed, not yet taken off their component's size
    std::vector<std::int64_t> removed_in;  // per component: collapses in this zone this round
  };

  // Takes the mesh's triangles (they become the working copy); its positions must outlive the Surface.
  Surface(Mesh& mesh, const SimplifyOptions& options, int threads)
      : p_(mesh.positions), tri_(std::move(mesh.triangles)), options_(options), threads_(threads) {
    const auto vertices = static_cast<std::int32_t>(p_.size());
    const auto half_edges = static_cast<std::int64_t>(tri_.size()) * 3;
    if (half_edges >= std::numeric_limits<std::int32_t>::max())
      throw std::invalid_argument("simplify_surface: more than 2^31 half-edges");
    for (const auto& t : tri_)
      for (const auto v : t)
        if (v < 0 || v >= vertices) throw std::invalid_argument("simplify_surface: a triangle index is out of range");
    pair_half_edges();
    // One leaving half-edge per vertex; each vertex's triangles must form one fan.
    out_.assign(static_cast<std::size_t>(vertices), kDead);
    {
      std::vector<std::int32_t> corners(static_cast<std::size_t>(vertices), 0);
      for (std::int32_t h = 0; h < half_edges; ++h) out_[from(h)] = h, ++corners[from(h)];
      for (std::int32_t v = 0; v < vertices; ++v) {
        if (out_[v] == kDead) throw std::invalid_argument("simplify_surface: a vertex belongs to no triangle");
        if (degree(v) != corners[v])
          throw std::invalid_argument("simplify_surface: a vertex's triangles form several fans (a pinched vertex)");
      }
    }
    // Components (by shared vertices), numbered by their smallest vertex, and their vertex counts: none may
    // shrink below 4 (a tetrahedron). Per-component figures are indexed by that number, not by vertex: a
    // contour has millions of vertices and a handful of components.
    {
      std::vector<std::int32_t> parent(static_cast<std::size_t>(vertices));
      std::iota(parent.begin(), parent.end(), 0);
      auto root = [&](std::int32_t v) {
        while (parent[v] != v) v = parent[v] = parent[parent[v]];
        return v;
      };
      for (const auto& t : tri_)
        for (int k = 1; k < 3; ++k) {
          const auto a = root(t[0]), b = root(t[k]);
          if (a != b) parent[std::max(a, b)] = std::min(a, b);
        }
      // A root is the smallest vertex of its component, so it is numbered before any other vertex of it.
      component_.resize(static_cast<std::size_t>(vertices));
      for (std::int32_t v = 0; v < vertices; ++v) {
        const std::int32_t r = root(v);
        if (r == v) {
          component_[v] = static_cast<std::int32_t>(component_size_.size());
          component_size_.push_back(0);
        } else {
          component_[v] = component_[r];
        }
        ++component_size_[component_[v]];
      }
    }
    merged_into_.assign(static_cast<std::size_t>(vertices), kDead);
    quality_.resize(tri_.size());
    unflippable_.assign(tri_.size(), 0);
    skip_unflippable_ = detail::simplify_skips_known_unflippable_edges();
    for (std::size_t t = 0; t < tri_.size(); ++t) quality_[t] = triangle_cosine(static_cast<std::int32_t>(t));
    if (!options.oriented_on.empty()) {
      if (options.oriented_on.size() != p_.size())
        throw std::invalid_argument("simplify_surface: oriented_on has " + std::to_string(options.oriented_on.size()) +
                                    " points for " + std::to_string(p_.size()) + " vertices");
      for (const auto& t : tri_)
        if (!keeps_orientation(t[0], t[1], t[2]))
          throw std::invalid_argument("simplify_surface: a triangle is not positively oriented on oriented_on");
    }
    kept_.assign(static_cast<std::size_t>(vertices), false);
    for (const auto v : options.kept_vertices) {
      if (v < 0 || v >= vertices) throw std::invalid_argument("simplify_surface: a kept vertex does not exist");
      kept_[v] = true;
    }
    cos_min_angle_ = std::cos(options.min_angle_degrees * std::numbers::pi / 180);
    const double cos_normal_change = std::cos(options.max_normal_change_degrees * std::numbers::pi / 180);
    cos_normal_change_squared_ = cos_normal_change * cos_normal_change;
    const double high = options.target_edge_length * 4 / 3;
    longest_squared_ = high * high;
  }

  // opp_: the half-edge across each edge, every edge shared by exactly two triangles in opposite directions.
  void pair_half_edges() {
    opp_ = opposite_half_edges(p_.size(), tri_, threads_);
    if (std::find(opp_.begin(), opp_.end(), kDead) != opp_.end())
      throw std::invalid_argument(
          "simplify_surface: the mesh is not a closed, consistently oriented 2-manifold (an edge is not shared by "
          "exactly two triangles in opposite directions)");
  }

  [[nodiscard]] std::int32_t from(std::int32_t h) const { return tri_[h / 3][h % 3]; }
  [[nodiscard]] std::int32_t to(std::int32_t h) const { return tri_[h / 3][next_corner(h % 3)]; }
  // The third vertex of h's triangle.
  [[nodiscard]] std::int32_t apex(std::int32_t h) const { return tri_[h / 3][previous_corner(h % 3)]; }
  // The next half-edge leaving from(h): the one that runs back along h's triangle's previous edge.
  [[nodiscard]] std::int32_t rotate(std::int32_t h) const { return opp_[3 * (h / 3) + previous_corner(h % 3)]; }

  [[nodiscard]] std::int32_t degree(std::int32_t v) const {
    std::int32_t count = 0, h = out_[v];
    do ++count, h = rotate(h);
    while (h != out_[v]);
    return count;
  }
  [[nodiscard]] bool alive_vertex(std::int32_t v) const { return out_[v] != kDead; }
  [[nodiscard]] bool alive_triangle(std::int32_t t) const { return tri_[t][0] != kDead; }

  // The half-edge from u to v, or kDead when they are not adjacent.
  [[nodiscard]] std::int32_t half_edge(std::int32_t u, std::int32_t v) const {
    std::int32_t h = out_[u];
    do {
      if (to(h) == v) return h;
      h = rotate(h);
    } while (h != out_[u]);
    return kDead;
  }

  // worst_corner_cosine of triangle t.
  [[nodiscard]] double triangle_cosine(std::int32_t t) const {
    return worst_corner_cosine(p_[tri_[t][0]], p_[tri_[t][1]], p_[tri_[t][2]]);
  }

  // Triangle t changed (its corners, or what lies across its edges): its edges may flip again, seen
  // from either side.
  void forget_unflippable(std::int32_t t) {
    unflippable_[t] = 0;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t across = opp_[3 * t + k];
      unflippable_[across / 3] &= static_cast<std::uint8_t>(~(1u << (across % 3)));
    }
  }

  // The triangle (a, b, c) is positively oriented on options.oriented_on (or that is not asked).
  [[nodiscard]] bool keeps_orientation(std::int32_t a, std::int32_t b, std::int32_t c) const {
    const auto& q = options_.oriented_on;
    return q.empty() || orientation_sign(q[a], q[b], q[c]) > 0;
  }

  // normal . reference >= cos(max turn) |normal| |reference|, without square roots (the turn is below 90
  // degrees, so both sides are positive when it holds).
  [[nodiscard]] bool faces_within_turn(const Vec3& normal, const Vec3& reference, double reference_squared) const {
    const double along = dot(normal, reference);
    return along > 0 && along * along >= cos_normal_change_squared_ * dot(normal, normal) * reference_squared;
  }

  // The neighbours of v in rotation order (triangles (v, ring[i], ring[i + 1])), with their positions;
  // returns the half-edge from v to `target` (kDead if they are not adjacent).
  // `worst` gets the worst_corner_cosine of each triangle (v, ring[i], ring[i + 1]).
  std::int32_t gather_ring(std::int32_t v, std::int32_t target, std::vector<std::int32_t>& ring,
                           std::vector<Vec3>& points, std::vector<double>& worst) const {
    ring.clear(), points.clear(), worst.clear();
    std::int32_t g = out_[v], found = kDead;
    do {
      const std::int32_t w = to(g);
      if (w == target) found = g;
      ring.push_back(w), points.push_back(p_[w]), worst.push_back(quality_[g / 3]);
      g = rotate(g);
    } while (g != out_[v]);
    return found;
  }

  // Checks merging u (at pu, neighbours `ring` at `points`) into its neighbour ring[j]. When allowed,
  // returns true with the largest corner cosine of the triangles it makes (smaller is better) in *worst and
  // the distance of u from them in *distance. The link condition and the degrees of the two apexes are
  // the caller's (they do not depend on the direction).
  bool collapse_allowed(const Vec3& pu, const std::vector<std::int32_t>& ring, const std::vector<Vec3>& points,
                        const std::vector<double>& old_cosines, std::size_t j, bool must_improve, double* worst,
                        double* distance) {
    const std::size_t n = ring.size();
    const Vec3& pv = points[j];
    const std::size_t before = (j + n - 1) % n, after = (j + 1) % n;
    // The new edges (v to u's other neighbours) first: the cheapest test.
    for (std::size_t i = 0; i < n; ++i)
      if (i != j && i != before && i != after && squared_distance(pv, points[i]) > longest_squared_) return false;
    // The vector area of u's fan depends only on its link polygon, so the new fan has the same: a new
    // triangle must face within the allowed turn of it (a sliver's own normal says little, so it is not
    // the reference).
    Vec3 fan_area{0, 0, 0};
    for (std::size_t i = 0; i < n; ++i) fan_area = fan_area + cross(points[i], points[i + 1 == n ? 0 : i + 1]);
    const double fan_area_squared = dot(fan_area, fan_area);
    double old_worst = -1, new_worst = -1;
    for (std::size_t i = 0; i < n; ++i) {
      const std::size_t next = i + 1 == n ? 0 : i + 1;
      const Vec3 &p1 = points[i], &p2 = points[next];
      const double old_cosine = old_cosines[i];
      old_worst = std::max(old_worst, old_cosine);
      if (i == j || next == j) continue;  // the two triangles that vanish
      if (!keeps_orientation(ring[j], ring[i], ring[next])) return false;
      const Vec3 new_normal = cross(p1 - pv, p2 - pv);
      if (old_cosine < kSliverCosine) {
        const Vec3 old_normal = cross(p1 - pu, p2 - pu);
        if (!faces_within_turn(new_normal, old_normal, dot(old_normal, old_normal))) return false;
      } else if (!faces_within_turn(new_normal, fan_area, fan_area_squared)) {
        return false;
      }
      new_worst = std::max(new_worst, worst_corner_cosine(pv, p1, p2));
    }
    if (new_worst > std::max(old_worst, cos_min_angle_) || (must_improve && !(new_worst < old_worst))) return false;
    // The first new triangle within the tolerance settles it (its distance breaks ties between the two
    // directions).
    double nearest = INFINITY;
    for (std::size_t i = 0; i < n && !(nearest <= options_.max_error); ++i) {
      const std::size_t next = i + 1 == n ? 0 : i + 1;
      if (i != j && next != j) nearest = std::min(nearest, point_triangle_distance(pu, pv, points[i], points[next]));
    }
    if (!(nearest <= options_.max_error)) return false;
    *worst = new_worst, *distance = nearest;
    return true;
  }

  enum class Outcome { kCollapsed, kRefused, kDeferred };

  // Collapses the edge ab in whichever allowed direction makes the better-shaped triangles (then the
  // nearer). Refused when neither is allowed or a and b are no longer adjacent.
  // With `for_quality` (an edge no shorter than the collapse threshold, on a sliver) only while one of
  // its two triangles is still a sliver, and only if the collapse raises the smallest angle around it.
  // With zone >= 0 (a parallel pass) a collapse that would read or change anything outside the zone, or
  // could shrink a component to a tetrahedron, is deferred to the serial pass instead.
  Outcome try_collapse(std::int32_t a, std::int32_t b, bool for_quality, Workspace& w, int zone) {
    auto outside_zone = [&](const std::vector<std::int32_t>& ring) {
      return zone >= 0 && std::any_of(ring.begin(), ring.end(), [&](std::int32_t x) { return zone_[x] != zone; });
    };
    const std::int32_t ab = gather_ring(a, b, w.ring_a, w.points_a, w.worst_a);
    if (ab == kDead) return Outcome::kRefused;
    if (outside_zone(w.ring_a)) return Outcome::kDeferred;
    if (for_quality && !(quality_[ab / 3] > cos_min_angle_ || quality_[opp_[ab] / 3] > cos_min_angle_))
      return Outcome::kRefused;
    const std::int32_t component = component_[a];
    if (zone >= 0 &&
        w.removed_in[static_cast<std::size_t>(component)] >= zone_budget_[static_cast<std::size_t>(component)])
      return Outcome::kDeferred;
    if (component_size_[component_[a]] <= 4) return Outcome::kRefused;
    // The apexes of the two triangles on ab each lose an edge: they need degree 4 or more.
    if (degree(apex(ab)) < 4 || degree(apex(opp_[ab])) < 4) return Outcome::kRefused;
    const std::int32_t ba = opp_[ab];
    gather_ring(b, kDead, w.ring_b, w.points_b, w.worst_b);
    if (outside_zone(w.ring_b)) return Outcome::kDeferred;
    // Link condition: a and b have exactly the two apexes as common neighbours (with more than 4 vertices
    // in the component this also rules out a shared link edge).
    int common = 0;
    for (const auto x : w.ring_a) common += static_cast<int>(std::count(w.ring_b.begin(), w.ring_b.end(), x));
    if (common != 2) return Outcome::kRefused;
    const auto b_in_a = static_cast<std::size_t>(std::find(w.ring_a.begin(), w.ring_a.end(), b) - w.ring_a.begin());
    const auto a_in_b = static_cast<std::size_t>(std::find(w.ring_b.begin(), w.ring_b.end(), a) - w.ring_b.begin());
    double worst_ab = 0, worst_ba = 0, distance_ab = 0, distance_ba = 0;
    const bool remove_a = !kept_[a] && collapse_allowed(p_[a], w.ring_a, w.points_a, w.worst_a, b_in_a, for_quality,
                                                        &worst_ab, &distance_ab);
    const bool remove_b = !kept_[b] && collapse_allowed(p_[b], w.ring_b, w.points_b, w.worst_b, a_in_b, for_quality,
                                                        &worst_ba, &distance_ba);
    if (!remove_a && !remove_b) return Outcome::kRefused;
    const bool a_goes =
        remove_a && (!remove_b || worst_ab < worst_ba || (worst_ab == worst_ba && distance_ab <= distance_ba));
    collapse(a_goes ? ab : ba, w);
    if (zone >= 0) ++w.removed_in[static_cast<std::size_t>(component)];
    return Outcome::kCollapsed;
  }

  // Merges from(h) into to(h): its two triangles go, the others get to(h) in its place.
  // Component sizes are the caller's (see Workspace::removed).
  void collapse(std::int32_t h, Workspace& w) {
    const std::int32_t u = from(h), v = to(h), back = opp_[h];
    const std::int32_t t1 = h / 3, t2 = back / 3;
    std::int32_t g = out_[u];
    auto& fan = w.fan;
    fan.clear();
    do fan.push_back(g), g = rotate(g);
    while (g != out_[u]);
    // Glue the outer edges of the two vanishing triangles: (v, a) with (a, u) in t1, (u, b) with (b, v) in t2.
    const std::int32_t va = 3 * t1 + next_corner(h % 3), au = 3 * t1 + previous_corner(h % 3);
    const std::int32_t ub = 3 * t2 + next_corner(back % 3), bv = 3 * t2 + previous_corner(back % 3);
    const std::int32_t x1 = opp_[va], y1 = opp_[au], x2 = opp_[ub], y2 = opp_[bv];
    opp_[x1] = y1, opp_[y1] = x1, opp_[x2] = y2, opp_[y2] = x2;
    for (const auto f : fan) {
      const std::int32_t t = f / 3;
      if (t == t1 || t == t2) continue;
      tri_[t][f % 3] = v;
      quality_[t] = triangle_cosine(t);
      forget_unflippable(t);  // after the gluing: x1 and y2 (outside the fan) are across from y1 and x2 in it
    }
    // y1 now runs v -> a, x1 a -> v, x2 b -> v: valid leaving half-edges for v, a and b.
    out_[v] = y1, out_[from(x1)] = x1, out_[from(x2)] = x2, out_[u] = kDead;
    for (const auto t : {t1, t2}) tri_[t] = {kDead, kDead, kDead};
    w.removed.push_back(u);
    merged_into_[u] = v;
  }

  // Flips the edge of h when that raises the smaller corner angle of its two triangles, keeps both
  // normals within the allowed turn and the diagonals within max_error of each other, and creates no
  // existing edge.
  bool flip_if_better(std::int32_t h) {
    const std::int32_t back = opp_[h];
    const std::uint8_t bit = static_cast<std::uint8_t>(1u << (h % 3));
    if ((unflippable_[h / 3] & bit) && skip_unflippable_) return false;
    const std::int32_t a = from(h), b = to(h), c = apex(h), d = apex(back);
    if (c == d) return false;
    const Vec3 &pa = p_[a], &pb = p_[b], &pc = p_[c], &pd = p_[d];
    const double old_worst = std::max(worst_corner_cosine(pa, pb, pc), worst_corner_cosine(pb, pa, pd));
    const double new_worst = std::max(worst_corner_cosine(pc, pa, pd), worst_corner_cosine(pd, pb, pc));
    if (!(new_worst < old_worst - 1e-9)) {
      unflippable_[h / 3] |= bit;
      return false;
    }
    if (degree(a) < 4 || degree(b) < 4 || half_edge(c, d) != kDead) return false;
    // The quad's vector area is the same before and after: both new triangles must face within the
    // allowed turn of it.
    const Vec3 quad_area = cross(pb - pa, pc - pa) + cross(pa - pb, pd - pb);
    const double quad_area_squared = dot(quad_area, quad_area);
    if (!faces_within_turn(cross(pa - pc, pd - pc), quad_area, quad_area_squared) ||
        !faces_within_turn(cross(pb - pd, pc - pd), quad_area, quad_area_squared))
      return false;
    if (!(segment_distance(pa, pb, pc, pd) <= options_.max_error)) return false;
    if (!keeps_orientation(c, a, d) || !keeps_orientation(d, b, c)) return false;
    // t1 = (a, b, c) and t2 = (b, a, d) become (c, a, d) and (d, b, c).
    const std::int32_t t1 = h / 3, t2 = back / 3;
    const std::int32_t ca = opp_[3 * t1 + previous_corner(h % 3)], bc = opp_[3 * t1 + next_corner(h % 3)];
    const std::int32_t ad = opp_[3 * t2 + next_corner(back % 3)], db = opp_[3 * t2 + previous_corner(back % 3)];
    tri_[t1] = {c, a, d};
    tri_[t2] = {d, b, c};
    quality_[t1] = triangle_cosine(t1), quality_[t2] = triangle_cosine(t2);
    auto link = [&](std::int32_t x, std::int32_t y) { opp_[x] = y, opp_[y] = x; };
    link(3 * t1 + 0, ca), link(3 * t1 + 1, ad), link(3 * t1 + 2, 3 * t2 + 2);
    link(3 * t2 + 0, db), link(3 * t2 + 1, bc);
    forget_unflippable(t1), forget_unflippable(t2);
    out_[a] = 3 * t1 + 1, out_[b] = 3 * t2 + 1, out_[c] = 3 * t1 + 0, out_[d] = 3 * t2 + 0;
    return true;
  }

  // One round: every edge shorter than 4/5 of the target, shortest first (ties by vertex pair),
  // collapsed in whichever allowed direction makes the better-shaped triangles. Returns the number of
  // collapses.
  std::int64_t collapse_round() {
    const double low = options_.target_edge_length * 4 / 5, low_squared = low * low;
    // Two zones, split at the median x of the vertices, are worked on at once (each by its own thread
    // when there are two); whatever would touch both waits for a serial pass afterwards. Each zone's
    // work reads and writes only its own vertices and the triangles all of whose corners are in it, so
    // the result is the same in whatever order, or on however many threads, the zones run. (Zones first:
    // the median's scratch is gone before the candidates take their memory.)
    assign_zones();
    const auto candidate_groups = collapse_candidates(low_squared);
    std::array<Workspace, 2> zone_work;
    collapse_in_zones(candidate_groups, low_squared, zone_work);
    std::int64_t collapses = 0;
    auto count_removed = [&](Workspace& w) {
      for (const auto u : w.removed) --component_size_[component_[u]];
      collapses += static_cast<std::int64_t>(w.removed.size());
      w.removed.clear();
    };
    count_removed(zone_work[0]);
    count_removed(zone_work[1]);
    // The deferred candidates: zone 0's, then zone 1's, each in the order they were met.
    auto& deferred = zone_work[0].deferred;
    deferred.insert(deferred.end(), zone_work[1].deferred.begin(), zone_work[1].deferred.end());
    auto& serial = zone_work[0];
    for (const auto& c : deferred) {
      if (!alive_vertex(c.a) || !alive_vertex(c.b)) continue;
      const bool short_edge = squared_distance(p_[c.a], p_[c.b]) < low_squared;
      if (try_collapse(c.a, c.b, !short_edge, serial, -1) == Outcome::kCollapsed) count_removed(serial);
    }
    return collapses;
  }

  // The candidate edges of a collapse round, shortest first within blocks of consecutive triangles
  // (2^14: a compact piece of the mesh, whose data stay in cache), by classes of lengths within a factor
  // 2^(1/4) of each other, and in triangle order within a class. A global sort by length would visit the
  // mesh at random and spend its time in cache misses; a global sweep per class would stream the whole
  // mesh 16 times. A block's candidates are sorted as soon as it is read, so only their vertices are
  // kept, not their lengths. The length goes through float as when candidates kept it, so that the
  // classes stay the same. Blocks are read in groups of kBlocksPerGroup on every thread, each group's
  // candidates in a list of its own: the lists, in group order, are what one thread reading the blocks in
  // order would make.
  std::vector<std::vector<Candidate>> collapse_candidates(double low_squared) const {
    constexpr int kClasses = 16;
    constexpr std::int32_t kBlockTriangles = 1 << 14;
    auto length_class = [&](double squared_length) {
      const double ratio = std::min(1.0, static_cast<double>(static_cast<float>(squared_length)) / low_squared);
      return ratio <= 0
                 ? 0
                 : std::clamp(kClasses - 1 + static_cast<int>(std::floor(2 * std::log2(ratio))), 0, kClasses - 1);
    };
    constexpr std::int32_t kBlocksPerGroup = 16;
    const auto triangle_count = static_cast<std::int32_t>(tri_.size());
    const std::int64_t blocks = (static_cast<std::int64_t>(triangle_count) + kBlockTriangles - 1) / kBlockTriangles;
    const std::int64_t groups = (blocks + kBlocksPerGroup - 1) / kBlocksPerGroup;
    std::vector<std::vector<Candidate>> candidate_groups(static_cast<std::size_t>(groups));
    detail::parallel_chunks(groups, threads_, [&](std::int64_t group, int) {
      auto& candidates = candidate_groups[static_cast<std::size_t>(group)];
      std::vector<std::pair<std::uint8_t, Candidate>> block;  // length class, edge
      const std::int64_t last_block = std::min(blocks, (group + 1) * kBlocksPerGroup);
      for (std::int64_t block_index = group * kBlocksPerGroup; block_index < last_block; ++block_index) {
        const auto first = static_cast<std::int32_t>(block_index * kBlockTriangles);
        block.clear();
        const std::int32_t last = std::min(triangle_count, first + kBlockTriangles);
        for (std::int32_t t = first; t < last; ++t) {
          if (!alive_triangle(t)) continue;
          // Every edge of a triangle with a corner below min_angle_degrees is a candidate too, whatever its
          // length: a sliver whose short edges are long already (a vertex almost on the opposite edge, often
          // of degree 3, which no flip can remove) goes only by a collapse.
          const bool sliver = quality_[t] > cos_min_angle_;
          for (int k = 0; k < 3; ++k) {
            const std::int32_t a = tri_[t][k], b = tri_[t][next_corner(k)];
            const double squared_length = squared_distance(p_[a], p_[b]);
            if ((a < b && squared_length < low_squared) || (sliver && squared_length >= low_squared))
              block.push_back(
                  {static_cast<std::uint8_t>(length_class(squared_length)), {std::min(a, b), std::max(a, b)}});
          }
        }
        std::array<std::size_t, kClasses + 1> start{};
        for (const auto& [length, edge] : block) ++start[static_cast<std::size_t>(length) + 1];
        for (int k = 0; k < kClasses; ++k) start[k + 1] += start[k];
        const std::size_t offset = candidates.size();
        candidates.resize(offset + block.size());
        for (const auto& [length, edge] : block) candidates[offset + start[length]++] = edge;
      }
    });
    return candidate_groups;
  }

  // The parallel pass of a collapse round: each zone's candidates (both ends in the zone) collapsed by the
  // zone's own thread; the others deferred to zone_work[z].deferred.
  void collapse_in_zones(const std::vector<std::vector<Candidate>>& candidate_groups, double low_squared,
                         std::array<Workspace, 2>& zone_work) {
    for (auto& w : zone_work) w.removed_in.assign(component_size_.size(), 0);
    auto run_zone = [&](int zone) {
      auto& w = zone_work[static_cast<std::size_t>(zone)];
      for (const auto& candidates : candidate_groups) {
        for (const auto& c : candidates) {
          if (zone_[c.a] != zone || !alive_vertex(c.a)) continue;
          // An end in the other zone is that zone's thread's to change: it is not even read here (the serial
          // pass skips the candidate if it died meanwhile).
          if (zone_[c.b] != zone) {
            w.deferred.push_back(c);
            continue;
          }
          if (!alive_vertex(c.b)) continue;
          const bool short_edge = squared_distance(p_[c.a], p_[c.b]) < low_squared;
          if (try_collapse(c.a, c.b, !short_edge, w, zone) == Outcome::kDeferred) w.deferred.push_back(c);
        }
      }
    };
    if (threads_ > 1) {
      std::exception_ptr error;
      std::thread second([&] {
        try {
          run_zone(1);
        } catch (...) {
          error = std::current_exception();
        }
      });
      run_zone(0);
      second.join();
      if (error) std::rethrow_exception(error);
    } else {
      run_zone(0);
      run_zone(1);
    }
  }

  // zone_[v] for the alive vertices (0 or 1 by x against the median), and how many vertices of each
  // component each zone may remove in its parallel pass: half of what a component has beyond 64, so
  // that no component comes near a tetrahedron without the serial pass's checks.
  void assign_zones() {
    std::vector<double> xs;
    xs.reserve(out_.size());
    for (std::size_t v = 0; v < out_.size(); ++v)
      if (out_[v] != kDead) xs.push_back(p_[v][0]);
    double split = 0;
    if (!xs.empty()) {
      std::nth_element(xs.begin(), xs.begin() + static_cast<std::ptrdiff_t>(xs.size() / 2), xs.end());
      split = xs[xs.size() / 2];
    }
    zone_.resize(out_.size());
    for (std::size_t v = 0; v < out_.size(); ++v) zone_[v] = p_[v][0] < split ? 0 : 1;
    zone_budget_.resize(component_size_.size());
    for (std::size_t c = 0; c < component_size_.size(); ++c)
      zone_budget_[c] = std::max<std::int64_t>(0, (component_size_[c] - 64) / 2);
  }

  // One pass of angle-improving flips over every edge, in triangle order. Returns the number of flips.
  std::int64_t flip_round() {
    std::int64_t flips = 0;
    for (std::int32_t t = 0; t < static_cast<std::int32_t>(tri_.size()); ++t) {
      if (!alive_triangle(t)) continue;
      for (int k = 0; k < 3; ++k) {
        const std::int32_t h = 3 * t + k;
        if (from(h) < to(h) && flip_if_better(h)) ++flips;
      }
    }
    return flips;
  }

  // The upper bound of SimplifyReport::max_vertex_distance: each removed vertex is measured against
  // the triangles around the vertex it was merged into (transitively), then around each vertex nearer to
  // it on a walk from there (to the nearest neighbour, while one is nearer), and the triangles bordering
  // the last one's fan.
  [[nodiscard]] double removed_vertex_distance() const {
    const auto vertices = static_cast<std::int32_t>(out_.size());
    auto largest_in = [&](std::int32_t first, std::int32_t last) {
      double largest = 0;
      for (std::int32_t x = first; x < last; ++x) {
        if (alive_vertex(x)) continue;
        std::int32_t r = merged_into_[x];
        while (!alive_vertex(r)) r = merged_into_[r];
        const Vec3& point = p_[x];
        double nearest = INFINITY, closest_vertex = squared_distance(point, p_[r]);
        // A vertex already as near as the largest so far cannot raise it: the rest of its walk is skipped.
        bool settled = false;
        for (int steps = 0; steps < 16 && !settled; ++steps) {
          std::int32_t g = out_[r], next = kDead;
          do {
            const std::int32_t w = to(g);
            nearest = std::min(nearest, point_triangle_distance(point, p_[r], p_[w], p_[apex(g)]));
            const double d = squared_distance(point, p_[w]);
            if (d < closest_vertex) closest_vertex = d, next = w;
            g = rotate(g);
          } while (g != out_[r]);
          settled = nearest <= largest;
          if (next == kDead) break;
          r = next;
        }
        if (settled) continue;
        // The point may lie over a triangle just outside the fan of its nearest vertex: those across
        // the fan's outer edges count too.
        std::int32_t g = out_[r];
        do {
          const std::int32_t across = opp_[3 * (g / 3) + next_corner(g % 3)];
          nearest =
              std::min(nearest, point_triangle_distance(point, p_[from(across)], p_[to(across)], p_[apex(across)]));
          g = rotate(g);
        } while (g != out_[r]);
        largest = std::max(largest, nearest);
      }
      return largest;
    };
    if (threads_ <= 1) return largest_in(0, vertices);
    double second_half = 0;
    std::thread second([&] { second_half = largest_in(vertices / 2, vertices); });  // reads only
    const double first_half = largest_in(0, vertices / 2);
    second.join();
    return std::max(first_half, second_half);
  }

  [[nodiscard]] const std::vector<Triangle>& triangles() const { return tri_; }
  [[nodiscard]] std::int64_t alive_vertices() const {
    return std::count_if(out_.begin(), out_.end(), [](std::int32_t h) { return h != kDead; });
  }

 private:
  const std::vector<Vec3>& p_;
  std::vector<Triangle> tri_;
  SimplifyOptions options_;
  std::vector<std::int32_t> opp_, out_, component_, merged_into_;
  std::vector<std::int64_t> component_size_;
  std::vector<bool> kept_;
  std::vector<double> quality_;  // worst_corner_cosine of each triangle, kept up to date
  // Bit k of triangle t: the edge of half-edge 3t + k, evaluated by flip_if_better, did not pass its
  // angle test, and neither triangle on it has changed since. Positions never move, so the test would
  // fail again: the flip passes skip it. One byte per triangle; the parallel collapse zones write only
  // the bytes of triangles with two corners in their own zone, never the same byte.
  std::vector<std::uint8_t> unflippable_;
  bool skip_unflippable_ = true;  // detail::simplify_skips_known_unflippable_edges() when made
  std::vector<std::int8_t> zone_;
  std::vector<std::int64_t> zone_budget_;
  int threads_ = 1;
  double cos_min_angle_ = 1, cos_normal_change_squared_ = 1, longest_squared_ = INFINITY;
};

struct ShapeFigures {
  double area = 0, mean_edge = 0, min_angle_degrees = 0;
};

ShapeFigures shape_figures(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
  ShapeFigures figures;
  double worst = -1, edges = 0;
  std::int64_t alive = 0;
  for (const auto& t : triangles) {
    if (t[0] == kDead) continue;
    const Vec3 &a = positions[t[0]], &b = positions[t[1]], &c = positions[t[2]];
    worst = std::max(worst, worst_corner_cosine(a, b, c));
    figures.area += triangle_area(a, b, c);
    edges += norm(b - a) + norm(c - b) + norm(a - c);
    ++alive;
  }
  if (alive == 0) return figures;
  figures.mean_edge = edges / static_cast<double>(3 * alive);
  figures.min_angle_degrees = std::acos(std::clamp(worst, -1.0, 1.0)) * 180 / std::numbers::pi;
  return figures;
}

}  // namespace

Mesh simplify_surface(Mesh mesh, const SimplifyOptions& options, SimplifyReport* report) {
  for (const double value :
       {options.target_edge_length, options.max_error, options.min_angle_degrees, options.max_normal_change_degrees})
    if (!(value >= 0) || !std::isfinite(value))
      throw std::invalid_argument("simplify_surface: options must be finite and not negative");
  if (!(options.max_normal_change_degrees < 90))
    throw std::invalid_argument("simplify_surface: max_normal_change_degrees must be below 90");
  if (options.max_rounds < 0) throw std::invalid_argument("simplify_surface: max_rounds must not be negative");
  SimplifyReport local;
  SimplifyReport& r = report ? *report : local;
  r = SimplifyReport{};
  r.vertices_before = static_cast<std::int64_t>(mesh.vertex_count());
  r.triangles_before = static_cast<std::int64_t>(mesh.triangle_count());
  const ShapeFigures before = shape_figures(mesh.positions, mesh.triangles);
  r.area_before = before.area, r.mean_edge_before = before.mean_edge,
  r.min_angle_before_degrees = before.min_angle_degrees;
  const unsigned hardware = std::thread::hardware_concurrency();
  Surface surface(mesh, options, options.threads > 0 ? options.threads : static_cast<int>(std::max(1u, hardware)));
  if (options.target_edge_length > 0) {
    std::int64_t left = r.vertices_before;
    for (int round = 0; round < options.max_rounds; ++round) {
      const std::int64_t collapses = surface.collapse_round();
      r.collapses += collapses;
      left -= collapses;
      r.flips += surface.flip_round();
      ++r.rounds;
      if (collapses * 200 < left) break;
    }
    for (int pass = 0; pass < 2; ++pass) {
      const std::int64_t flips = surface.flip_round();
      r.flips += flips;
      if (flips == 0) break;
    }
  }
  r.max_vertex_distance = options.measure_distance ? surface.removed_vertex_distance() : -1;
  // Survivors in input order, triangles in input order.
  const auto& triangles = surface.triangles();  // mesh.triangles were taken by the surface
  std::vector<std::int32_t> new_index(mesh.vertex_count(), kDead);
  for (const auto& t : triangles)
    if (t[0] != kDead)
      for (const auto v : t) new_index[v] = 0;
  for (std::int32_t v = 0; v < static_cast<std::int32_t>(new_index.size()); ++v)
    if (new_index[v] == 0) new_index[v] = static_cast<std::int32_t>(r.kept_vertex.size()), r.kept_vertex.push_back(v);
  Mesh out;
  out.positions.reserve(r.kept_vertex.size());
  for (const auto v : r.kept_vertex) out.positions.push_back(mesh.positions[v]);
  for (const auto& t : triangles)
    if (t[0] != kDead) out.triangles.push_back({new_index[t[0]], new_index[t[1]], new_index[t[2]]});
  auto pick = [&](const auto& values) {
    std::remove_cvref_t<decltype(values)> kept;
    kept.reserve(r.kept_vertex.size());
    for (const auto v : r.kept_vertex) kept.push_back(values[static_cast<std::size_t>(v)]);
    return kept;
  };
  for (const auto& [name, values] : mesh.real_attributes) out.real_attributes[name] = pick(values);
  for (const auto& [name, values] : mesh.integer_attributes) out.integer_attributes[name] = pick(values);
  for (const auto& [name, text] : mesh.text_attributes) out.text_attributes[name] = {text.dictionary, pick(text.codes)};
  r.vertices_after = static_cast<std::int64_t>(out.vertex_count());
  r.triangles_after = static_cast<std::int64_t>(out.triangle_count());
  const ShapeFigures after = shape_figures(out.positions, out.triangles);
  r.area_after = after.area, r.mean_edge_after = after.mean_edge, r.min_angle_after_degrees = after.min_angle_degrees;
  return out;
}

}  // namespace spheremap
