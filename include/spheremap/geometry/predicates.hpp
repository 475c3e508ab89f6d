// Exact geometric predicates (adaptive precision, after Shewchuk 1997).
#pragma once

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Sign of det[a, b, c] (the orientation of triangle abc as seen from the origin, i.e. +1 when abc is
/// counter-clockwise seen from outside a sphere centred at the origin), computed exactly for any
/// finite double inputs: a floating-point filter decides the easy cases and exact expansion
/// arithmetic the rest. `decided_exactly` (optional) is set to true when the filter was not enough.
/// Precondition: all coordinates finite. Never throws.
int orientation_sign(const Vec3& a, const Vec3& b, const Vec3& c, bool* decided_exactly = nullptr);

/// Sign of the 2D orientation of (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear; exact.
/// Precondition: all coordinates finite. Never throws.
int orientation_sign_2d(double ax, double ay, double bx, double by, double cx, double cy);

}  // namespace spheremap
