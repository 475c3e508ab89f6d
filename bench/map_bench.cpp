// Map + certify on generated meshes (issue: the mapping engine). Run with
//   ./build/map_bench --benchmark_filter=... (see BENCHMARKS.md for the exact commands and results)
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <map>

#include "spheremap/shapes.hpp"
#include "spheremap/sphere/map.hpp"
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

double peak_rss_megabytes() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return static_cast<double>(usage.ru_maxrss) / 1024.0;
}

void run(benchmark::State& state, spheremap::Solver solver) {
  const auto& mesh = cube(static_cast<int>(state.range(0)));
  spheremap::MapOptions options;
  options.solver = solver;
  bool certified = true, converged = true;
  std::int64_t sweeps = 0;
  for (auto _ : state) {
    const auto map = spheremap::map_to_sphere(mesh, options);
    certified = certified && map.certificate.certified();
    converged = converged && map.gauss_seidel_converged;
    sweeps = map.gauss_seidel_sweeps;
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
void BM_MapGaussSeidel(benchmark::State& state) { run(state, spheremap::Solver::kGaussSeidel); }

BENCHMARK(BM_MapDirect)->Arg(41)->Arg(129)->Arg(337)->Arg(408)->Arg(500)->Unit(benchmark::kMillisecond)->MeasureProcessCPUTime()->UseRealTime();
BENCHMARK(BM_MapGaussSeidel)->Arg(41)->Arg(129)->Unit(benchmark::kMillisecond)->Iterations(1)->MeasureProcessCPUTime()->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
