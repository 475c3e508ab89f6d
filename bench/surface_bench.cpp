// Surface stage: time, memory and accuracy of the SES against the MSMS areas of the issue. Run with
//   ./build/surface_bench   (needs ../shared/data; see BENCHMARKS.md)
// BM_Surface/<structure>/<grid in 1/100 Å>; structures 0-4 are those of the MSMS references, 5 (1aon) is
// the large one (filter it out for a quick run: --benchmark_filter='BM_Surface/[0-4]/'), 6 is 5hr7. SPHEREMAP_THREADS=n
// sets SurfaceOptions::threads (default: one per hardware thread). peak_rss_MB is the whole process so far: measure one
// benchmark per process.
#include <benchmark/benchmark.h>
#include <sys/resource.h>

#include <cstdlib>
#include <filesystem>

#include "spheremap/molecule/structure.hpp"
#include "spheremap/surface/ses.hpp"
#include "spheremap/topology/components.hpp"

namespace {

struct Reference {
  const char* file;
  double msms_area;    // Å², probe 1.4
  double msms_volume;  // Å³, probe 1.4 (0 when not given)
};
const Reference kReferences[] = {
    {"misc/1crn.cif", 2273.4, 4690.1},
    {"paper77/1ejg.pdb", 2245.6, 0},
    {"paper77/3lzt.pdb", 5465.6, 15643.5},
    {"misc/2src.pdb", 19550.1, 0},
    {"misc/4hhb.cif", 22629.8, 73469.1},
    // GroEL-GroES (58.9k heavy atoms): the memory goal, 0.25 Å within 4 GB. No MSMS figure.
    {"misc/1aon.pdb", 0, 0},
    // 8.7k atoms: the size of the speed goals (NanoShaper 0.81 s at 0.5 Å, 3.0 s at 0.25 Å).
    {"misc/5hr7.pdb", 0, 0}};

void BM_Surface(benchmark::State& state) {
  const Reference& reference = kReferences[state.range(0)];
  const auto path = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb" / reference.file;
  if (!std::filesystem::exists(path)) {
    state.SkipWithError("../shared/data not found");
    return;
  }
  const auto molecule = spheremap::read_structure(path);
  spheremap::SurfaceOptions options;
  options.grid = static_cast<double>(state.range(1)) / 100.0;
  if (const char* threads = std::getenv("SPHEREMAP_THREADS")) options.threads = std::atoi(threads);
  spheremap::Mesh mesh;
  for (auto _ : state) mesh = spheremap::solvent_excluded_surface(molecule.atoms, options);
  const auto components = spheremap::mesh_components(mesh);  // the outer surface first (largest area)
  const auto& outer = components.front();
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  state.counters["atoms"] = static_cast<double>(molecule.atoms.size());
  state.counters["triangles"] = static_cast<double>(mesh.triangle_count());
  state.counters["components"] = static_cast<double>(components.size());
  state.counters["outer_genus"] = outer.genus;
  state.counters["outer_area"] = outer.area;
  if (reference.msms_area > 0) state.counters["area_vs_msms_pct"] = 100 * (outer.area / reference.msms_area - 1);
  state.counters["outer_volume"] = outer.signed_volume;
  if (reference.msms_volume > 0)
    state.counters["volume_vs_msms_pct"] = 100 * (outer.signed_volume / reference.msms_volume - 1);
  state.counters["peak_rss_MB"] = static_cast<double>(usage.ru_maxrss) / 1024.0;
  state.SetLabel(reference.file);
}

BENCHMARK(BM_Surface)
    ->ArgsProduct({{0, 1, 2, 3, 4, 5, 6}, {50, 25}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(1)
    ->MeasureProcessCPUTime()
    ->UseRealTime();

}  // namespace

BENCHMARK_MAIN();
