// A generated map for the viewer's tests: a bumpy sphere (the "surface") mapped radially onto an icosphere
// (the "sphere"), with fake residues of five atoms each and five properties, one per kind of scale.
#pragma once

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "spheremap/render/viewer.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap::testing_support {

inline Vec3 fibonacci_direction(int i, int n) {
  const double z = 1 - (2.0 * i + 1) / n;
  const double r = std::sqrt(std::max(0.0, 1 - z * z));
  const double angle = i * std::numbers::pi * (3 - std::sqrt(5.0));
  return {r * std::cos(angle), r * std::sin(angle), z};
}

inline double dot3(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }

/// Radius of the bumpy surface in direction u (unit): a large bump at the north pole (its top is a smooth
/// cap, so the highest vertex is in plain view from +z) and smaller ones elsewhere.
inline double bumpy_radius(const Vec3& u) {
  double r = 1 + 0.25 * std::exp(-(1 - u[2]) * 12);
  for (int k = 0; k < 14; ++k) r += 0.08 * std::exp(-(1 - dot3(u, fibonacci_direction(k, 14))) * 25);
  return 20 * r;  // Å, about a small protein
}

/// `residues` residues on the sphere (chain A then B, numbered from 1 in each), five atoms each (N CA C O
/// CB); each vertex names the residue nearest in direction and one of its atoms. Properties: height
/// (sequential, Å), electrostatics (diverging, kT/e, range -2..2), b_factor (sequential, NaN on the
/// atoms of residue A:7), chain and octant (categorical).
inline ViewerData make_viewer_test_map(int levels, int residues) {
  static constexpr std::array<const char*, 20> kNames{"ALA", "ARG", "ASN", "ASP", "CYS", "GLN", "GLU",
                                                      "GLY", "HIS", "ILE", "LEU", "LYS", "MET", "PHE",
                                                      "PRO", "SER", "THR", "TRP", "TYR", "VAL"};
  static constexpr std::array<const char*, 5> kAtoms{"N", "CA", "C", "O", "CB"};
  const Mesh sphere = make_icosphere(levels);
  ViewerData data;
  data.title = "test map: bumpy sphere";
  data.sphere_positions = sphere.positions;
  data.triangles = sphere.triangles;
  const int per_chain = (residues + 1) / 2;
  for (int r = 0; r < residues; ++r)
    for (const char* atom : kAtoms)
      data.atoms.push_back({r < per_chain ? "A" : "B", kNames[r % kNames.size()], r % per_chain + 1, "", atom});

  ViewerProperty height{"height", "Å", ScaleKind::sequential, {}, {}, {}};
  ViewerProperty potential{"electrostatics", "kT/e", ScaleKind::diverging, {-2, 2}, {}, {}};
  ViewerProperty b_factor{"b_factor", "Å²", ScaleKind::sequential, {}, {}, {}};
  ViewerProperty chain{"chain", "", ScaleKind::categorical, {0, 255}, {}, {"A", "B"}};
  ViewerProperty octant{"octant", "", ScaleKind::categorical,
                        {0, 255}, {}, {"+x+y+z", "-x+y+z", "+x-y+z", "-x-y+z", "+x+y-z", "-x+y-z", "+x-y-z", "-x-y-z"}};
  std::vector<Vec3> seeds;
  for (int r = 0; r < residues; ++r) seeds.push_back(fibonacci_direction(r, residues));
  for (const Vec3& u : sphere.positions) {
    const double radius = bumpy_radius(u);
    data.surface_positions.push_back({radius * u[0], radius * u[1], radius * u[2]});
    int nearest = 0;
    for (int r = 1; r < residues; ++r)
      if (dot3(u, seeds[r]) > dot3(u, seeds[nearest])) nearest = r;
    // The atom: one of five sectors of longitude.
    const double angle = std::atan2(u[1], u[0]) + std::numbers::pi;
    const int atom = std::min(4, static_cast<int>(angle / (2 * std::numbers::pi) * 5));
    data.vertex_atoms.push_back(5 * nearest + atom);
    const double lat = std::asin(std::clamp(u[2], -1.0, 1.0)), lon = std::atan2(u[1], u[0]);
    height.values.push_back(static_cast<float>(radius * u[2]));
    potential.values.push_back(static_cast<float>(3 * std::sin(3 * lon) * std::cos(lat) + 0.5 * std::sin(5 * lat)));
    const bool missing = nearest == 6;  // A:7
    b_factor.values.push_back(missing ? std::numeric_limits<float>::quiet_NaN()
                                      : static_cast<float>(10 + 30 * (radius / 20 - 1) + 5 * std::cos(7 * lon)));
    chain.values.push_back(nearest < per_chain ? 0.0f : 1.0f);
    octant.values.push_back(static_cast<float>((u[0] < 0) + 2 * (u[1] < 0) + 4 * (u[2] < 0)));
  }
  height.range = data_range(ScaleKind::sequential, height.values);
  b_factor.range = data_range(ScaleKind::sequential, b_factor.values);
  data.properties = {height, potential, b_factor, chain, octant};
  return data;
}

/// The vertex of largest surface z: the top of the north bump, in plain view from +z.
inline std::int32_t highest_vertex(const ViewerData& data) {
  std::int32_t best = 0;
  for (std::size_t v = 1; v < data.surface_positions.size(); ++v)
    if (data.surface_positions[v][2] > data.surface_positions[best][2]) best = static_cast<std::int32_t>(v);
  return best;
}

}  // namespace spheremap::testing_support
