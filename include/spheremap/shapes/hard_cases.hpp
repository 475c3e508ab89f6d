// Generated closed genus-0 meshes that are hard to map onto the sphere: the families on which the plain
// algorithm and its repair can end uncertified, so that the fallback (sphere/fallback.hpp) is exercised.
// All outward oriented, deterministic for a seed.
#pragma once

#include <cstdint>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// A stacked triangulation: a regular tetrahedron into whose triangles vertices are inserted one by one,
/// each at a random interior point of a triangle (barycentric weights at least 0.1 / 2.8 each), lifted
/// by `height` times the square root of that triangle's area along its outward normal; the triangle
/// becomes three. With probability `nesting` the triangle is one of the three made by the previous
/// insertion (a nested chain: triangle areas shrink geometrically with depth), otherwise any triangle.
/// Preconditions: vertices >= 4; nesting in [0, 1]; height finite and >= 0.
/// Throws std::invalid_argument otherwise, or when a triangle to insert into has an area below 1e-250
/// (a chain nested so deep that double precision cannot hold it).
Mesh make_stacked_triangulation(int vertices, double nesting, std::uint32_t seed, double height = 0.1);

enum class TubeBend {
  kU,  // two straight legs joined by a half circle
  kC,  // three quarters of a circle
};

/// A tube of radius `radius` along a U- or C-shaped centre line of unit bend radius: `rings` rings of
/// `segments` vertices (every other ring turned by half a segment), each end closed by one apex vertex.
/// Coarse tubes (3-6 segments) are where harmonic maps collapse and fold.
/// Preconditions: segments in [3, 1000], rings in [2, 100000], radius in (0, 0.5].
/// Throws std::invalid_argument otherwise.
Mesh make_bent_tube(TubeBend bend, int segments, int rings, double radius = 0.25);

/// A sea urchin: an icosphere of `level` from which `spikes` randomly chosen vertices (at least three
/// edges apart) grow thin tubes: each vertex's star becomes `rings` rings a third as wide as the star,
/// reaching out to distance 1 + `length` from the centre, closed by the vertex itself as the tip.
/// Harmonic maps decay exponentially along each spike.
/// Preconditions: level in [0, 6], spikes >= 0, length finite and > 0, rings in [1, 10000].
/// Throws std::invalid_argument otherwise.
Mesh make_spiky_sphere(int level, int spikes, double length, int rings, std::uint32_t seed);

}  // namespace spheremap
