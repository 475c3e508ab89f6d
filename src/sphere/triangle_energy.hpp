// Private to the sphere stage: per-triangle energies of a sphere map and their derivatives in R^9 (the
// three corners' coordinates), for optimize_on_sphere.
#pragma once

#include <Eigen/Dense>

#include "spheremap/mesh.hpp"
#include "spheremap/sphere/optimize.hpp"

namespace spheremap::detail {

/// What an energy compares a map's triangle with: the surface triangle's cotangents (corner k's, for the
/// edge opposite it) and its target area on the sphere.
struct RestTriangle {
  double cot[3];
  double area;
};

/// The rest data of the surface triangle abc with target area `area`. A triangle with an angle below
/// `min_angle` (or no area) counts as equilateral.
RestTriangle rest_triangle(const Vec3& a, const Vec3& b, const Vec3& c, double area, double min_angle);

/// ½·det[a, b, c] (the chord triangle's area times its plane's distance from the centre, which is the
/// area for small triangles), from edge vectors so that it keeps its relative precision when tiny.
double half_det(const Vec3& a, const Vec3& b, const Vec3& c);

/// ½·det[a, b, c] of the equilateral spherical triangle of solid angle `solid_angle` (in (0, 2π)): the
/// area target of a triangle with that share of the sphere.
double equilateral_half_det(double solid_angle);

using Vector9 = Eigen::Matrix<double, 9, 1>;
using Matrix9 = Eigen::Matrix<double, 9, 9>;

/// Symmetric Dirichlet N·(1 + A²/S²) with N = ½ Σ cot_k |e_k|² (chord edges e_k opposite corner k,
/// the Dirichlet energy of the affine map), A the target area and S = half_det(a, b, c); +inf if S <= 0.
double symmetric_dirichlet(const RestTriangle& rest, const Vec3& a, const Vec3& b, const Vec3& c);

/// The same, with its gradient and Hessian with respect to (a, b, c). Precondition: S > 0.
double symmetric_dirichlet(const RestTriangle& rest, const Vec3& a, const Vec3& b, const Vec3& c, Vector9& gradient,
                           Matrix9& hessian);

/// The second term of an energy: its weight and, for kConformal, the ratio S/A below which its collapse
/// barrier acts (0: the power law weight·A·(A/S)² everywhere; see SphereOptimizeOptions).
struct SecondTerm {
  SecondTerm(double weight_, double threshold_ = 0)
      : weight(weight_), threshold(threshold_) {}  // NOLINT: from a weight
  double weight;
  double threshold;
};

/// kLogAreaRatio and kConformal (optimize.hpp) with `weight`/`term` their second term (the shape term,
/// the collapse barrier), with their gradient and Hessian in the second forms (precondition there:
/// S > 0); the first forms give +inf if S <= 0. With `secant`, kLogAreaRatio's Hessian is a model, not
/// the exact one: the area term's second derivative in S is at least its secant curvature
/// 2A·ln(S/A)/(S(S - A)), whose 1-D Newton step goes to S = A (positive where the exact one is negative,
/// S > eA).
double log_area_ratio(const RestTriangle& rest, double weight, const Vec3& a, const Vec3& b, const Vec3& c);
double log_area_ratio(const RestTriangle& rest, double weight, const Vec3& a, const Vec3& b, const Vec3& c,
                      Vector9& gradient, Matrix9& hessian, bool secant = false);
double conformal(const RestTriangle& rest, SecondTerm term, const Vec3& a, const Vec3& b, const Vec3& c);
double conformal(const RestTriangle& rest, SecondTerm term, const Vec3& a, const Vec3& b, const Vec3& c,
                 Vector9& gradient, Matrix9& hessian);

/// The energy `energy` of one triangle (a new SphereEnergy gets its two functions here), `term` its
/// second term (unused by kSymmetricDirichlet): +inf when the triangle is not positively oriented; the
/// second form also gives the gradient and Hessian in R^9 (precondition: positively oriented; `secant`:
/// kLogAreaRatio's model Hessian, see log_area_ratio).
double triangle_energy(SphereEnergy energy, SecondTerm term, const RestTriangle& rest, const Vec3& a, const Vec3& b,
                       const Vec3& c);
double triangle_energy(SphereEnergy energy, SecondTerm term, const RestTriangle& rest, const Vec3& a, const Vec3& b,
                       const Vec3& c, Vector9& gradient, Matrix9& hessian, bool secant = false);

}  // namespace spheremap::detail
