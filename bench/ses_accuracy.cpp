// Surface stage: outer SES area and volume against MSMS's analytic figures of the issue, for any grid,
// probe and contour vertex clamp. Prints one row per run (CPU time of solvent_excluded_surface included).
//   ./build/ses_accuracy [--grid 0.5,0.25] [--probe 1.4,1.8] [--clamp 0.1,0] [--threads N] [--only 1crn,4hhb]
// Needs ../shared/data (see BENCHMARKS.md, "Solvent-excluded surface").
#include <sys/resource.h>
#include <ctime>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include "spheremap/molecule/structure.hpp"
#include "spheremap/surface/ses.hpp"
#include "spheremap/topology/components.hpp"

namespace {

struct Reference {
  const char* name;
  const char* file;
  double area14, area18;  // Å², MSMS outer SES, probes 1.4 and 1.8 Å
  double volume14;        // Å³, probe 1.4 (0: not given)
};
const Reference kReferences[] = {{"1crn", "misc/1crn.cif", 2273.4, 2198.7, 4690.1},
                                 {"1ejg", "paper77/1ejg.pdb", 2245.6, 2167.8, 0},
                                 {"3lzt", "paper77/3lzt.pdb", 5465.6, 5145.0, 15643.5},
                                 {"2src", "misc/2src.pdb", 19550.1, 17879.3, 0},
                                 {"4hhb", "misc/4hhb.cif", 22629.8, 20492.7, 73469.1}};

std::vector<double> numbers(const char* text) {
  std::vector<double> out;
  std::stringstream in(text);
  std::string item;
  while (std::getline(in, item, ',')) out.push_back(std::atof(item.c_str()));
  return out;
}

double cpu_seconds() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + 1e-9 * static_cast<double>(t.tv_nsec);
}

}  // namespace

int main(int argc, char** argv) {
  std::vector<double> grids{0.5, 0.25}, probes{1.4, 1.8}, clamps{spheremap::kContourMinimumFraction, 0};
  std::string only;
  int threads = 0;
  for (int a = 1; a + 1 < argc; a += 2) {
    if (!std::strcmp(argv[a], "--grid"))
      grids = numbers(argv[a + 1]);
    else if (!std::strcmp(argv[a], "--probe"))
      probes = numbers(argv[a + 1]);
    else if (!std::strcmp(argv[a], "--clamp"))
      clamps = numbers(argv[a + 1]);
    else if (!std::strcmp(argv[a], "--threads"))
      threads = std::atoi(argv[a + 1]);
    else if (!std::strcmp(argv[a], "--only"))
      only = argv[a + 1];
    else {
      std::fprintf(stderr, "unknown option %s\n", argv[a]);
      return 1;
    }
  }
  std::printf("%-5s %5s %5s %5s %10s %8s %10s %8s %5s %5s %8s\n", "pdb", "grid", "probe", "clamp", "area", "vs_msms",
              "volume", "vs_msms", "comp", "genus", "cpu_s");
  for (const auto& reference : kReferences) {
    if (!only.empty() && only.find(reference.name) == std::string::npos) continue;
    const auto path = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb" / reference.file;
    if (!std::filesystem::exists(path)) {
      std::fprintf(stderr, "%s not found (needs ../shared/data)\n", path.c_str());
      return 1;
    }
    const auto molecule = spheremap::read_structure(path);
    for (double probe : probes)
      for (double grid : grids)
        for (double clamp : clamps) {
          spheremap::SurfaceOptions options;
          options.grid = grid;
          options.probe = probe;
          options.contour_minimum_fraction = clamp;
          options.threads = threads;
          const double start = cpu_seconds();
          const auto mesh = spheremap::solvent_excluded_surface(molecule.atoms, options);
          const double cpu = cpu_seconds() - start;
          const auto components = spheremap::mesh_components(mesh);  // the outer surface first (largest area)
          const auto& outer = components.front();
          const double msms = probe == 1.4 ? reference.area14 : probe == 1.8 ? reference.area18 : 0;
          const double msms_volume = probe == 1.4 ? reference.volume14 : 0;
          char area_pct[16] = "-", volume_pct[16] = "-";
          if (msms > 0) std::snprintf(area_pct, sizeof area_pct, "%+.2f%%", 100 * (outer.area / msms - 1));
          if (msms_volume > 0)
            std::snprintf(volume_pct, sizeof volume_pct, "%+.2f%%", 100 * (outer.signed_volume / msms_volume - 1));
          std::printf("%-5s %5.3g %5.2g %5.2g %10.1f %8s %10.1f %8s %5zu %5d %8.3f\n", reference.name, grid, probe,
                      clamp, outer.area, area_pct, outer.signed_volume, volume_pct, components.size(), outer.genus,
                      cpu);
          std::fflush(stdout);
        }
  }
  return 0;
}
