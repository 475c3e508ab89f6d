// Generated closed genus-0 meshes, for tests, benchmarks and `spheremap generate` (stage: shapes). All
// outward oriented.
#pragma once

#include <cstdint>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Icosahedron subdivided `levels` times (1-to-4), projected on the unit sphere:
/// 10*4^levels + 2 vertices. levels in [0, 10]; throws std::invalid_argument otherwise.
Mesh make_icosphere(int levels);

/// Icosphere scaled by (ax, ay, az). E.g. (1, 1, 20) for a 1:20 cigar.
/// Throws std::invalid_argument if a semi-axis is not finite and positive, or as make_icosphere.
Mesh make_ellipsoid(int levels, double ax, double ay, double az);

/// Two unit spheres whose centres are `separation` apart along x, joined by a tube of radius
/// `neck_radius` (< 1): a surface of revolution sampled with `rings` x `segments` quads split in two,
/// closed by two pole vertices. Genus 0.
/// Throws std::invalid_argument unless separation >= 0 (finite), neck_radius in (0, 1), rings >= 1,
/// segments >= 3 and the vertices fit 32-bit indices.
Mesh make_dumbbell(double separation, double neck_radius, int rings, int segments);

/// Moves every vertex by a random offset of at most `amplitude` times its mean edge length, with a
/// fixed seed (deterministic). Topology and attributes unchanged.
/// Throws std::invalid_argument if amplitude is negative or not finite, or a triangle index is out of range.
Mesh perturb_vertices(const Mesh& mesh, double amplitude, std::uint32_t seed);

/// Flips each interior edge with probability `probability` when the flip keeps the mesh a simplicial
/// 2-manifold (no duplicate edges) and both new triangles keep the orientation; deterministic for a seed.
/// Creates degree-3 vertices and separating triangles, the hard cases of the map.
/// Preconditions: a closed, consistently oriented 2-manifold. Throws std::invalid_argument if it is not,
/// if probability is outside [0, 1], or a triangle index is out of range.
Mesh random_edge_flips(const Mesh& mesh, double probability, std::uint32_t seed);

/// A mesh with many exact ties in the harmonic z: an axis-aligned cube surface subdivided into
/// n x n squares per face, split along the same diagonal (symmetric).
/// Throws std::invalid_argument unless n is in [1, 10000].
Mesh make_subdivided_cube(int n);

}  // namespace spheremap
