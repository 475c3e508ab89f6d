#include "triangle_energy.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>

#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {
namespace {

// M(v)_ij = ε_ijk v_k: the block ∂²(a·(b×c))/∂a∂b is M(c).
Eigen::Matrix3d epsilon_contract(const Vec3& v) {
  Eigen::Matrix3d m;
  m << 0, v[2], -v[1], -v[2], 0, v[0], v[1], -v[0], 0;
  return m;
}

Eigen::Vector3d eigen(const Vec3& v) { return {v[0], v[1], v[2]}; }

}  // namespace

RestTriangle rest_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double area, double min_angle) {
  const Vec3* corner[3] = {&a, &b, &c};
  RestTriangle rest{{0, 0, 0}, area};
  for (int k = 0; k < 3; ++k) {
    const Vec3 u = *corner[(k + 1) % 3] - *corner[k];
    const Vec3 v = *corner[(k + 2) % 3] - *corner[k];
    const double sine = norm(cross(u, v)), cosine = dot(u, v);
    if (!(sine > 0) || std::atan2(sine, cosine) < min_angle) {
      for (double& x : rest.cot) x = 1 / std::sqrt(3.0);
      return rest;
    }
    rest.cot[k] = cosine / sine;
  }
  return rest;
}

double equilateral_half_det(double solid_angle) {
  // Corners at angular distance ρ from the centre, 120° apart: det = (3√3/2) sin²ρ cos ρ and
  // 1 + a·b + b·c + c·a = 4 - (9/2) sin²ρ; tan(Ω/2) = det / that (van Oosterom & Strackee) grows
  // with ρ from 0 to a great circle (Ω = 2π at ρ = π/2). Newton's method on ρ from the small-triangle
  // estimate Ω ≈ (3√3/4)ρ², kept inside a bracket that bisection shrinks when a step would leave it:
  // a few steps where bisection took a hundred (this runs once per triangle).
  const double root27 = 3 * std::sqrt(3.0);
  double low = 0, high = 0.5 * std::numbers::pi;
  double rho = std::min(std::sqrt(4 * solid_angle / root27), 0.5 * high);
  if (!(rho > 0)) rho = 0.5 * high;
  for (int iteration = 0; iteration < 100; ++iteration) {
    const double s = std::sin(rho), c = std::cos(rho), s2 = s * s;
    const double u = 0.5 * root27 * s2 * c, v = 4 - 4.5 * s2;
    const double f = 2 * std::atan2(u, v) - solid_angle;
    (f < 0 ? low : high) = rho;
    const double du = 0.5 * root27 * s * (2 * c * c - s2), dv = -9 * s * c;
    const double slope = 2 * (du * v - u * dv) / (u * u + v * v);
    const double next = rho - f / slope;
    if (f == 0 || std::abs(next - rho) <= 1e-15 * rho) {
      rho = next;
      break;
    }
    rho = next > low && next < high ? next : 0.5 * (low + high);
  }
  return 0.25 * root27 * std::sin(rho) * std::sin(rho) * std::cos(rho);
}

double half_det(const Vec3& a, const Vec3& b, const Vec3& c) { return 0.5 * dot(a, cross(b - a, c - a)); }

double symmetric_dirichlet(const RestTriangle& rest, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double s = half_det(a, b, c);
  if (!(s > 0)) return std::numeric_limits<double>::infinity();
  const double n = 0.5 * (rest.cot[0] * squared_distance(b, c) + rest.cot[1] * squared_distance(c, a) +
                          rest.cot[2] * squared_distance(a, b));
  return n * (1 + (rest.area / s) * (rest.area / s));
}

