#include "spheremap/surface/ses.hpp"

#include <gtest/gtest.h>

#include "../test_support.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <numbers>

#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/topology/components.hpp"
#include "test_atoms.hpp"

namespace spheremap {
namespace {

using testing_support::atom_at;

double area_of(const Mesh& mesh) {
  double area = 0;
  for (const auto& t : mesh.triangles)
    area += triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  return area;
}

using testing_support::expect_closed_oriented_manifold;

TEST(Ses, OneAtomGivesItsVanDerWaalsSphere) {
  SurfaceOptions options;
  options.grid = 0.25;
  const Mesh mesh = solvent_excluded_surface({atom_at({0.3, -0.2, 0.1}, 1.7, 1)}, options);
  expect_closed_oriented_manifold(mesh);
  EXPECT_NEAR(area_of(mesh) / (4 * std::numbers::pi * 1.7 * 1.7), 1.0, 0.02);
  // Vertices may sit up to a tenth of a step off the interpolated crossing (contour_isosurface), plus
  // the linear interpolation error of a curved surface: within 0.2 step.
  for (const auto& p : mesh.positions) ASSERT_NEAR(norm(p - Vec3{0.3, -0.2, 0.1}), 1.7, 0.2 * options.grid);
}

TEST(Ses, TwoTouchingAtomsAreBridgedByTheProbeAndFarAtomsAreNot) {
  SurfaceOptions options;
  options.grid = 0.25;
  // 4 Å apart: the van der Waals spheres (1.7) do not touch, but a 1.4 probe cannot pass between them
  // (4 < 2 * (1.7 + 1.4)), so the SES is one closed surface with a re-entrant neck.
  const Mesh bridged = solvent_excluded_surface({atom_at({0, 0, 0}, 1.7, 1), atom_at({4, 0, 0}, 1.7, 2)}, options);
  expect_closed_oriented_manifold(bridged);
  const double two_spheres = 2 * 4 * std::numbers::pi * 1.7 * 1.7;
  // Closed form: each sphere loses the cap facing the other one (half-angle α at its centre, towards
  // the ring of probe centres), and the probe's arc between its two contact points sweeps a toroidal
  // patch around the axis (Pappus: arc length x 2π x distance of the arc's centroid to the axis).
  const double r = 1.7, probe = 1.4, half = 2.0, reach = r + probe;
  const double ring = std::sqrt(reach * reach - half * half);  // distance of the probe centres to the axis
  const double cos_alpha = half / reach;
  const double caps = 2 * (2 * std::numbers::pi * r * r * (1 - cos_alpha));
  const double arc_angle = std::acos((-half * half + ring * ring) / (reach * reach));
  const double centroid = probe * std::sin(arc_angle / 2) / (arc_angle / 2);
  const double torus = probe * arc_angle * 2 * std::numbers::pi * (ring - centroid);
  EXPECT_NEAR(area_of(bridged) / (two_spheres - caps + torus), 1.0, 0.01);
  // Far apart: two separate spheres, exactly the two van der Waals areas.
  const Mesh apart = solvent_excluded_surface({atom_at({0, 0, 0}, 1.7, 1), atom_at({9, 0, 0}, 1.7, 2)}, options);
  expect_closed_oriented_manifold(apart);
  EXPECT_NEAR(area_of(apart) / two_spheres, 1.0, 0.02);
}

TEST(Ses, ThreeAtomsInARowHaveTwoIndependentNecks) {
  SurfaceOptions options;
  options.grid = 0.25;
  // Centres 4 Å apart on a line: each neighbouring pair is bridged as in the test above, and the middle
  // atom's two caps (half-angle α = 49.8° each) are far apart, so the closed form is 3 spheres - 4 caps
  // + 2 toroidal necks.
  const Mesh row = solvent_excluded_surface(
      {atom_at({0, 0, 0}, 1.7, 1), atom_at({4, 0, 0}, 1.7, 2), atom_at({8, 0, 0}, 1.7, 3)}, options);
  expect_closed_oriented_manifold(row);
  const double r = 1.7, probe = 1.4, half = 2.0, reach = r + probe;
  const double ring = std::sqrt(reach * reach - half * half);
  const double cap = 2 * std::numbers::pi * r * r * (1 - half / reach);
  const double arc_angle = std::acos((-half * half + ring * ring) / (reach * reach));
  const double centroid = probe * std::sin(arc_angle / 2) / (arc_angle / 2);
  const double torus = probe * arc_angle * 2 * std::numbers::pi * (ring - centroid);
  EXPECT_NEAR(area_of(row) / (3 * 4 * std::numbers::pi * r * r - 4 * cap + 2 * torus), 1.0, 0.01);
}

TEST(Ses, EveryVertexCarriesItsNearestAtom) {
  std::vector<Atom> atoms;
  for (int k = 0; k < 12; ++k)
    atoms.push_back(atom_at({1.3 * k, 0.7 * (k % 3), 0.4 * (k % 2)}, 1.5 + 0.05 * k, 100 + k));
  const Mesh mesh = solvent_excluded_surface(atoms, SurfaceOptions{});
  const auto& index = mesh.integer_attributes.at(attributes::kAtomId);
  const auto& serial = mesh.integer_attributes.at(attributes::kAtomSerial);
  ASSERT_EQ(index.size(), mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    double best = INFINITY;
    for (const auto& a : atoms) best = std::min(best, norm(mesh.positions[v] - a.position) - a.radius);
    const auto& chosen = atoms[static_cast<std::size_t>(index[v])];
    ASSERT_DOUBLE_EQ(norm(mesh.positions[v] - chosen.position) - chosen.radius, best);
    ASSERT_EQ(serial[v], chosen.serial);
  }
}

TEST(Ses, RefusesAGridBeyondTheMemoryBudgetAndSaysWhichSpacingFits) {
  SurfaceOptions options;
  options.grid = 0.01;
  options.max_grid_bytes = 1e6;
  try {
    solvent_excluded_field({atom_at({0, 0, 0}, 1.7, 1), atom_at({30, 0, 0}, 1.7, 2)}, options);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("use --grid"), std::string::npos) << e.what();
  }
}

// (area, signed volume) of each connected component, largest area first.
std::vector<std::pair<double, double>> components_of(const Mesh& mesh) {
  std::vector<std::pair<double, double>> out;
  for (const auto& c : mesh_components(mesh)) out.emplace_back(c.area, c.signed_volume);
  return out;
}

// Carbon atoms on a sphere of radius 10 Å, about 1.6 Å apart (Fibonacci lattice): no probe passes the
// shell, and the inside is a void of radius about 10 - 3.1 Å where a probe fits.
std::vector<Atom> hollow_shell() {
  std::vector<Atom> atoms;
  const int n = 480;
  const double golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int k = 0; k < n; ++k) {
    const double z = 1 - 2 * (k + 0.5) / n, r = std::sqrt(1 - z * z);
    atoms.push_back(atom_at({10 * r * std::cos(golden * k), 10 * r * std::sin(golden * k), 10 * z}, 1.7, k + 1));
  }
  return atoms;
}

