// Maps made in several threads of one process at once are byte-identical to one made alone
// (docs/library.md, "Thread safety"): the same prepared meshes mapped from four threads, 50 rounds each.
// Without the library's SolverSection, Debian 12's serial OpenBLAS handed two threads the same scratch
// buffer and 51 to 265 of the 600 maps came out different.
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/prepare.hpp"

namespace spheremap {
namespace {

// Everything a map holds that must not depend on the thread, as bytes.
std::string map_bytes(const SphereMap& map) {
  std::string bytes;
  const auto add = [&](const void* data, std::size_t size) { bytes.append(static_cast<const char*>(data), size); };
  add(map.sphere.data(), map.sphere.size() * sizeof(Vec3));
  add(map.theta.data(), map.theta.size() * sizeof(double));
  add(map.phi.data(), map.phi.size() * sizeof(double));
  const Certificate& c = map.certificate;
  for (const auto count : {c.triangle_count, c.folded, c.collapsed}) add(&count, sizeof count);
  add(&c.coverage, sizeof c.coverage);
  const int rounds[] = {map.diagnostics.repair.reweighting_rounds, map.diagnostics.repair.equalizing_rounds};
  add(rounds, sizeof rounds);
  return bytes;
}

struct Case {
  std::string name;
  Mesh mesh;
  MapOptions options;
};

// Each path into CHOLMOD and UMFPACK: re-weighted Cholesky (uniform), sparse LU (mean-value), and the
// objective's Newton steps (CHOLMOD through Eigen).
std::vector<Case> cases() {
  std::vector<Case> list;
  MapOptions uniform;
  list.push_back({"cube", prepare_mesh(perturb_vertices(make_subdivided_cube(20), 0.2, 3)).mesh, uniform});
  MapOptions mean_value;
  mean_value.weights = Weights::kMeanValue;
  list.push_back({"icosphere",
                  prepare_mesh(random_edge_flips(perturb_vertices(make_icosphere(4), 0.3, 7), 0.1, 11)).mesh,
                  mean_value});
  MapOptions balanced;
  balanced.objective = MapObjective::kBalanced;
  balanced.objective_max_iterations = 3;
  list.push_back({"dumbbell", prepare_mesh(make_dumbbell(3.0, 0.3, 40, 40)).mesh, balanced});
  return list;
}

TEST(LongThreads, FourThreadsMapTheSameMeshesAsOneThreadDoes) {
  const std::vector<Case> inputs = cases();
  std::vector<std::string> alone;
  for (const auto& input : inputs) {
    const SphereMap map = map_to_sphere(input.mesh, input.options);
    ASSERT_TRUE(map.certificate.certified()) << input.name;
    alone.push_back(map_bytes(map));
  }
  constexpr int kThreads = 4, kRounds = 50;
  std::vector<std::vector<int>> differing(kThreads, std::vector<int>(inputs.size(), 0));  // per thread, per mesh
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (int round = 0; round < kRounds; ++round)
        for (std::size_t k = 0; k < inputs.size(); ++k) {
          const auto i = (k + static_cast<std::size_t>(t)) % inputs.size();  // threads start on different meshes
          differing[t][i] += map_bytes(map_to_sphere(inputs[i].mesh, inputs[i].options)) != alone[i];
        }
    });
  for (auto& thread : threads) thread.join();
  int count = 0;
  std::string which;
  for (std::size_t i = 0; i < inputs.size(); ++i) {
    int of_mesh = 0;
    for (const auto& per_mesh : differing) of_mesh += per_mesh[i];
    count += of_mesh;
    which += " " + inputs[i].name + " " + std::to_string(of_mesh) + "/" + std::to_string(kThreads * kRounds);
  }
  EXPECT_EQ(count, 0) << count << " of " << kThreads * kRounds * static_cast<int>(inputs.size())
                      << " maps made in threads differ from the map made alone:" << which;
}

// A structure through the whole job (molecular surface, repair, simplification, map) from four threads.
TEST(DataThreads, AStructureMapsTheSameFromFourThreadsAsAlone) {
  const std::filesystem::path input = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb/misc/1yjp.pdb";
  if (!std::filesystem::exists(input)) GTEST_SKIP() << input << " is absent (../shared/data)";
  MapJobOptions options;
  options.surface.grid = 1.0;
  const MapJobResult alone = run_map_job(input, options);
  const std::string expected = map_bytes(alone.map);
  constexpr int kThreads = 4, kRounds = 10;
  std::vector<int> differing(kThreads, 0);
  std::vector<std::thread> threads;
  for (int t = 0; t < kThreads; ++t)
    threads.emplace_back([&, t] {
      for (int round = 0; round < kRounds; ++round) {
        const MapJobResult result = run_map_job(input, options);
        differing[t] += map_bytes(result.map) != expected ||
                        result.prepared.mesh.positions != alone.prepared.mesh.positions ||
                        result.prepared.mesh.triangles != alone.prepared.mesh.triangles;
      }
    });
  for (auto& thread : threads) thread.join();
  int count = 0;
  for (const int d : differing) count += d;
  EXPECT_EQ(count, 0) << count << " of " << kThreads * kRounds << " jobs made in threads differ from the job run alone";
}

}  // namespace
}  // namespace spheremap