namespace {

// What every energy is made of: N = ½ Σ cot_k |e_k|² (the Dirichlet energy of the affine map from the
// rest triangle to the chord triangle), S = ½·det[a, b, c], and their derivatives (∇²N = K ⊗ I3).
struct ChordTerms {
  double n, s;
  Vector9 grad_n, grad_s;
  Eigen::Matrix3d k;
  Matrix9 hess_s;
};

ChordTerms chord_terms(const RestTriangle& rest, const Vec3& a, const Vec3& b, const Vec3& c) {
  ChordTerms t;
  t.s = half_det(a, b, c);
  const double c0 = rest.cot[0], c1 = rest.cot[1], c2 = rest.cot[2];
  t.n = 0.5 * (c0 * squared_distance(b, c) + c1 * squared_distance(c, a) + c2 * squared_distance(a, b));
  t.grad_n << eigen(c1 * (a - c) + c2 * (a - b)), eigen(c0 * (b - c) + c2 * (b - a)),
      eigen(c0 * (c - b) + c1 * (c - a));
  t.k << c1 + c2, -c2, -c1, -c2, c0 + c2, -c0, -c1, -c0, c0 + c1;
  // ∇S: ½ b×c etc., each written as a short cross product plus one tangent to its corner, so that the
  // tangential part (all the optimization sees) keeps its precision on tiny triangles.
  t.grad_s << eigen(0.5 * (cross(b - a, c - a) + cross(a, c - b))),
      eigen(0.5 * (cross(c - b, a - b) + cross(b, a - c))), eigen(0.5 * (cross(a - c, b - c) + cross(c, b - a)));
  t.hess_s = Matrix9::Zero();
  t.hess_s.block<3, 3>(0, 3) = 0.5 * epsilon_contract(c);
  t.hess_s.block<3, 3>(0, 6) = -0.5 * epsilon_contract(b);
  t.hess_s.block<3, 3>(3, 6) = 0.5 * epsilon_contract(a);
  t.hess_s.block<3, 3>(3, 0) = t.hess_s.block<3, 3>(0, 3).transpose();
  t.hess_s.block<3, 3>(6, 0) = t.hess_s.block<3, 3>(0, 6).transpose();
  t.hess_s.block<3, 3>(6, 3) = t.hess_s.block<3, 3>(3, 6).transpose();
  return t;
}

// The partial derivatives of an energy f(N, S) of one triangle.
struct Partials {
  double f, n, s, nn, ns, ss;
};

// Chain rule: ∇f = f_N ∇N + f_S ∇S, ∇²f = f_N ∇²N + f_S ∇²S + f_NN ∇N∇Nᵀ + f_SS ∇S∇Sᵀ + f_NS (∇N∇Sᵀ + ∇S∇Nᵀ).
double chain(const ChordTerms& t, const Partials& d, Vector9& gradient, Matrix9& hessian) {
  gradient = d.n * t.grad_n + d.s * t.grad_s;
  hessian = d.s * t.hess_s + d.nn * t.grad_n * t.grad_n.transpose() + d.ss * t.grad_s * t.grad_s.transpose() +
            d.ns * (t.grad_n * t.grad_s.transpose() + t.grad_s * t.grad_n.transpose());
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) hessian.block<3, 3>(3 * i, 3 * j).diagonal().array() += d.n * t.k(i, j);
  return d.f;
}

double dirichlet_n(const RestTriangle& rest, const Vec3& a, const Vec3& b, const Vec3& c) {
  return 0.5 * (rest.cot[0] * squared_distance(b, c) + rest.cot[1] * squared_distance(c, a) +
                rest.cot[2] * squared_distance(a, b));
}

// f = A ln²(S/A) + w A N/S. With `secant`, the area term's ∂²/∂S² is raised to its secant curvature
// f_S/(S - A) where that is larger: the parabola in S through the term's slope with its minimum at S = A.
// The term is concave in S above S = eA, and its exact curvature there (projected to 0 by the optimizer)
// makes the Newton step of a triangle far too large on the sphere as long as the curvature of its shape
// term alone: on the paper's maps (areas 10-fold off on average) the first steps were then cut to a
// few thousandths, tens of them. The secant asks each triangle for its target area, as Newton's step in
// ln S would.
Partials log_area_partials(double w, double area, double n, double s, bool secant) {
  const double l = std::log(s / area);
  double area_ss = 2 * area * (1 - l) / (s * s);
  if (secant && s != area) area_ss = std::max(area_ss, 2 * area * l / (s * (s - area)));
  return {area * l * l + w * area * n / s,
          w * area / s,
          2 * area * l / s - w * area * n / (s * s),
          0,
          -w * area / (s * s),
          area_ss + 2 * w * area * n / (s * s * s)};
}

