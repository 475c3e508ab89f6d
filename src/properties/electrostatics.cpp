#include "spheremap/properties/electrostatics.hpp"

#include <algorithm>
#include <cctype>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/geometry/normals.hpp"
#include "spheremap/properties/potential_map.hpp"

namespace spheremap {
namespace {

bool is_pqr(const std::filesystem::path& path) {
  std::filesystem::path p = path;
  std::string extension = p.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return std::tolower(c); });
  if (extension == ".gz") {
    extension = p.stem().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(),
                   [](unsigned char c) { return std::tolower(c); });
  }
  return extension == ".pqr";
}

std::string dielectric_text(const CoulombOptions& options) {
  return options.dielectric == Dielectric::kDistanceDependent ? fmt::format("epsilon = {}r", options.dielectric_value)
                                                              : fmt::format("epsilon = {}", options.dielectric_value);
}

}  // namespace

ChargeAssignment assign_charges(const std::vector<Atom>& atoms, const std::filesystem::path& structure_file,
                                const ElectrostaticsOptions& options, const ProgressCallback& progress) {
  const std::string name = structure_file.string();
  switch (options.charges) {
    case ChargeChoice::kFormal: return formal_charges(atoms);
    case ChargeChoice::kFile: {
      ChargeAssignment charges = read_pqr_charges(atoms, options.charges_file);
      fill_unmatched_with_formal(charges, atoms);
      return charges;
    }
    case ChargeChoice::kPdb2pqr: return pdb2pqr_charges(atoms, options.force_field, name, progress);
    case ChargeChoice::kInputOrFormal:
      return is_pqr(structure_file) ? read_pqr_charges(atoms, structure_file) : formal_charges(atoms);
    case ChargeChoice::kAuto: break;
  }
  if (is_pqr(structure_file)) return read_pqr_charges(atoms, structure_file);
  if (!pdb2pqr_available()) {
    ChargeAssignment formal = formal_charges(atoms);
    formal.warnings.push_back("formal charges: pdb2pqr30 is not installed (Debian package pdb2pqr)");
    return formal;
  }
  try {
    return pdb2pqr_charges(atoms, options.force_field, name, progress);
  } catch (const InputError& error) {
    ChargeAssignment formal = formal_charges(atoms);
    formal.warnings.push_back(fmt::format("formal charges, because pdb2pqr failed: {}", error.what()));
    return formal;
  }
}

ElectrostaticsResult surface_electrostatics(const Mesh& surface, const std::vector<Atom>& atoms,
                                            const std::filesystem::path& structure_file,
                                            const ElectrostaticsOptions& options, const ProgressCallback& progress) {
  const std::vector<Vec3> points =
      offset_along_normals(surface.positions, vertex_normals(surface.positions, surface.triangles), options.offset);
  ElectrostaticsResult result;
  switch (options.method) {
    case ElectrostaticsMethod::kPotentialMap:
      result.potential = interpolate_dx(read_dx(options.potential_map), points, options.potential_map.string());
      result.source = fmt::format("APBS map {}", options.potential_map.filename().string());
      return result;
    case ElectrostaticsMethod::kApbs: {
      ApbsOptions apbs = options.apbs;
      apbs.force_field = options.force_field;
      apbs.temperature = options.temperature;
      ApbsResult run = run_apbs(atoms, points, apbs, structure_file.string(), progress);
      result.potential = std::move(run.potential);
      result.source = fmt::format("APBS (pdb2pqr {}, lpbe, pdie {}, sdie {}, {} x {} x {} grid)",
                                  to_string(apbs.force_field), apbs.solute_dielectric, apbs.solvent_dielectric,
                                  run.grid.points[0], run.grid.points[1], run.grid.points[2]);
      result.warnings = run.warnings;
      result.charges = std::move(run.charges);
      return result;
    }
    case ElectrostaticsMethod::kCoulomb: break;
  }
  ChargeAssignment charges = assign_charges(atoms, structure_file, options, progress);
  CoulombOptions coulomb = options.coulomb;
  coulomb.temperature = options.temperature;
  result.potential = coulomb_potential(charges.points, points, coulomb);
  result.source = fmt::format("Coulomb, {}, charges: {}", dielectric_text(coulomb), charges.source);
  result.warnings = charges.warnings;
  result.charges = std::move(charges);
  return result;
}

}  // namespace spheremap