TEST(Ses, CavitiesAreFilledByDefaultAndCarvedOnRequest) {
  const auto atoms = hollow_shell();
  SurfaceOptions options;
  const Mesh filled = solvent_excluded_surface(atoms, options);
  expect_closed_oriented_manifold(filled);
  EXPECT_EQ(components_of(filled).size(), 1u);
  options.carve_cavities = true;
  const Mesh carved = solvent_excluded_surface(atoms, options);
  expect_closed_oriented_manifold(carved);
  const auto parts = components_of(carved);
  ASSERT_EQ(parts.size(), 2u);
  // The outer surface is the same; the cavity faces into the void (negative signed volume), with about
  // the area of a sphere through the inner sides of the atoms (radius 10 - 1.7 Å), a little more for the
  // bumps between them.
  EXPECT_NEAR(parts[0].first / components_of(filled)[0].first, 1.0, 1e-9);
  EXPECT_GT(parts[0].second, 0);
  EXPECT_LT(parts[1].second, 0);
  const double inner_sphere = 4 * std::numbers::pi * 8.3 * 8.3;
  EXPECT_GT(parts[1].first, 0.9 * inner_sphere);
  EXPECT_LT(parts[1].first, 1.3 * inner_sphere);
  // The carved volume is the void: at least the ball of radius 10 - 3.1 Å swept by the probe.
  EXPECT_GT(-parts[1].second, 4.0 / 3 * std::numbers::pi * std::pow(10 - 3.1 + 1.4, 3) * 0.9);
}

