#include <sstream>

#include <fmt/format.h>

#include "commands.hpp"
#include "spheremap/error.hpp"

namespace spheremap::cli {

void StructureCliOptions::add(CLI::App* cmd, MapJobOptions& options, bool for_map) {
  command = cmd;
  if (for_map) {
    cmd->add_option("--mesh-edge", mesh_edge,
                    "Simplify the surface before mapping to well-shaped triangles with edges of about this length, keeping a "
                    "subset of its vertices (structures: default 1 Å; 0 maps the contour as it is; mesh files: only when "
                    "given, in the mesh's units)")
        ->check(CLI::NonNegativeNumber);
  } else {
    options.simplify.target_edge_length = 0;
    cmd->add_option("--mesh-edge", mesh_edge,
                    "Write the surface simplified to well-shaped triangles with edges of about this length in Å, a subset "
                    "of the contour's vertices (default: the contour as it is; spheremap map uses 1 Å)")
        ->check(CLI::NonNegativeNumber);
  }
  cmd->add_option("--mesh-tolerance", mesh_tolerance,
                  "With simplification: each removed vertex stays within this distance of the triangles that replace it "
                  "(default: a tenth of --mesh-edge)")
      ->check(CLI::PositiveNumber);
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
                              "binary grid contoured at 1/2: vertices at edge midpoints). 'fast': a quick look (grid {} Å{}; "
                              "areas about 1-1.5% below MSMS's). Options given explicitly still win",
                              kPaperProbe, kPaperGrid, kFastGrid,
                              for_map ? fmt::format(", mesh edges {} Å, at most {} equalizing rounds", kFastMeshEdge, kFastEqualizingRounds) : ""))
      ->check(CLI::IsMember({"paper", "fast"}));
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
    options.simplify.target_edge_length = 0;  // the paper maps its contour as it is
  }
  if (preset == "fast") {
    if (command->count("--grid") == 0) options.surface.grid = kFastGrid;
    // The surface command has neither option: it writes the contour as it is unless --mesh-edge is given.
    const CLI::Option* equalizing = command->get_option_no_throw("--equalizing-rounds");
    if (equalizing != nullptr) {
      if (equalizing->count() == 0) options.map.max_equalizing_rounds = kFastEqualizingRounds;
      if (mesh_edge < 0) options.simplify.target_edge_length = kFastMeshEdge;
    }
  }
  if (mesh_edge >= 0) {
    options.simplify.target_edge_length = mesh_edge;
    options.simplify_mesh_files = mesh_edge > 0;
  }
  options.simplify.max_error = mesh_tolerance > 0 ? mesh_tolerance : options.simplify.target_edge_length / 10;
}

void add_equalizing_rounds_option(CLI::App* command, MapOptions& options) {
  command->add_option("--equalizing-rounds", options.max_equalizing_rounds,
                      "After re-weighting has certified a map: at most this many rounds that spread limbs and pockets more "
                      "evenly, each kept only if the map stays certified and its area distortion drops (default 12; 0: "
                      "faster, the first certified map)")
      ->check(CLI::NonNegativeNumber);
}

Weights parse_weights(const std::string& name) {
  if (name == "uniform") return Weights::kUniform;
  if (name == "cotan") return Weights::kCotangent;
  if (name == "mean-value") return Weights::kMeanValue;
  throw InputError(fmt::format("weights '{}': expected uniform, cotan or mean-value", name));
}

}  // namespace spheremap::cli
