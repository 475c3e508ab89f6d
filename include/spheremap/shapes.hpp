// Generated closed genus-0 meshes, for tests, benchmarks and examples. All outward oriented.
#pragma once

#include <cstdint>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Icosahedron subdivided `levels` times (1-to-4), projected on the unit sphere:
/// 10*4^levels + 2 vertices. levels in [0, 10]; throws std::invalid_argument otherwise.
Mesh make_icosphere(int levels);

/// Icosphere scaled by (ax, ay, az). E.g. (1, 1, 20) for a 1:20 cigar.
Mesh make_ellipsoid(int levels, double ax, double ay, double az);

/// Two unit spheres whose centres are `separation` apart along x, joined by a tube of radius
/// `neck_radius` (< 1): a surface of revolution sampled with `rings` x `segments` quads split in two,
/// closed by two pole vertices. Genus 0.
Mesh make_dumbbell(double separation, double neck_radius, int rings, int segments);

/// Moves every vertex by a random offset of at most `amplitude` times its mean edge length, with a
/// fixed seed (deterministic). Topology unchanged.
Mesh perturb_vertices(const Mesh& mesh, double amplitude, std::uint32_t seed);

/// Flips each interior edge with probability `probability` when the flip keeps the mesh a simplicial
/// 2-manifold (no duplicate edges) and both new triangles keep the orientation; deterministic for a seed.
/// Creates degree-3 vertices and separating triangles, the hard cases of the map.
Mesh random_edge_flips(const Mesh& mesh, double probability, std::uint32_t seed);

/// A mesh with many exact ties in the harmonic z: an axis-aligned cube surface subdivided into
/// n x n squares per face, split along the same diagonal (symmetric).
Mesh make_subdivided_cube(int n);

}  // namespace spheremap
