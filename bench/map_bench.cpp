// Map + certify on generated meshes (issue: the mapping engine) and on molecular surfaces, and the sparse
// Cholesky factorization in each fill-reducing order. Run with
//   ./build/map_bench --benchmark_filter=... (see BENCHMARKS.md for the exact commands and results)
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <chrono>
#include <filesystem>
#include <map>
#include <string>

#include "../src/sphere/harmonic.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/sphere/poles.hpp"
#include "spheremap/topology/connectivity.hpp"
#include "spheremap/topology/prepare.hpp"

namespace {

// Subdivided cube surfaces: 6n² + 2 vertices (n = 41: 10,088; 129: 99,848; 337: 681,416; 408: 998,786; 500: 1,500,002),
// with z ties everywhere (a symmetric mesh).
const spheremap::Mesh& cube(int n) {
  static std::map<int, spheremap::Mesh> cache;
  auto it = cache.find(n);
  if (it == cache.end()) it = cache.emplace(n, spheremap::prepare_mesh(spheremap::make_subdivided_cube(n)).mesh).first;
  return it->second;
}

// The same cube with every vertex moved by up to 5% of its mean edge length (issue 26): as
// `spheremap generate cube --n N --perturb 0.05 --seed 1` makes it. No ties in z.
const spheremap::Mesh& perturbed_cube(int n) {
  static std::map<int, spheremap::Mesh> cache;
  auto it = cache.find(n);
  if (it == cache.end())
    it = cache
             .emplace(
                 n,
                 spheremap::prepare_mesh(spheremap::perturb_vertices(spheremap::make_subdivided_cube(n), 0.05, 1)).mesh)
             .first;
  return it->second;
}

// A mesh of ../shared/data/meshes, prepared as `spheremap map` prepares it; null if absent.
const spheremap::Mesh* shared_mesh(const char* name) {
  static std::map<std::string, spheremap::Mesh> cache;
  if (auto it = cache.find(name); it != cache.end()) return &it->second;
  const auto path = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "meshes" / name;
  if (!std::filesystem::exists(path)) return nullptr;
  return &cache.emplace(name, spheremap::prepare_mesh(spheremap::read_polygon_soup(path)).mesh).first->second;
}

double peak_rss_megabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

void run(benchmark::State& state, spheremap::Solver solver, bool perturbed = false) {
  const auto& mesh =
      perturbed ? perturbed_cube(static_cast<int>(state.range(0))) : cube(static_cast<int>(state.range(0)));
  spheremap::MapOptions options;
  options.solver = solver;
  bool certified = true, converged = true;
  std::int64_t sweeps = 0;
  for (auto _ : state) {
    const auto map = spheremap::map_to_sphere(mesh, options);
    certified = certified && map.certificate.certified();
    converged = converged && map.diagnostics.solve.gauss_seidel_converged;
    sweeps = map.diagnostics.solve.gauss_seidel_sweeps;
    benchmark::DoNotOptimize(map.sphere.data());
  }
  state.counters["vertices"] = static_cast<double>(mesh.vertex_count());
  state.counters["certified"] = certified ? 1 : 0;
  if (solver == spheremap::Solver::kGaussSeidel) {
    state.counters["sweeps_z_plus_phi"] = static_cast<double>(sweeps);
    state.counters["converged"] = converged ? 1 : 0;
  }
  state.counters["peak_rss_MB"] = peak_rss_megabytes();
}

void BM_MapDirect(benchmark::State& state) { run(state, spheremap::Solver::kDirect); }
void BM_MapDirectPerturbed(benchmark::State& state) { run(state, spheremap::Solver::kDirect, true); }

// Times map_to_sphere with the default options on a prepared mesh; counts its vertices, certification and
// re-weighting rounds. Returns the last map.
spheremap::SphereMap map_with_defaults(benchmark::State& state, const spheremap::Mesh& mesh) {
  spheremap::SphereMap map;
  for (auto _ : state) map = spheremap::map_to_sphere(mesh);
  state.counters["vertices"] = static_cast<double>(mesh.vertex_count());
  state.counters["certified"] = map.certificate.certified() ? 1 : 0;
  state.counters["rounds"] = map.diagnostics.repair.reweighting_rounds;
  return map;
}

// map_to_sphere with the default options on ../shared/data/meshes/libigl_armadillo.obj (43,243 vertices;
// issue 26: FLASH 0.97 s), prepared outside the timing.
void BM_MapArmadillo(benchmark::State& state) {
  const auto* mesh = shared_mesh("libigl_armadillo.obj");
  if (!mesh) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  const auto map = map_with_defaults(state, *mesh);
  state.SetLabel(to_string(map.diagnostics.solve.elimination_order));
}
void BM_MapGaussSeidel(benchmark::State& state) { run(state, spheremap::Solver::kGaussSeidel); }

// Molecular surfaces as `spheremap map` maps them: the outer surface of a structure of ../shared/data at
// grid/100 Å, handles repaired, simplified to 1 Å edges (built once, outside the timing). Null if absent.
constexpr const char* kStructures[] = {"misc/5hr7.pdb", "misc/4hhb.cif", "misc/1aon.pdb"};

const spheremap::Mesh* molecular_surface(int which, int grid) {
  static std::map<std::pair<int, int>, spheremap::Mesh> cache;
  const auto key = std::make_pair(which, grid);
  if (auto it = cache.find(key); it != cache.end()) return &it->second;
  const auto path = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb" / kStructures[which];
  if (!std::filesystem::exists(path)) return nullptr;
  spheremap::MapJobOptions options;
  options.surface.grid = grid / 100.0;
  options.map.repair = false;  // only the prepared mesh is wanted here
  return &cache.emplace(key, spheremap::run_map_job(path, options).prepared.mesh).first->second;
}

// map_to_sphere with the default options on a molecular surface (BM_MapMolecular/structure/grid).
void BM_MapMolecular(benchmark::State& state) {
  const auto* mesh = molecular_surface(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  if (!mesh) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  const auto map = map_with_defaults(state, *mesh);
  state.SetLabel(std::string(kStructures[state.range(0)]) + " " + to_string(map.diagnostics.solve.elimination_order));
}

// One numeric factorization of the uniform-weight system of a molecular surface (poles: the farthest
// pair, fixed with their rings), in the geometric order (order 0), METIS's (1) or AMD's (2):
// BM_Factorize/structure/grid/order. The order's own time is a counter (computed once).
void factorize(benchmark::State& state, const spheremap::Mesh* mesh, int method, const std::string& name) {
  if (!mesh) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  namespace detail = spheremap::detail;
  const auto n = static_cast<std::int32_t>(mesh->vertex_count());
  const auto rings = spheremap::build_vertex_rings(n, mesh->triangles);
  const auto [north, south] = spheremap::farthest_pair(mesh->positions);
  std::vector<char> fixed(n, 0);
  for (const auto pole : {north, south}) {
    fixed[pole] = 1;
    for (const auto v : rings.ring(pole)) fixed[v] = 1;
  }
  const auto start = std::chrono::steady_clock::now();
  const auto order = method == 1   ? detail::metis_elimination_order(rings, mesh->positions, fixed)
                     : method == 2 ? detail::amd_elimination_order(rings, mesh->positions, fixed)
                                   : detail::geometric_elimination_order(rings, mesh->positions, fixed);
  const double order_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  detail::ReusableCholesky factor(rings, order);
  const detail::EdgeWeights weights{std::vector<double>(rings.neighbors.size(), 1.0), true, 0};
  const detail::HarmonicProblem problem{&rings, &weights, &mesh->positions, fixed, {}};
  for (auto _ : state) benchmark::DoNotOptimize(factor.factorize(problem));
  state.counters["vertices"] = n;
  state.counters["flops"] = factor.flops();
  state.counters["order_seconds"] = order_seconds;
  state.SetLabel(name + " " + spheremap::to_string(order.method));
}

void BM_Factorize(benchmark::State& state) {
  factorize(state, molecular_surface(static_cast<int>(state.range(0)), static_cast<int>(state.range(1))),
            static_cast<int>(state.range(2)), kStructures[state.range(0)]);
}

// The same on the meshes of issue 26's speed goals, BM_FactorizeMesh/mesh/order: the subdivided cube of
// 681,416 vertices (mesh 0), perturbed (1), and armadillo (2). The map takes the order with fewer flops;
// this measures whether that is the faster one.
void BM_FactorizeMesh(benchmark::State& state) {
  const auto which = state.range(0);
  const spheremap::Mesh* mesh = which == 0   ? &cube(337)
                                : which == 1 ? &perturbed_cube(337)
                                             : shared_mesh("libigl_armadillo.obj");
  const char* names[] = {"cube 337", "perturbed cube 337", "armadillo"};
  factorize(state, mesh, static_cast<int>(state.range(1)), names[which]);
}

BENCHMARK(BM_MapMolecular)
    ->Args({0, 50})
    ->Args({1, 50})
    ->Args({2, 100})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_Factorize)
    ->ArgsProduct({{0, 1}, {50}, {0, 1, 2}})
    ->Args({2, 100, 0})
    ->Args({2, 100, 1})
    ->Args({2, 100, 2})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_FactorizeMesh)
    ->ArgsProduct({{0, 1, 2}, {0, 2}})
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_MapDirectPerturbed)->Arg(337)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(BM_MapArmadillo)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(BM_MapDirect)
    ->Arg(41)
    ->Arg(129)
    ->Arg(337)
    ->Arg(408)
    ->Arg(500)
    ->Unit(benchmark::kMillisecond)
    ->MeasureProcessCPUTime()
    ->UseRealTime();
BENCHMARK(BM_MapGaussSeidel)
    ->Arg(41)
    ->Arg(129)
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
