// Pictures of a map (issue 24's speed goals). Run with
//   ./build/pictures_bench   (needs ../shared/data for BM_AllPictures5hr7; see BENCHMARKS.md)
// Goals on 2 cores: every default picture and the viewer of 5hr7 (8.7k atoms, default options) in
// <= 0.5 s (BM_AllPictures5hr7: what `map` adds after writing the map); a 2048 x 1024 Mollweide map of a
// 1M-vertex sphere in <= 1 s (BM_RenderMollweide1M: the locator, the sampling and the figure, as `render`).
#include <benchmark/benchmark.h>

#include <unistd.h>
#include <cmath>
#include <filesystem>

#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/render/map_picture.hpp"
#include "spheremap/render/map_pictures.hpp"
#include "spheremap/render/viewer_data.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace {

const std::filesystem::path k5hr7 = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb/misc/5hr7.pdb";

void BM_AllPictures5hr7(benchmark::State& state) {
  if (!std::filesystem::exists(k5hr7)) {
    state.SkipWithError("../shared/data/pdb/misc/5hr7.pdb not found");
    return;
  }
  static const spheremap::MapJobResult result = spheremap::run_map_job(k5hr7, {});
  const std::filesystem::path folder =
      std::filesystem::temp_directory_path() / ("spheremap-pictures-bench-" + std::to_string(::getpid()));
  std::filesystem::create_directories(folder);
  std::size_t files = 0;
  for (auto _ : state) {
    const spheremap::Mesh& surface = result.prepared.mesh;
    // The properties `map` draws (cli/pictures.cpp's globe_of): the map job's, else those of the attributes.
    const spheremap::Globe globe = spheremap::make_globe(
        surface, result.map.sphere,
        result.properties.empty() ? spheremap::properties_from_attributes(surface, result.map.sphere)
                                  : result.properties,
        "5hr7");
    const auto written = spheremap::write_map_pictures(
        folder, globe, spheremap::viewer_data_for_map(surface, result.map.sphere, "5hr7", globe.properties), 2);
    files = written.size();
  }
  std::filesystem::remove_all(folder);
  state.counters["vertices"] = static_cast<double>(result.prepared.mesh.vertex_count());
  state.counters["files"] = static_cast<double>(files);  // pictures, grids and the viewer
}
BENCHMARK(BM_AllPictures5hr7)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

void BM_RenderMollweide1M(benchmark::State& state) {
  // A subdivided cube pushed onto the sphere: 6 * 409^2 + 2 = 1,003,688 vertices.
  static const spheremap::Globe globe = [] {
    const spheremap::Mesh cube = spheremap::make_subdivided_cube(409);
    std::vector<spheremap::Vec3> sphere;
    spheremap::SurfaceProperty z{{"z", "", spheremap::ScaleKind::sequential, std::nullopt, {}}, "bench", {}};
    for (const spheremap::Vec3& p : cube.positions) {
      const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
      sphere.push_back({p[0] / n, p[1] / n, p[2] / n});
      z.values.push_back(p[2] / n);
    }
    return spheremap::make_globe(cube, sphere, {z}, "cube");
  }();
  spheremap::MapFigureOptions options;
  options.threads = 2;
  for (auto _ : state) {
    const spheremap::SphereLocator locator = spheremap::make_sphere_locator(globe.sphere, globe.triangles, 2);
    const auto size = spheremap::map_image_size(options);
    const auto samples = spheremap::sample_map(locator, spheremap::Projection::mollweide, size[0], size[1], 2);
    benchmark::DoNotOptimize(spheremap::map_figure(globe, globe.properties[0], samples, options).size());
  }
  state.counters["vertices"] = static_cast<double>(globe.sphere.size());
}
BENCHMARK(BM_RenderMollweide1M)->Unit(benchmark::kMillisecond)->UseRealTime()->MeasureProcessCPUTime();

}  // namespace

BENCHMARK_MAIN();
