// The electrostatic potential on a molecular surface, in kT/e, three ways: built-in Coulomb, an APBS map
// given by the user, or APBS run for the user.
#pragma once

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/properties/apbs.hpp"
#include "spheremap/properties/charges.hpp"
#include "spheremap/properties/coulomb.hpp"
#include "spheremap/properties/pdb2pqr.hpp"

namespace spheremap {

enum class ElectrostaticsMethod {
  kCoulomb,       // (a) the built-in Coulomb sum over the charges (`charges`)
  kPotentialMap,  // (b) --potential-map FILE.dx, interpolated
  kApbs,          // (c) --apbs: pdb2pqr then APBS, run in a temporary folder
};

/// --charges: where the Coulomb sum's charges come from.
enum class ChargeChoice {
  kAuto,     // a PQR input's own charges; else pdb2pqr when installed (formal if it fails, with a warning); else formal
  kPdb2pqr,  // pdb2pqr, or an error naming the package when it is not installed
  kFormal,   // the built-in table (formal_charges)
  kFile,     // the PQR file `charges_file`, matched by chain, residue and atom name
  kInputOrFormal,  // a PQR input's own charges, else the formal table: no external program (the map's default)
};

struct ElectrostaticsOptions {
  ElectrostaticsMethod method = ElectrostaticsMethod::kCoulomb;
  ChargeChoice charges = ChargeChoice::kAuto;
  std::filesystem::path charges_file;   // for ChargeChoice::kFile
  std::filesystem::path potential_map;  // for kPotentialMap
  ForceField force_field = ForceField::kAmber;
  /// K; applies to the Coulomb sum and to APBS (the unit kT/e depends on it). A map's values are taken as
  /// they are (APBS writes kT/e at the temperature of its own run).
  double temperature = kDefaultTemperature;
  /// Å: the potential is taken at each vertex moved this far out along its area-weighted outward normal
  /// (ChimeraX's `coulombic` offset), off the surface where the Coulomb sum is steep.
  double offset = 1.4;
  CoulombOptions coulomb;  // dielectric, summation, threads (its temperature is replaced by `temperature`)
  ApbsOptions apbs;        // grid and dielectrics (force field and temperature replaced by the above)
};

struct ElectrostaticsResult {
  std::vector<double> potential;  // kT/e at every vertex of the surface
  std::string
      source;  // e.g. "Coulomb, epsilon = 4r, charges: pdb2pqr (AMBER)", "APBS map FILE", "APBS (pdb2pqr AMBER)"
  std::optional<ChargeAssignment> charges;  // what the potential summed (Coulomb and APBS)
  std::vector<std::string> warnings;
};

/// The charges for the Coulomb sum as options.charges says. `structure_file` is the input (a .pqr gives its
/// own charges under kAuto), `atoms` what was read from it. Throws InputError as read_pqr_charges and
/// pdb2pqr_charges do (kPdb2pqr without pdb2pqr installed: the package to install).
ChargeAssignment assign_charges(const std::vector<Atom>& atoms, const std::filesystem::path& structure_file,
                                const ElectrostaticsOptions& options, const ProgressCallback& progress = nullptr);

/// The potential at every vertex of `surface` (triangles counter-clockwise seen from outside), at the
/// vertex moved options.offset Å out along its normal. Throws InputError as assign_charges, read_dx,
/// interpolate_dx and run_apbs do; std::invalid_argument for out-of-range options (coulomb_potential).
ElectrostaticsResult surface_electrostatics(const Mesh& surface, const std::vector<Atom>& atoms,
                                            const std::filesystem::path& structure_file,
                                            const ElectrostaticsOptions& options,
                                            const ProgressCallback& progress = nullptr);

}  // namespace spheremap