// hollow_shell() with one window: the shell's atoms near the +z pole are replaced by a ring of 14
// atoms of radius `ring` (centres) around the z axis. The probe centre passes the window iff
// ring > 1.7 + 1.4: with ring = 3.2 Å its passage is 0.2 Å wide, narrower than the grid.
std::vector<Atom> shell_with_window(double ring) {
  std::vector<Atom> atoms;
  for (const Atom& a : hollow_shell())
    if (a.position[2] < 0 || std::hypot(a.position[0], a.position[1]) >= ring + 1.2) atoms.push_back(a);
  const double height = std::sqrt(100 - ring * ring);
  for (int k = 0; k < 14; ++k) {
    const double angle = 2 * std::numbers::pi * k / 14;
    atoms.push_back(atom_at({ring * std::cos(angle), ring * std::sin(angle), height}, 1.7, 1000 + k));
  }
  return atoms;
}

TEST(Ses, AProbePassesAChannelNarrowerThanTheGrid) {
  for (const double grid : {0.5, 0.25}) {
    SurfaceOptions options;
    options.grid = grid;
    // Closed window (the ring's enlarged spheres overlap on the axis): the void is filled, as without
    // a window. Open window, 0.2 Å wide for the probe centre: the probe rolls in and carves the void,
    // which joins the outer surface (no lattice sample lies in the passage: a lattice flood fill
    // alone filled it).
    const Mesh closed = solvent_excluded_surface(shell_with_window(3.0), options);
    const Mesh open = solvent_excluded_surface(shell_with_window(3.2), options);
    expect_closed_oriented_manifold(closed);
    expect_closed_oriented_manifold(open);
    const auto closed_parts = components_of(closed), open_parts = components_of(open);
    ASSERT_EQ(closed_parts.size(), 1u) << grid;
    ASSERT_EQ(open_parts.size(), 1u) << grid;
    const double filled = components_of(solvent_excluded_surface(hollow_shell(), options)).front().second;
    EXPECT_NEAR(closed_parts[0].second / filled, 1.0, 0.01) << grid;
    // Carved: the ball of radius 10 - 3.1 + 1.4 Å swept by the probe inside is gone from the volume.
    EXPECT_LT(open_parts[0].second, filled - 0.9 * 4.0 / 3 * std::numbers::pi * std::pow(10 - 3.1 + 1.4, 3)) << grid;
    EXPECT_GT(open_parts[0].first, 1.4 * closed_parts[0].first) << grid;
  }
}

TEST(Ses, TheAvx2PathGivesTheSameFieldToTheLastBit) {
#if defined(__GNUC__) && defined(__x86_64__)
  if (!__builtin_cpu_supports("avx2")) GTEST_SKIP() << "this processor has no AVX2: only the four-lane path runs here";
#else
  GTEST_SKIP() << "not an x86-64 build: there is no AVX2 path";
#endif
  std::vector<Atom> atoms = hollow_shell();
  atoms.resize(300);
  SurfaceOptions options;
  options.grid = 0.25;  // rows of up to 17 samples: one to three 8-lane vectors
  const auto eight_lanes = solvent_excluded_field_float(atoms, options);
  options.use_avx2 = false;
  const auto four_lanes = solvent_excluded_field_float(atoms, options);
  EXPECT_EQ(eight_lanes.values, four_lanes.values);
}

TEST(Ses, ResultsDoNotDependOnTheNumberOfThreads) {
  std::vector<Atom> atoms = hollow_shell();
  atoms.resize(300);  // an open bowl: pockets, re-entrant parts and circles of every kind
  SurfaceOptions options;
  options.grid = 0.4;
  options.threads = 1;
  const auto field = solvent_excluded_field(atoms, options);
  const auto field_float = solvent_excluded_field_float(atoms, options);
  const Mesh mesh = solvent_excluded_surface(atoms, options);
  for (int threads : {2, 3, 8}) {
    options.threads = threads;
    EXPECT_EQ(solvent_excluded_field(atoms, options).values, field.values) << threads;
    EXPECT_EQ(solvent_excluded_field_float(atoms, options).values, field_float.values) << threads;
    const Mesh again = solvent_excluded_surface(atoms, options);
    EXPECT_EQ(again.positions, mesh.positions) << threads;
    EXPECT_EQ(again.triangles, mesh.triangles) << threads;
    EXPECT_EQ(again.integer_attributes, mesh.integer_attributes) << threads;
  }
  // Single and double precision fields give the same surface up to rounding.
  const Mesh from_double = surface_from_field(field, atoms, options);
  expect_closed_oriented_manifold(mesh);
  ASSERT_EQ(from_double.triangles, mesh.triangles);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v)
    ASSERT_LT(norm(from_double.positions[v] - mesh.positions[v]), 1e-4 * options.grid);
}

