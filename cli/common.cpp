#include <sstream>

#include <fmt/format.h>

#include "commands.hpp"
#include "spheremap/error.hpp"

namespace spheremap::cli {

void StructureCliOptions::add(CLI::App* cmd, MapJobOptions& options) {
  command = cmd;
  cmd->add_option("--probe", options.surface.probe, "Probe radius in Å (default 1.4)")->check(CLI::PositiveNumber);
  cmd->add_option("--grid", options.surface.grid, "Grid spacing of the molecular surface in Å (default 0.5)")
      ->check(CLI::Range(0.05, 5.0));
  cmd->add_option("--model", options.structure.model, "Model to read: 1 = the first (default), N = the N-th")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--chains", chains, "Chains to keep, comma-separated (default: all)");
  cmd->add_flag("--keep-hydrogens", options.structure.keep_hydrogens, "Keep hydrogen atoms (default: removed)");
  cmd->add_flag("--keep-waters", options.structure.keep_waters, "Keep waters (default: removed)");
  cmd->add_flag("--no-hetero", no_hetero, "Remove ligands, ions and other HETATM groups (default: kept)");
  cmd->add_option("--radii", radii_file, "Radius table: 'ELEMENT RADIUS' per line (default: Bondi 1964)");
  cmd->add_option("--preset", preset,
                  fmt::format("'paper': the paper's settings for reproduction (probe {} Å, Bondi radii, grid {} Å, the "
                              "binary grid contoured at 1/2: vertices at edge midpoints); --probe and --grid given "
                              "explicitly still win",
                              kPaperProbe, kPaperGrid))
      ->check(CLI::IsMember({"paper"}));
  cmd->add_flag("--cavities", cavities,
                "Carve internal cavities that hold a probe, as separate reported components (default: filled, as MSMS's "
                "outer surface; with it, pockets within a probe diameter of the outside open into the outer surface)");
  cmd->add_flag("--keep-topology", options.keep_topology,
                "Do not repair handles of the molecular surface (map: refuse a surface of genus > 0, the paper's filter)");
}

void StructureCliOptions::apply(MapJobOptions& options) const {
  if (!chains.empty()) {
    std::stringstream list(chains);
    for (std::string chain; std::getline(list, chain, ',');)
      if (!chain.empty()) options.structure.chains.push_back(chain);
  }
  options.structure.keep_hetero = !no_hetero;
  if (cavities) options.surface.carve_cavities = true;
  if (!radii_file.empty()) options.structure.radii = load_radius_table(radii_file);
  if (preset == "paper") {
    if (command->count("--probe") == 0) options.surface.probe = kPaperProbe;
    if (command->count("--grid") == 0) options.surface.grid = kPaperGrid;
    options.surface.contour_minimum_fraction = kPaperContourFraction;
  }
}

Weights parse_weights(const std::string& name) {
  if (name == "uniform") return Weights::kUniform;
  if (name == "cotan") return Weights::kCotangent;
  if (name == "mean-value") return Weights::kMeanValue;
  throw InputError(fmt::format("weights '{}': expected uniform, cotan or mean-value", name));
}

}  // namespace spheremap::cli
