// The handle repair over every structure of ../shared/data/pdb at one grid spacing: genus before, what
// the repair did (cuts and fills, samples, volume, area), the outer area changed, and the genus after
// (must be 0). Prints a Markdown table and a summary line for BENCHMARKS.md.
//   ./build/repair_distribution GRID [PROBE] [--skip NAME,...] [--only NAME,...] [--threads N]
// NAME is a file's stem (e.g. 1aon). "seconds": wall-clock time of reading the structure and
// repaired_surface (field, contour, repair, provenance, components); "repair s": the wall-clock time of
// its repair stage alone; "CPU s": the process's CPU time over the whole (every thread).
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/error.hpp"
#include "spheremap/pipeline/molecular_surface.hpp"

namespace fs = std::filesystem;

int main(int argc, char** argv) {
  if (argc < 2) {
    std::fprintf(stderr, "usage: %s GRID [PROBE] [--skip NAME,...] [--only NAME,...] [--threads N]\n", argv[0]);
    return 1;
  }
  spheremap::SurfaceOptions surface;
  surface.grid = std::stod(argv[1]);
  if (argc > 2 && std::string(argv[2]).rfind("--", 0) != 0) surface.probe = std::stod(argv[2]);
  std::string skip, only;
  for (int a = 1; a + 1 < argc; ++a) {
    const std::string option = argv[a];
    if (option == "--skip") skip = "," + std::string(argv[a + 1]) + ",";
    if (option == "--only") only = "," + std::string(argv[a + 1]) + ",";
    if (option == "--threads") surface.threads = std::stoi(argv[a + 1]);
  }
  const fs::path data = fs::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb";
  if (!fs::exists(data)) {
    std::fprintf(stderr, "repair_distribution: %s not found\n", data.c_str());
    return 1;
  }
  std::vector<fs::path> files;
  for (const char* set : {"paper77", "misc"})
    for (const auto& entry : fs::directory_iterator(data / set)) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  std::printf(
      "| structure | atoms | genus before | method | cuts | fills | samples | volume (Å³) | outer area before (Å²) | "
      "area change (Å²) | change %% | Å² per handle | genus after | seconds | repair s | CPU s |\n");
  std::printf("|---|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|--:|\n");
  std::vector<double> changes;
  int repaired = 0, failed = 0, skipped = 0, per_handle = 0, measured = 0;
  for (const auto& file : files) {
    const std::string name = file.parent_path().filename().string() + "/" + file.filename().string();
    const std::string stem = "," + file.stem().string() + ",";
    if ((!skip.empty() && skip.find(stem) != std::string::npos) ||
        (!only.empty() && only.find(stem) == std::string::npos)) {
      if (only.empty()) std::printf("| %s | | | skipped | | | | | | | | | | | | |\n", name.c_str());
      ++skipped;
      continue;
    }
    ++measured;
    const auto start = std::chrono::steady_clock::now();
    const std::clock_t cpu_start = std::clock();
    try {
      const auto molecule = spheremap::read_structure(file);
      spheremap::HandleRepairReport repair;
      const auto result = spheremap::repaired_surface(molecule.atoms, surface, false, &repair);
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      const double cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
      double repair_seconds = 0;
      for (const auto& t : result.timings)
        if (t.stage == "repair") repair_seconds = t.seconds;
      const double area = repair.area_after - repair.area_before;
      const double change = repair.area_before > 0 ? 100 * (repair.area_after / repair.area_before - 1) : 0;
      const int genus_after = result.components.empty() ? 0 : result.components.front().genus;
      if (genus_after != 0) ++failed;
      if (repair.genus_before != 0) ++repaired, changes.push_back(std::abs(change));
      if (repair.method == spheremap::RepairMethod::kPerHandle) ++per_handle;
      int cuts = 0, fills = 0;
      for (const auto& c : repair.closures) (c.kind == spheremap::ClosureKind::kCut ? cuts : fills) += 1;
      std::printf(
          "| %s | %zu | %d | %s | %d | %d | %lld | %.1f | %.1f | %+.1f | %+.3f | %.1f | %d | %.1f | %.2f | %.1f |\n",
          name.c_str(), molecule.atoms.size(), repair.genus_before, spheremap::to_string(repair.method), cuts, fills,
          static_cast<long long>(repair.samples_changed), repair.volume_changed, repair.area_before, area, change,
          repair.genus_before > 0 ? area / repair.genus_before : 0.0, genus_after, seconds, repair_seconds, cpu);
    } catch (const std::exception& e) {
      ++failed;
      std::printf("| %s | | | error: %s | | | | | | | | | | | | |\n", name.c_str(), e.what());
    }
    std::fflush(stdout);
  }
  std::sort(changes.begin(), changes.end());
  auto quantile = [&](double q) {
    return changes.empty() ? 0.0 : changes[static_cast<std::size_t>(q * (changes.size() - 1))];
  };
  const auto over_one = std::count_if(changes.begin(), changes.end(), [](double c) { return c > 1.0; });
  std::printf(
      "\nSummary (grid %.2f Å, probe %.2f Å): %d structures measured, %d skipped, %d with handles repaired (%d per "
      "handle), "
      "%d not genus 0 after; |area change| of the repaired: median %.3f%%, 90th percentile %.3f%%, max %.3f%%, "
      "%lld above 1%%\n",
      surface.grid, surface.probe, measured, skipped, repaired, per_handle, failed, quantile(0.5), quantile(0.9),
      quantile(1.0), static_cast<long long>(over_one));
  return failed == 0 ? 0 : 3;
}