TEST(Ses, TheBudgetCountsOneValuePerSample) {
  SurfaceOptions options;
  options.grid = 0.5;
  const std::vector<Atom> two = {atom_at({0, 0, 0}, 1.7, 1), atom_at({30, 0, 0}, 1.7, 2)};
  const auto field = solvent_excluded_field(two, options);
  const double needed = static_cast<double>(field.count()) * sizeof(double);
  options.max_grid_bytes = needed;
  EXPECT_NO_THROW(solvent_excluded_field(two, options));
  options.max_grid_bytes = needed / 2 + 1;  // enough for floats only
  EXPECT_THROW(solvent_excluded_field(two, options), InputError);
  EXPECT_NO_THROW(solvent_excluded_field_float(two, options));
}

}  // namespace
}  // namespace spheremap

namespace spheremap {
namespace {

TEST(DataSes, OuterAreaAndVolumeMatchMsmsAtBothProbesAndGrids) {
  const std::filesystem::path pdb = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb";
  if (!std::filesystem::exists(pdb)) GTEST_SKIP() << "shared data not found: " << pdb << " (skipped on purpose)";
  // MSMS analytic SES of the outer surface (Bondi radii, heavy atoms, no waters, HETATM kept), from the
  // issue: areas at probes 1.4 and 1.8 Å, volumes at 1.4 Å (0: not given).
  struct Reference {
    const char* file;
    double area14, area18, volume14;
  };
  const Reference references[] = {{"misc/1crn.cif", 2273.4, 2198.7, 4690.1},
                                  {"paper77/1ejg.pdb", 2245.6, 2167.8, 0},
                                  {"paper77/3lzt.pdb", 5465.6, 5145.0, 15643.5},
                                  {"misc/2src.pdb", 19550.1, 17879.3, 0},
                                  {"misc/4hhb.cif", 22629.8, 20492.7, 73469.1}};
  // Measured (bench/ses_accuracy, BENCHMARKS.md): with the default vertex clamp within 0.30% at 0.5 Å
  // and 0.47% at 0.25 Å; without it (plain linear interpolation) within 0.81% and 0.39%; volumes within
  // 0.06%.
  for (const auto& reference : references) {
    const auto molecule = read_structure(pdb / reference.file);
    for (const double probe : {1.4, 1.8})
      for (const double grid : {0.5, 0.25}) {
        SCOPED_TRACE(std::string(reference.file) + " probe " + std::to_string(probe) + " grid " + std::to_string(grid));
        SurfaceOptions options;
        options.probe = probe;
        options.grid = grid;
        const auto field = solvent_excluded_field_float(molecule.atoms, options);
        const double msms = probe == 1.4 ? reference.area14 : reference.area18;
        const Mesh mesh = surface_from_field(field, molecule.atoms, options);
        expect_closed_oriented_manifold(mesh);
        const auto outer = components_of(mesh).front();
        EXPECT_NEAR(outer.first / msms, 1.0, 0.005) << outer.first << " Å² against MSMS " << msms;
        if (probe == 1.4 && reference.volume14 > 0)
          EXPECT_NEAR(outer.second / reference.volume14, 1.0, 0.001)
              << outer.second << " Å³ against MSMS " << reference.volume14;
        options.contour_minimum_fraction = 0;
        const double plain = components_of(surface_from_field(field, molecule.atoms, options)).front().first;
        EXPECT_NEAR(plain / msms, 1.0, grid == 0.5 ? 0.01 : 0.005)
            << plain << " Å² (no vertex clamp) against MSMS " << msms;
      }
  }
}

}  // namespace
}  // namespace spheremap
