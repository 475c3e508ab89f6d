#include "spheremap/properties/apbs.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fstream>
#include <stdexcept>

#include <fmt/format.h>

#include "../util/subprocess.hpp"
#include "spheremap/error.hpp"
#include "spheremap/properties/potential_map.hpp"

namespace spheremap {
namespace {

// psize.py's constants: coarse = cfac * extent, fine = extent + fadd, 200 bytes of APBS memory a grid point.
constexpr double kCoarseFactor = 1.7;
constexpr double kFineMargin = 20;
constexpr double kBytesPerPoint = 200;

int grid_points(double length, double spacing) {
  const int blocks = static_cast<int>(length / spacing / 32 + 0.5);
  return std::max(33, 32 * blocks + 1);
}

}  // namespace

bool apbs_available() { return detail::find_executable(kApbsProgram).has_value(); }

ApbsGrid apbs_grid(const std::vector<Atom>& atoms, const std::vector<Vec3>& points, const ApbsOptions& options) {
  if (atoms.empty() || !(options.grid_spacing > 0)) throw std::invalid_argument("apbs_grid: atoms and a spacing > 0");
  Vec3 lo = atoms[0].position, hi = lo;
  const auto include = [&](const Vec3& p, double radius) {
    for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d] - radius), hi[d] = std::max(hi[d], p[d] + radius);
  };
  for (const Atom& a : atoms) include(a.position, a.radius);
  for (const Vec3& p : points) include(p, 0);
  ApbsGrid grid;
  for (int d = 0; d < 3; ++d) {
    const double extent = hi[d] - lo[d];
    grid.centre[d] = 0.5 * (lo[d] + hi[d]);
    grid.fine_length[d] = extent + kFineMargin;
    grid.coarse_length[d] = std::max(kCoarseFactor * extent, grid.fine_length[d]);
  }
  for (grid.spacing = options.grid_spacing;; grid.spacing *= 1.1) {
    double total = kBytesPerPoint;
    for (int d = 0; d < 3; ++d) total *= grid.points[d] = grid_points(grid.fine_length[d], grid.spacing);
    if (total <= options.memory_limit_megabytes * 1e6 || grid.points == std::array<int, 3>{33, 33, 33}) break;
  }
  return grid;
}

std::string apbs_input(const std::string& pqr_file, const ApbsGrid& grid, const ApbsOptions& options,
                       const std::string& output_stem) {
  const auto triple = [](const auto& v) { return fmt::format("{:.4f} {:.4f} {:.4f}", v[0], v[1], v[2]); };
  return fmt::format(
      "read\n    mol pqr {}\nend\nelec\n    mg-auto\n    dime {} {} {}\n    cglen {}\n    fglen {}\n"
      "    cgcent {}\n    fgcent {}\n    mol 1\n    lpbe\n    bcfl sdh\n    pdie {:.4f}\n    sdie {:.4f}\n"
      "    srfm smol\n    chgm spl2\n    sdens 10.00\n    srad 1.40\n    swin 0.30\n    temp {:.4f}\n"
      "    calcenergy no\n    calcforce no\n    write pot dx {}\nend\nquit\n",
      pqr_file, grid.points[0], grid.points[1], grid.points[2], triple(grid.coarse_length), triple(grid.fine_length),
      triple(grid.centre), triple(grid.centre), options.solute_dielectric, options.solvent_dielectric,
      options.temperature, output_stem);
}

ApbsResult run_apbs(const std::vector<Atom>& atoms, const std::vector<Vec3>& points, const ApbsOptions& options,
                    const std::string& name, const ProgressCallback& progress) {
  const auto apbs = detail::find_executable(kApbsProgram);
  if (!apbs)
    throw InputError(
        fmt::format("{}: --apbs needs APBS, which is not installed (apbs is on no folder of PATH); install "
                    "Debian's packages apbs and pdb2pqr (apt-get install apbs pdb2pqr)",
                    name));
  ApbsResult result;
  const Pdb2pqrInput input = pdb2pqr_input(atoms, name);
  const detail::TemporaryFolder folder("spheremap-apbs");
  const auto start = std::chrono::steady_clock::now();
  const std::vector<Atom> charged = run_pdb2pqr(input, options.force_field, folder.path(), name, progress);
  result.pdb2pqr_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.charges = match_pqr_charges(atoms, charged, fmt::format("pdb2pqr ({})", to_string(options.force_field)));
  result.grid = apbs_grid(charged, points, options);
  if (result.grid.spacing > options.grid_spacing)
    result.warnings.push_back(fmt::format("APBS grid spacing {:.2f} Å instead of {:.2f} Å, to stay within {:.0f} MB",
                                          result.grid.spacing, options.grid_spacing, options.memory_limit_megabytes));
  {
    std::ofstream in(folder.path() / "apbs.in");
    in << apbs_input("structure.pqr", result.grid, options, "potential");
    if (!in) throw InputError(fmt::format("{}: cannot write APBS's input in {}", name, folder.path().string()));
  }
  const auto& g = result.grid;
  if (progress)
    progress(
        fmt::format("apbs: solving the Poisson-Boltzmann equation on {} x {} x {} points ({:.0f} x {:.0f} x {:.0f} "
                    "Å)",
                    g.points[0], g.points[1], g.points[2], g.fine_length[0], g.fine_length[1], g.fine_length[2]));
  const auto run =
      detail::run_program({apbs->string(), "apbs.in"}, folder.path(), folder.path() / "apbs.log", [&](double seconds) {
        if (progress) progress(fmt::format("apbs: running for {:.0f} s", seconds));
      });
  result.apbs_seconds = run.seconds;
  // Debian's APBS is built with MPI and names the map after the process: potential-PE0.dx.
  std::filesystem::path map;
  for (const char* file : {"potential.dx", "potential-PE0.dx"})
    if (std::filesystem::exists(folder.path() / file)) map = folder.path() / file;
  if (run.exit_code != 0 || map.empty())
    throw InputError(
        fmt::format("{}: apbs failed (exit status {}{}); its last lines:\n{}Check the structure, or run "
                    "APBS yourself and give its map with --potential-map",
                    name, run.exit_code, map.empty() ? ", no potential map written" : "", run.log_tail));
  if (progress) progress(fmt::format("apbs: done in {:.1f} s", run.seconds));
  result.potential = interpolate_dx(read_dx(map), points, fmt::format("{}: APBS's map", name));
  return result;
}

}  // namespace spheremap
