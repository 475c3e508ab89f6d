#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/surface/nearest_atoms.hpp"
#include "test_atoms.hpp"

namespace spheremap {
namespace {

using testing_support::atom_at;

// Smallest |p - centre| - radius, ties to the smallest index: the definition, by brute force.
std::int32_t brute_nearest(const Vec3& p, const std::vector<Atom>& atoms) {
  double best = std::numeric_limits<double>::infinity();
  std::int32_t chosen = -1;
  for (std::size_t a = 0; a < atoms.size(); ++a) {
    const double gap = norm(p - atoms[a].position) - atoms[a].radius;
    if (gap < best) best = gap, chosen = static_cast<std::int32_t>(a);
  }
  return chosen;
}

void expect_brute_force(const Mesh& mesh, const std::vector<Atom>& atoms) {
  const auto& index = mesh.integer_attributes.at(attributes::kAtomId);
  const auto& serial = mesh.integer_attributes.at(attributes::kAtomSerial);
  const auto& residue = mesh.integer_attributes.at(attributes::kResidueNumber);
  const auto& model = mesh.integer_attributes.at(attributes::kModel);
  ASSERT_EQ(index.size(), mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const std::int32_t expected = brute_nearest(mesh.positions[v], atoms);
    ASSERT_EQ(index[v], expected) << "vertex " << v;
    const Atom& atom = atoms[static_cast<std::size_t>(expected)];
    ASSERT_EQ(serial[v], atom.serial);
    ASSERT_EQ(residue[v], atom.residue_number);
    ASSERT_EQ(model[v], atom.model);
  }
}

TEST(NearestAtoms, AnyPointsGetTheNearestSphereAsBruteForceFindsIt) {
  // A random cluster of atoms and points in, around and far from it (points are not a surface: the
  // search must not rely on where a contour puts its vertices), with any number of threads.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  std::vector<Atom> atoms;
  for (int a = 0; a < 300; ++a)
    atoms.push_back(
        atom_at({20 * unit(random), 20 * unit(random), 20 * unit(random)}, 1.2 + 0.8 * unit(random), 1000 + a));
  Mesh mesh;
  for (int v = 0; v < 20000; ++v)
    mesh.positions.push_back({-4 + 28 * unit(random), -4 + 28 * unit(random), -4 + 28 * unit(random)});
  mesh.positions.push_back({200, -50, 3});  // far from every atom
  mesh.positions.push_back({-60, 0, 0});
  for (int threads : {1, 2, 3}) {
    SurfaceOptions options;
    options.threads = threads;
    Mesh copy = mesh;
    add_nearest_atoms(copy, atoms, options);
    expect_brute_force(copy, atoms);
  }
}

TEST(NearestAtoms, TiesGoToTheSmallestIndexAndCellBordersLoseNothing) {
  // Two equal spheres mirrored through x = 5: points on the mirror plane are tied. Points sit on
  // integer coordinates too (the borders of the 1 Å cells vertices are grouped by).
  std::vector<Atom> atoms = {atom_at({7, 1, 1}, 1.5, 1), atom_at({3, 1, 1}, 1.5, 2), atom_at({5, 6, 1}, 1.7, 3)};
  Mesh mesh;
  for (int x = 0; x <= 10; ++x)
    for (int y = -2; y <= 8; ++y)
      for (int z = -2; z <= 4; ++z)
        mesh.positions.push_back({static_cast<double>(x), static_cast<double>(y), static_cast<double>(z)});
  for (int y = -20; y <= 80; ++y) mesh.positions.push_back({5, 0.1 * y, 1.0 / 3.0});
  add_nearest_atoms(mesh, atoms, SurfaceOptions{});
  expect_brute_force(mesh, atoms);
  // On the mirror plane (away from the third atom) the tie goes to atom 0.
  EXPECT_EQ(mesh.integer_attributes.at(attributes::kAtomId)[mesh.vertex_count() - 101], 0);
}

TEST(NearestAtoms, AnEmptyMeshNeedsNoAtomsAndAMeshWithoutAtomsIsRefused) {
  Mesh empty;
  add_nearest_atoms(empty, {}, SurfaceOptions{});
  EXPECT_TRUE(empty.integer_attributes.at(attributes::kAtomId).empty());
  Mesh one;
  one.positions.push_back({0, 0, 0});
  EXPECT_THROW(add_nearest_atoms(one, {}, SurfaceOptions{}), InputError);
}

}  // namespace
}  // namespace spheremap
