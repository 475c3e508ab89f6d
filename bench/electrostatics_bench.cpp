// The built-in electrostatics on GroEL-GroES (1aon, 58,870 heavy atoms): the Coulomb potential at every
// vertex of the surface `spheremap map` maps (default options: 0.5 Å grid, handles repaired, 1 Å edges),
// 1.4 Å out along the normals, by the treecode on 2 threads; each benchmark reports the relative RMS error
// against the exact pair sum (computed once, untimed: about a minute). Run with
//   ./build/electrostatics_bench   (needs ../shared/data; BM_*Pdb2pqr also pdb2pqr30; see BENCHMARKS.md)
// The goal: <= 2 s on 2 cores with a relative RMS error <= 1e-3 (BM_CoulombGroEL/Random and /Pdb2pqr, 4r).
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <random>

#include "spheremap/geometry/normals.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/properties/coulomb.hpp"
#include "spheremap/properties/pdb2pqr.hpp"

namespace {

const std::filesystem::path kGroEL = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb/misc/1aon.pdb";

struct Problem {
  spheremap::PointCharges charges;
  std::vector<spheremap::Vec3> points;
  std::map<int, std::vector<double>> exact;  // by dielectric (0: 4r, 1: constant 4)
};

// The points: the mapped surface's vertices moved 1.4 Å out (built once).
const std::vector<spheremap::Vec3>& offset_points(std::vector<spheremap::Atom>* atoms) {
  static std::vector<spheremap::Atom> structure;
  static const std::vector<spheremap::Vec3> points = [] {
    spheremap::MapJobOptions options;
    options.map.repair = false;  // only the prepared (simplified) mesh is wanted
    const spheremap::Mesh mesh = spheremap::run_map_job(kGroEL, options).prepared.mesh;
    structure = spheremap::read_structure(kGroEL).atoms;
    return spheremap::offset_along_normals(mesh.positions, spheremap::vertex_normals(mesh.positions, mesh.triangles),
                                           1.4);
  }();
  if (atoms) *atoms = structure;
  return points;
}

// Charges: 0 = a partial charge in [-0.5, 0.5] on every heavy atom (fixed seed); 1 = pdb2pqr's AMBER charges
// with the hydrogens it adds (about 120k charges). Null when a program or the data is missing.
Problem* problem(int charges) {
  static std::map<int, Problem> cache;
  if (auto it = cache.find(charges); it != cache.end()) return &it->second;
  if (!std::filesystem::exists(kGroEL) || (charges == 1 && !spheremap::pdb2pqr_available())) return nullptr;
  std::vector<spheremap::Atom> atoms;
  Problem p;
  p.points = offset_points(&atoms);
  if (charges == 0) {
    std::mt19937 random(1);
    std::uniform_real_distribution<double> charge(-0.5, 0.5);
    for (const auto& a : atoms) {
      p.charges.positions.push_back(a.position);
      p.charges.charges.push_back(charge(random));
    }
  } else {
    p.charges = spheremap::pdb2pqr_charges(atoms, spheremap::ForceField::kAmber, "1aon.pdb").points;
  }
  return &cache.emplace(charges, std::move(p)).first->second;
}

spheremap::CoulombOptions options(int dielectric, spheremap::CoulombSummation summation) {
  spheremap::CoulombOptions o;
  o.dielectric = dielectric == 0 ? spheremap::Dielectric::kDistanceDependent : spheremap::Dielectric::kConstant;
  o.summation = summation;
  o.threads = 2;
  if (const char* threads = std::getenv("SPHEREMAP_THREADS")) o.threads = std::atoi(threads);
  return o;
}

// BM_CoulombGroEL/<charges: 0 random, 1 pdb2pqr>/<dielectric: 0 is 4r, 1 is constant>
void BM_CoulombGroEL(benchmark::State& state) {
  Problem* p = problem(static_cast<int>(state.range(0)));
  if (p == nullptr) {
    state.SkipWithError("../shared/data/pdb/misc/1aon.pdb or pdb2pqr30 not found");
    return;
  }
  const int dielectric = static_cast<int>(state.range(1));
  auto& exact = p->exact[dielectric];
  if (exact.empty())
    exact =
        spheremap::coulomb_potential(p->charges, p->points, options(dielectric, spheremap::CoulombSummation::kExact));
  std::vector<double> fast;
  for (auto _ : state)
    fast = spheremap::coulomb_potential(p->charges, p->points,
                                        options(dielectric, spheremap::CoulombSummation::kTreecode));
  // Also over the points of moderate potential only (|exact| <= 30 kT/e): the few points a handle cut puts
  // inside atoms reach thousands of kT/e and would dominate the reference.
  double squared_error = 0, moderate_error = 0, moderate_reference = 0;
  for (std::size_t i = 0; i < fast.size(); ++i) {
    const double e = (fast[i] - exact[i]) * (fast[i] - exact[i]);
    squared_error += e;
    if (std::abs(exact[i]) <= 30) moderate_error += e, moderate_reference += exact[i] * exact[i];
  }
  state.counters["points"] = static_cast<double>(p->points.size());
  state.counters["charges"] = static_cast<double>(p->charges.charges.size());
  state.counters["relative_rms_error"] = spheremap::relative_rms_difference(fast, exact);
  state.counters["rms_error_kT_per_e"] = std::sqrt(squared_error / static_cast<double>(fast.size()));
  if (moderate_reference > 0)
    state.counters["relative_rms_error_below_30"] = std::sqrt(moderate_error / moderate_reference);
}
BENCHMARK(BM_CoulombGroEL)->ArgsProduct({{0, 1}, {0, 1}})->Unit(benchmark::kMillisecond)->UseRealTime()->Iterations(3);

}  // namespace

BENCHMARK_MAIN();
