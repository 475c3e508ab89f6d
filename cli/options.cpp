// The options shared by map, batch and surface, each registered once.
#include "options.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <limits>
#include <sstream>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/molecule/structure.hpp"

namespace spheremap::cli {
namespace {

constexpr double kUnbounded = std::numeric_limits<double>::infinity();

void add_mesh_edge_option(CLI::App* cmd, double& mesh_edge, PresetScope scope) {
  const char* text =
      scope == PresetScope::kMap
          ? "Simplify the surface before mapping to well-shaped triangles with edges of about this length, keeping a "
            "subset of its vertices (structures: default 1 Å; 0 maps the contour as it is; mesh files: only when "
            "given, in the mesh's units)"
          : "Write the surface simplified to well-shaped triangles with edges of about this length in Å, a subset "
            "of the contour's vertices (default: the contour as it is; spheremap map uses 1 Å)";
  cmd->add_option("--mesh-edge", mesh_edge, text)->check(finite_number(0, kUnbounded));
}

std::string preset_help(PresetScope scope) {
  return fmt::format(
      "'paper': the paper's settings for reproduction (probe {} Å, Bondi radii, grid {} Å, the binary grid contoured "
      "at 1/2: vertices at edge midpoints). 'fast': a quick look (grid {} Å{}; areas about 1-1.5% below MSMS's). "
      "Options given explicitly still win",
      kPaperProbe, kPaperGrid, kFastGrid,
      scope == PresetScope::kMap
          ? fmt::format(", mesh edges {} Å, at most {} equalizing rounds", kFastMeshEdge, kFastEqualizingRounds)
          : "");
}

void add_equalizing_rounds_option(CLI::App* command, MapOptions& options) {
  command
      ->add_option("--equalizing-rounds", options.max_equalizing_rounds,
                   "After re-weighting has certified a map: at most this many rounds that spread limbs and pockets "
                   "more evenly, each kept only if the map stays certified and its area distortion drops (default "
                   "12; 0: faster, the first certified map)")
      ->check(CLI::Range(0, 1000));
}

}  // namespace

CLI::Validator finite_number(double low, double high, LowEnd low_end, const std::string& unit) {
  const bool open_low = low_end == LowEnd::kExcluded;
  std::string expected = high == kUnbounded
                             ? fmt::format("a number {} {}{}", open_low ? "above" : "of at least", low, unit)
                             : fmt::format("a number from {}{} to {}{}{}", low, unit, high, unit,
                                           open_low ? fmt::format(" (not {})", low) : "");
  auto check = [=](std::string& text) -> std::string {
    double value = 0;
    std::string_view number = text;
    if (number.size() > 1 && number.front() == '+') number.remove_prefix(1);
    const auto [end, error] = std::from_chars(number.data(), number.data() + number.size(), value);
    if (error != std::errc() || end != number.data() + number.size() || number.empty())
      return fmt::format("'{}' is not a number; expected {}", text, expected);
    if (!std::isfinite(value)) return fmt::format("{} is not a finite number; expected {}", text, expected);
    if (value < low || (open_low && value == low) || value > high)
      return fmt::format("{} is out of range; expected {}", text, expected);
    return {};
  };
  return CLI::Validator(check, expected);
}

void StructureCliOptions::add(CLI::App* cmd, MapJobOptions& options, PresetScope scope) {
  command = cmd;
  scope_ = scope;
  if (scope == PresetScope::kSurface) options.simplify.target_edge_length = 0;
  add_mesh_edge_option(cmd, mesh_edge, scope);
  cmd->add_option("--mesh-tolerance", mesh_tolerance,
                  "With simplification: each removed vertex stays within this distance of the triangles that replace "
                  "it (default: a tenth of --mesh-edge)")
      ->check(finite_number(0, kUnbounded, LowEnd::kExcluded));
  cmd->add_option("--probe", options.surface.probe, "Probe radius in Å (default 1.4; up to 100)")
      ->check(finite_number(0, 100, LowEnd::kExcluded, " Å"));
  cmd->add_option("--grid", options.surface.grid, "Grid spacing of the molecular surface in Å (default 0.5)")
      ->check(finite_number(0.05, 5.0, LowEnd::kIncluded, " Å"));
  cmd->add_option("--model", options.structure.model, "Model to read: 1 = the first (default), N = the N-th")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--chains", chains, "Chains to keep, comma-separated (default: all)");
  cmd->add_flag("--keep-hydrogens", keep_hydrogens,
                "Keep hydrogen atoms (default: removed from PDB and mmCIF files, kept from PQR files)");
  cmd->add_flag("--no-hydrogens", no_hydrogens,
                "Remove hydrogen atoms, also from PQR files (whose hydrogens otherwise count for charge; those of "
                "radius 0 make no surface)")
      ->excludes("--keep-hydrogens");
  cmd->add_flag("--keep-waters", options.structure.keep_waters, "Keep waters (default: removed)");
  cmd->add_flag("--no-hetero", no_hetero, "Remove ligands, ions and other HETATM groups (default: kept)");
  cmd->add_option("--radii", radii_file, "Radius table: 'ELEMENT RADIUS' per line (default: Bondi 1964)");
  cmd->add_flag("--strict", strict,
                "Refuse a structure file with any warning (a truncated last line, unknown elements, ignored "
                "columns): exit 1 instead of a map with warnings");
  cmd->add_option("--preset", preset, preset_help(scope))->check(CLI::IsMember({"paper", "fast"}));
  cmd->add_flag("--cavities", cavities,
                "Carve internal cavities that hold a probe, as separate reported components (default: filled, as "
                "MSMS's outer surface; with it, pockets within a probe diameter of the outside open into the outer "
                "surface)");
  cmd->add_flag("--keep-topology", options.keep_topology,
                "Do not repair handles of the molecular surface (map: refuse a surface of genus > 0, the paper's "
                "filter)");
}

void StructureCliOptions::apply(MapJobOptions& options) const {
  if (!chains.empty()) {
    std::stringstream list(chains);
    for (std::string chain; std::getline(list, chain, ',');)
      if (!chain.empty()) options.structure.chains.push_back(chain);
  }
  options.structure.keep_hetero = !no_hetero;
  if (keep_hydrogens || no_hydrogens) options.structure.keep_hydrogens = keep_hydrogens;
  options.structure.strict = strict;
  if (cavities) options.surface.carve_cavities = true;
  if (!radii_file.empty()) options.structure.radii = load_radius_table(radii_file);
  ExplicitOptions given;
  given.probe = command->count("--probe") != 0;
  given.grid = command->count("--grid") != 0;
  given.mesh_edge = mesh_edge >= 0;
  const CLI::Option* equalizing = command->get_option_no_throw("--equalizing-rounds");
  given.equalizing_rounds = equalizing != nullptr && equalizing->count() != 0;
  apply_preset(parse_preset(preset), options, given, scope_);
  if (mesh_edge >= 0) {
    options.simplify.target_edge_length = mesh_edge;
    options.simplify_mesh_files = mesh_edge > 0;
  }
  options.simplify.max_error = mesh_tolerance > 0 ? mesh_tolerance : options.simplify.target_edge_length / 10;
}

void MapCliOptions::add(CLI::App* command, WeightingCount count) {
  if (count == WeightingCount::kOne) {
    command
        ->add_option("--weights", weights,
                     "Harmonic weights: uniform (the paper, default), cotan (may fold), mean-value")
        ->check(CLI::IsMember({"uniform", "cotan", "mean-value"}));
  } else {
    command->add_option("--weights", weights,
                        "Harmonic weights, comma-separated: uniform (default), cotan, mean-value; with several, one "
                        "subfolder per weighting (each input is read and surfaced once)");
  }
  command->add_option("--solver", solver, "direct (CHOLMOD/UMFPACK, default) or gauss-seidel (the paper's relaxation)")
      ->check(CLI::IsMember({"direct", "gauss-seidel"}));
  command->add_option("--component", component,
                      "Which connected component to map: 'largest' or a number (meshes: file order, default refuse; "
                      "structures: by decreasing area, default 0 = the outer surface)");
  command
      ->add_option("--weld-tolerance", job.prepare.weld_tolerance,
                   "Weld vertices closer than this (default 0: exactly coincident only)")
      ->check(finite_number(0, kUnbounded));
  command
      ->add_option("--collapse-floor", job.map.collapse_floor,
                   "Normalized area ratio below which a triangle counts as collapsed (default 1e-6; below 1)")
      ->check(finite_number(0, 1, LowEnd::kExcluded));
  command->add_flag("--ascii", job.ascii, "Write ASCII PLY with full precision (%.17g), e.g. for PyMOL");
  add_equalizing_rounds_option(command, job.map);
  command
      ->add_option("--objective", objective,
                   "What the certified map is optimized for on the sphere, never leaving the certified maps: "
                   "paper (the paper's map, default), area (equal area), conformal (angles), balanced (both: "
                   "symmetric Dirichlet); an optimized map that does not certify is dropped for the paper's")
      ->check(CLI::IsMember({"paper", "area", "conformal", "balanced"}));
  command
      ->add_option("--objective-iterations", job.map.objective_max_iterations,
                   "With --objective: at most this many Newton steps on the mesh, all stages together (default 300; "
                   "each coarse level of the area objective's coarse start has the same cap)")
      ->check(CLI::PositiveNumber);
  command->add_flag("--no-repair", no_repair,
                    "The paper's algorithm only: no re-weighting, no untangling (the certificate still runs)");
  structure.add(command, job);
  properties.add(command, job);
}

void MapCliOptions::apply() {
  structure.apply(job);
  properties.apply(job);
  job.map.weights = weightings().front();
  job.map.solver = solver == "gauss-seidel" ? Solver::kGaussSeidel : Solver::kDirect;
  if (!component.empty()) job.prepare.component = parse_component(component);
  job.map.repair = !no_repair;
  job.map.objective = parse_map_objective(objective);
}

std::vector<Weights> MapCliOptions::weightings() const {
  std::vector<Weights> list;
  std::stringstream names(weights);
  for (std::string name; std::getline(names, name, ',');) {
    const Weights w = parse_weights(name);
    if (std::find(list.begin(), list.end(), w) != list.end())
      throw InputError(fmt::format("--weights '{}': {} is listed twice", weights, name));
    list.push_back(w);
  }
  if (list.empty()) throw InputError("--weights: expected uniform, cotan or mean-value (comma-separated)");
  return list;
}

Weights parse_weights(const std::string& name) {
  if (name == "uniform") return Weights::kUniform;
  if (name == "cotan") return Weights::kCotangent;
  if (name == "mean-value") return Weights::kMeanValue;
  throw InputError(fmt::format("weights '{}': expected uniform, cotan or mean-value", name));
}

ComponentChoice parse_component(const std::string& text) {
  if (text == "largest") return ComponentChoice::largest();
  try {
    std::size_t used = 0;
    const int k = std::stoi(text, &used);
    if (used == text.size() && k >= 0) return ComponentChoice::numbered(k);
  } catch (const std::exception&) {
  }
  throw InputError(fmt::format("--component '{}': expected 'largest' or a component number (0, 1, ...)", text));
}

void add_output_option(CLI::App* command, std::string& output, const std::string& description) {
  command->add_option("-o,--output", output, description)->required();
}

void add_quiet_flag(CLI::App* command, bool& quiet, const std::string& description) {
  command->add_flag("-q,--quiet", quiet, description);
}

}  // namespace spheremap::cli