// f = A N/S + w A³/S², or with a threshold κ: f = A N/S + w A φ(S/(κA)), φ(x) = -(x-1)² ln x below
// x = 1 and 0 above (the barrier of incremental potential contact: twice differentiable at x = 1,
// unbounded as x -> 0, nothing at all on the triangles above κ of their share).
Partials conformal_partials(SecondTerm term, double area, double n, double s) {
  const double w = term.weight;
  Partials p{area * n / s, area / s, -area * n / (s * s), 0, -area / (s * s), 2 * area * n / (s * s * s)};
  if (term.threshold > 0) {
    const double kappa = term.threshold, x = s / (kappa * area);
    if (x < 1) {
      const double l = std::log(x);
      p.f += w * area * (-(x - 1) * (x - 1) * l);
      p.s += w / kappa * (-2 * (x - 1) * l - (x - 1) * (x - 1) / x);
      p.ss += w / (kappa * kappa * area) * (-2 * l - 2 * (x - 1) / x - (x - 1) * (x + 1) / (x * x));
    }
    return p;
  }
  const double a3 = area * area * area;
  p.f += w * a3 / (s * s);
  p.s -= 2 * w * a3 / (s * s * s);
  p.ss += 6 * w * a3 / (s * s * s * s);
  return p;
}

}  // namespace

double symmetric_dirichlet(const RestTriangle& rest, const Vec3& a, const Vec3& b, const Vec3& c, Vector9& gradient,
                           Matrix9& hessian) {
  const ChordTerms t = chord_terms(rest, a, b, c);
  const double s = t.s, n = t.n;
  // E = N (1 + Q), Q = A²/S².
  const double a2 = rest.area * rest.area;
  const double q = a2 / (s * s);
  const Vector9 grad_q = (-2 * a2 / (s * s * s)) * t.grad_s;
  gradient = (1 + q) * t.grad_n + n * grad_q;
  hessian = n * ((6 * a2 / (s * s * s * s)) * t.grad_s * t.grad_s.transpose() - (2 * a2 / (s * s * s)) * t.hess_s) +
            t.grad_n * grad_q.transpose() + grad_q * t.grad_n.transpose();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) hessian.block<3, 3>(3 * i, 3 * j).diagonal().array() += (1 + q) * t.k(i, j);
  return n * (1 + q);
}

double log_area_ratio(const RestTriangle& rest, double weight, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double s = half_det(a, b, c);
  if (!(s > 0)) return std::numeric_limits<double>::infinity();
  return log_area_partials(weight, rest.area, dirichlet_n(rest, a, b, c), s, false).f;
}

double log_area_ratio(const RestTriangle& rest, double weight, const Vec3& a, const Vec3& b, const Vec3& c,
                      Vector9& gradient, Matrix9& hessian, bool secant) {
  const ChordTerms t = chord_terms(rest, a, b, c);
  return chain(t, log_area_partials(weight, rest.area, t.n, t.s, secant), gradient, hessian);
}

double conformal(const RestTriangle& rest, SecondTerm term, const Vec3& a, const Vec3& b, const Vec3& c) {
  const double s = half_det(a, b, c);
  if (!(s > 0)) return std::numeric_limits<double>::infinity();
  return conformal_partials(term, rest.area, dirichlet_n(rest, a, b, c), s).f;
}

double conformal(const RestTriangle& rest, SecondTerm term, const Vec3& a, const Vec3& b, const Vec3& c,
                 Vector9& gradient, Matrix9& hessian) {
  const ChordTerms t = chord_terms(rest, a, b, c);
  return chain(t, conformal_partials(term, rest.area, t.n, t.s), gradient, hessian);
}

double triangle_energy(SphereEnergy energy, SecondTerm term, const RestTriangle& rest, const Vec3& a, const Vec3& b,
                       const Vec3& c) {
  switch (energy) {
    case SphereEnergy::kSymmetricDirichlet: return symmetric_dirichlet(rest, a, b, c);
    case SphereEnergy::kLogAreaRatio: return log_area_ratio(rest, term.weight, a, b, c);
    case SphereEnergy::kConformal: return conformal(rest, term, a, b, c);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

double triangle_energy(SphereEnergy energy, SecondTerm term, const RestTriangle& rest, const Vec3& a, const Vec3& b,
                       const Vec3& c, Vector9& gradient, Matrix9& hessian, bool secant) {
  switch (energy) {
    case SphereEnergy::kSymmetricDirichlet: return symmetric_dirichlet(rest, a, b, c, gradient, hessian);
    case SphereEnergy::kLogAreaRatio: return log_area_ratio(rest, term.weight, a, b, c, gradient, hessian, secant);
    case SphereEnergy::kConformal: return conformal(rest, term, a, b, c, gradient, hessian);
  }
  return std::numeric_limits<double>::quiet_NaN();
}

}  // namespace spheremap::detail
