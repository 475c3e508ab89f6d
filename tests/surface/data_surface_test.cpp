// Every structure of ../shared/data/pdb gives a closed, oriented, genus-0 outer surface after repair.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <utility>
#include <vector>

#include "../test_support.hpp"
#include "spheremap/pipeline/molecular_surface.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

class DataSurface : public testing_support::SharedStructuresTest {};

TEST_F(DataSurface, EveryStructureGivesAClosedGenusZeroOuterSurface) {
  // 1 Å keeps the whole set within CI time (GroEL included); the 0.5 and 0.25 Å figures are in
  // BENCHMARKS.md (bench/repair_distribution).
  const SurfaceOptions options{.grid = 1.0};
  int repaired = 0;
  double worst_change = 0;
  for (const auto& file : files_) {
    SCOPED_TRACE(file.string());
    const Molecule molecule = read_structure(file);
    HandleRepairReport repair;
    const MolecularSurface surface = repaired_surface(molecule.atoms, options, false, &repair);
    testing_support::expect_closed_oriented_manifold(surface.mesh);
    ASSERT_FALSE(surface.components.empty());
    EXPECT_EQ(surface.components.front().genus, 0);
    EXPECT_EQ(surface.reports.front().kind, SurfaceComponentKind::kOuter);
    if (repair.genus_before != 0) {
      ++repaired;
      EXPECT_FALSE(repair.closures.empty());
      worst_change = std::max(worst_change, std::abs(repair.area_after / repair.area_before - 1));
    }
  }
  std::printf("88 structures at 1 Å: %d repaired to genus 0, largest outer-area change %.3f%%\n", repaired,
              100 * worst_change);
}

TEST_F(DataSurface, HandleRepairChangesLittleAreaWhereTheGreedyRepairChangedMuch) {
  // At 0.5 Å the smallest-first repair changed the outer area of these by 4.9%, 2.0%, 1.5% and 2.3%
  // (cuts and fills paired badly, membranes where the growths met); the bounds sit above what the joint
  // choice and the moved membranes give (0.98%, 1.16%, 0.82%, 1.80%: BENCHMARKS.md).
  const fs::path pdb = fs::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb" / "misc";
  const std::vector<std::pair<const char*, double>> cases = {
      {"4gxy.cif", 1.2}, {"2src.pdb", 1.3}, {"1d66.pdb", 1.0}, {"4hhb.cif", 2.0}};
  for (const auto& [name, bound] : cases) {
    const fs::path file = pdb / name;
    if (!fs::exists(file)) GTEST_SKIP() << "shared data not found: " << file << " (skipped on purpose)";
    SCOPED_TRACE(file.string());
    const Molecule molecule = read_structure(file);
    SurfaceOptions options;
    options.grid = 0.5;
    HandleRepairReport repair;
    const MolecularSurface surface = repaired_surface(molecule.atoms, options, false, &repair);
    ASSERT_GT(repair.genus_before, 0);
    EXPECT_EQ(repair.method, RepairMethod::kPerHandle);
    EXPECT_EQ(surface.components.front().genus, 0);
    const double change = 100 * (repair.area_after / repair.area_before - 1);
    EXPECT_LT(std::abs(change), bound);
    // Each closure reports its area, its lining residues and how many handles it removed; together they
    // are the outer surface's change (these repairs touch no other component).
    double sum = 0;
    int handles = 0;
    for (const auto& c : repair.closures) {
      EXPECT_FALSE(c.lining_residues.empty());
      EXPECT_GT(c.volume, 0);
      sum += c.area_change;
      handles += c.handles_removed;
    }
    EXPECT_EQ(handles, repair.genus_before);
    EXPECT_NEAR(sum, repair.area_after - repair.area_before, 1e-6 * repair.area_before);
    std::printf("%s at 0.5 Å: genus %d, %zu closures, outer area %+.3f%%\n", name, repair.genus_before,
                repair.closures.size(), change);
  }
}

}  // namespace
}  // namespace spheremap