namespace spheremap::cli {

void PropertyCliOptions::add(CLI::App* command, MapJobOptions& job) {
  auto& e = job.properties.electrostatics;
  command->add_option("--properties", properties,
                      "Surface properties to compute, comma-separated (default: all that apply; 'none': none); "
                      "see docs/properties.md");
  command->add_option("--color", job.colour,
                      "Property the PLY files' vertex colours show (default: electrostatics, else hydrophobicity, "
                      "else octant)");
  command
      ->add_option("--values", values,
                   "CSV/TSV of per-residue or per-atom values (columns chain, residue_number, optional "
                   "insertion_code and atom_name, then value columns: one property each); repeatable")
      ->check(CLI::ExistingFile);
  command->add_option("--charges", charges,
                      "Charges of the Coulomb potential: formal (built-in table), pdb2pqr, or a PQR file (default: a "
                      "PQR input's own, else formal)");
  command->add_option("--potential-map", potential_map, "Electrostatics from an APBS OpenDX map (.dx), kT/e")
      ->check(CLI::ExistingFile);
  command->add_flag("--apbs", apbs, "Electrostatics by APBS (Poisson-Boltzmann; runs pdb2pqr and apbs)");
  command->add_option("--temperature", e.temperature, "Temperature in K of kT/e (default 298.15)")
      ->check(finite_number(0, 1e5, LowEnd::kExcluded, " K"));
  command->add_option("--dielectric", dielectric,
                      "Coulomb dielectric: '4r' (distance-dependent, default) or a constant such as 80");
  command
      ->add_option("--potential-offset", e.offset,
                   "Å: the potential is taken this far out along each vertex normal (default 1.4)")
      ->check(finite_number(0, 100, LowEnd::kIncluded, " Å"));
  command->add_option("--force-field", force_field, "pdb2pqr's force field: amber (default) or parse")
      ->check(CLI::IsMember({"amber", "parse"}));
}

void PropertyCliOptions::apply(MapJobOptions& job) const {
  auto& options = job.properties;
  auto& e = options.electrostatics;
  if (!properties.empty()) {
    std::vector<std::string> names;
    std::stringstream list(properties);
    for (std::string name; std::getline(list, name, ',');)
      if (!name.empty() && name != "none") names.push_back(name);
    options.only = names;
  }
  for (const auto& file : values) options.values_files.emplace_back(file);
  if (apbs && !potential_map.empty()) throw InputError("--apbs and --potential-map: give one source of the potential");
  if (apbs) e.method = ElectrostaticsMethod::kApbs;
  if (!potential_map.empty()) {
    e.method = ElectrostaticsMethod::kPotentialMap;
    e.potential_map = potential_map;
  }
  if (!charges.empty() && e.method != ElectrostaticsMethod::kCoulomb)
    throw InputError("--charges is for the built-in Coulomb potential, not with --apbs or --potential-map");
  if (charges == "formal") {
    e.charges = ChargeChoice::kFormal;
  } else if (charges == "pdb2pqr") {
    e.charges = ChargeChoice::kPdb2pqr;
  } else if (charges == "auto") {
    e.charges = ChargeChoice::kAuto;
  } else if (!charges.empty()) {
    if (!std::filesystem::is_regular_file(charges))
      throw InputError(fmt::format("--charges {}: expected formal, pdb2pqr, auto or an existing PQR file", charges));
    e.charges = ChargeChoice::kFile;
    e.charges_file = charges;
  }
  e.force_field = force_field == "parse" ? ForceField::kParse : ForceField::kAmber;
  if (!dielectric.empty()) {
    const bool distance = dielectric.back() == 'r';
    const std::string number = distance ? dielectric.substr(0, dielectric.size() - 1) : dielectric;
    std::size_t used = 0;
    double value = 0;
    try {
      value = std::stod(number, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (used == 0 || used != number.size() || !(value > 0))
      throw InputError(
          fmt::format("--dielectric '{}': expected a positive number, with 'r' for ε = κr (e.g. 4r, 80)", dielectric));
    e.coulomb.dielectric = distance ? Dielectric::kDistanceDependent : Dielectric::kConstant;
    e.coulomb.dielectric_value = value;
  }
  options.progress = [](const std::string& line) { std::cerr << "  " << line << std::endl; };
}

}  // namespace spheremap::cli
