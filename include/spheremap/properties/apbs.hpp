// Debian's APBS (package `apbs`), run for the user after pdb2pqr: the Poisson-Boltzmann potential at points.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include "spheremap/molecule/structure.hpp"
#include "spheremap/properties/charges.hpp"
#include "spheremap/properties/pdb2pqr.hpp"

namespace spheremap {

inline constexpr const char* kApbsProgram = "apbs";

/// True when apbs is on PATH.
bool apbs_available();

/// The APBS calculation: a linearized Poisson-Boltzmann equation (lpbe), no mobile ions, the molecular
/// surface as the dielectric boundary (srfm smol, srad 1.4), single Debye-Hückel boundary conditions
/// (bcfl sdh), charges by cubic B-splines (chgm spl2): pdb2pqr's template, with the grid sized below.
struct ApbsOptions {
  ForceField force_field = ForceField::kAmber;
  double temperature = 298.15;           // K
  double solute_dielectric = 2.0;        // pdie
  double solvent_dielectric = 78.54;     // sdie
  double grid_spacing = 0.5;             // Å, the fine grid's target spacing (psize's default)
  double memory_limit_megabytes = 2000;  // the spacing grows until APBS's estimated memory fits
};

/// An mg-auto grid. As APBS's psize.py: fine length = extent + 20 Å, coarse length = 1.7 extent, points
/// per side 32k + 1 (at least 33) for about `grid_spacing`; unlike psize, the extent covers the atoms (with
/// their radii) and the points where the potential is wanted, the coarse grid is never smaller than the
/// fine one (psize shrinks the fine one), and a grid over the memory limit (200 bytes a point, psize's
/// figure) gets a coarser spacing instead of psize's parallel split (which fails under Python 3.11).
struct ApbsGrid {
  std::array<int, 3> points{};
  Vec3 coarse_length{}, fine_length{}, centre{};
  double spacing = 0;  // the target spacing used (>= options.grid_spacing)
};

/// Preconditions: at least one atom; options.grid_spacing > 0. Throws std::invalid_argument otherwise.
ApbsGrid apbs_grid(const std::vector<Atom>& atoms, const std::vector<Vec3>& points, const ApbsOptions& options);

/// The APBS input file for `pqr_file` (a name in APBS's folder), writing the potential as OpenDX to
/// `output_stem` (APBS adds ".dx", or "-PE0.dx" when built with MPI as Debian's is).
std::string apbs_input(const std::string& pqr_file, const ApbsGrid& grid, const ApbsOptions& options,
                       const std::string& output_stem);

struct ApbsResult {
  std::vector<double> potential;  // kT/e at each point (trilinear in APBS's fine grid)
  ChargeAssignment charges;       // pdb2pqr's, matched to the structure
  ApbsGrid grid;
  double pdb2pqr_seconds = 0, apbs_seconds = 0;
  std::vector<std::string> warnings;
};

/// Runs pdb2pqr (run_pdb2pqr) then `apbs` in a temporary folder removed afterwards, reads the potential map
/// and interpolates it at `points`. `progress` hears what runs, and every 5 s that APBS still runs.
/// Throws InputError naming the Debian packages `apbs` / `pdb2pqr` when a program is missing (exit 1), with
/// the program's last lines when it fails, and as read_dx / interpolate_dx on its map.
ApbsResult run_apbs(const std::vector<Atom>& atoms, const std::vector<Vec3>& points, const ApbsOptions& options,
                    const std::string& name, const ProgressCallback& progress = nullptr);

}  // namespace spheremap
