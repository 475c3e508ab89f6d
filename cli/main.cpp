// The spheremap command line: a thin layer over the library (see include/spheremap/pipeline.hpp).
#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>
#include <sstream>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/pipeline.hpp"
#include "spheremap/shapes.hpp"

namespace {

std::pair<std::int32_t, std::int32_t> parse_poles(const std::string& text) {
  const auto comma = text.find(',');
  try {
    if (comma == std::string::npos) throw std::invalid_argument("no comma");
    std::size_t used_a = 0, used_b = 0;
    const int a = std::stoi(text.substr(0, comma), &used_a);
    const int b = std::stoi(text.substr(comma + 1), &used_b);
    if (used_a != comma || used_b != text.size() - comma - 1) throw std::invalid_argument("trailing text");
    return {a, b};
  } catch (const std::exception&) {
    throw spheremap::InputError(fmt::format("--poles '{}': expected two vertex indices like 12,345", text));
  }
}

int parse_component(const std::string& text) {
  if (text == "largest") return spheremap::kComponentLargest;
  try {
    std::size_t used = 0;
    const int k = std::stoi(text, &used);
    if (used == text.size() && k >= 0) return k;
  } catch (const std::exception&) {
  }
  throw spheremap::InputError(fmt::format("--component '{}': expected 'largest' or a component number (0, 1, ...)", text));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "spheremap: maps closed genus-0 surfaces onto the unit sphere, one-to-one and certified\n"
      "(Rahi & Sharp, 'Mapping Complicated Surfaces onto a Sphere', with the cases the paper leaves out).\n"
      "Exit codes: 0 certified map written; 1 bad command line or unreadable input; 2 mesh refused\n"
      "(open, non-manifold, several components, genus != 0; nothing written); 3 map written but NOT certified;\n"
      "4 internal error."};
  app.set_version_flag("--version", "spheremap 0.1.0");
  app.require_subcommand(1);

  auto* map_command = app.add_subcommand(
      "map", "Map a closed genus-0 mesh (OBJ, OFF, PLY, STL), or the molecular surface of a structure (PDB, mmCIF, PQR), onto the unit sphere");
  std::string input, output, weights = "uniform", solver = "direct", poles, component;
  spheremap::MapJobOptions options;
  bool no_repair = false, quiet = false;
  map_command->add_option("input", input,
                          "Mesh file: .obj .off .ply (ASCII/binary) .stl (ASCII/binary); or structure file: .pdb .ent .cif .mmcif (also .gz) .pqr")
      ->required();
  map_command->add_option("-o,--output", output, "Output folder: surface.ply, sphere.ply, report.json")->required();
  map_command->add_option("--weights", weights, "Harmonic weights: uniform (the paper, default), cotan (may fold), mean-value")
      ->check(CLI::IsMember({"uniform", "cotan", "mean-value"}));
  map_command->add_option("--solver", solver, "direct (CHOLMOD/UMFPACK, default) or gauss-seidel (the paper's relaxation)")
      ->check(CLI::IsMember({"direct", "gauss-seidel"}));
  map_command->add_option("--poles", poles, "North and south pole vertices 'i,j': 0-based indices in the input file's vertex order, at least 3 edges apart; default: the two vertices farthest apart");
  map_command->add_option("--component", component, "With several connected components: 'largest' or a component number");
  map_command->add_option("--weld-tolerance", options.prepare.weld_tolerance, "Weld vertices closer than this (default 0: exactly coincident only)")
      ->check(CLI::NonNegativeNumber);
  map_command->add_option("--collapse-floor", options.map.collapse_floor,
                          "Normalized area ratio below which a triangle counts as collapsed (default 1e-6)")
      ->check(CLI::PositiveNumber);
  map_command->add_flag("--ascii", options.ascii, "Write ASCII PLY with full precision (%.17g), e.g. for PyMOL");
  map_command->add_flag("--no-repair", no_repair, "The paper's algorithm only: no re-weighting, no untangling (the certificate still runs)");
  map_command->add_flag("-q,--quiet", quiet, "Print nothing on success");
  std::string chains, radii_file;
  bool no_hetero = false;
  // Structure and surface options, shared by `map` (for structure files) and `surface`.
  auto add_structure_options = [&](CLI::App* command) {
    command->add_option("--probe", options.surface.probe, "Probe radius in Å (default 1.4)")->check(CLI::PositiveNumber);
    command->add_option("--grid", options.surface.grid, "Grid spacing of the molecular surface in Å (default 0.5)")
        ->check(CLI::Range(0.05, 5.0));
    command->add_option("--model", options.structure.model, "Model to read: 1 = the first (default), N = the N-th")
        ->check(CLI::PositiveNumber);
    command->add_option("--chains", chains, "Chains to keep, comma-separated (default: all)");
    command->add_flag("--keep-hydrogens", options.structure.keep_hydrogens, "Keep hydrogen atoms (default: removed)");
    command->add_flag("--keep-waters", options.structure.keep_waters, "Keep waters (default: removed)");
    command->add_flag("--no-hetero", no_hetero, "Remove ligands, ions and other HETATM groups (default: kept)");
    command->add_option("--radii", radii_file, "Radius table: 'ELEMENT RADIUS' per line (default: Bondi 1964)");
    command->add_flag("--keep-topology", options.keep_topology,
                      "Do not repair handles of the molecular surface (map: refuse a surface of genus > 0, the paper's filter)");
  };
  add_structure_options(map_command);

  auto* surface_command = app.add_subcommand("surface", "Write the solvent-excluded surface of a structure (PDB, mmCIF, PQR) as PLY, every component, with atom provenance");
  std::string surface_output;
  surface_command->add_option("input", input, "Structure file: .pdb .ent .cif .mmcif (also .gz) .pqr")->required();
  surface_command->add_option("-o,--output", surface_output, "Output .ply file")->required();
  surface_command->add_flag("--ascii", options.ascii, "ASCII PLY with full precision (%.17g)");
  surface_command->add_flag("-q,--quiet", quiet, "Print nothing on success");
  add_structure_options(surface_command);

  auto* generate_command = app.add_subcommand(
      "generate", "Write a generated closed genus-0 mesh (for trying spheremap, tests and benchmarks) as PLY");
  std::string shape, generated_output;
  int level = 3, cube_n = 10, rings = 60, segments = 32;
  double stretch = 20, separation = 3, neck = 0.3, flips = 0, perturb = 0;
  unsigned seed = 1;
  generate_command->add_option("shape", shape, "icosphere | ellipsoid | dumbbell | cube")
      ->required()
      ->check(CLI::IsMember({"icosphere", "ellipsoid", "dumbbell", "cube"}));
  generate_command->add_option("-o,--output", generated_output, "Output .ply file")->required();
  generate_command->add_option("--level", level, "icosphere/ellipsoid: subdivision level (10*4^level+2 vertices)")->check(CLI::Range(0, 10));
  generate_command->add_option("--stretch", stretch, "ellipsoid: length of the z axis (x and y are 1)")->check(CLI::PositiveNumber);
  generate_command->add_option("--n", cube_n, "cube: squares per face edge (6n^2+2 vertices)")->check(CLI::Range(1, 10000));
  generate_command->add_option("--separation", separation, "dumbbell: distance between the two unit spheres' centres");
  generate_command->add_option("--neck", neck, "dumbbell: radius of the neck (0..1)");
  generate_command->add_option("--rings", rings, "dumbbell: vertex rings along the axis")->check(CLI::PositiveNumber);
  generate_command->add_option("--segments", segments, "dumbbell: vertices per ring")->check(CLI::Range(3, 100000));
  generate_command->add_option("--flips", flips, "probability of random edge flips (creates degree-3 vertices)")->check(CLI::Range(0.0, 1.0));
  generate_command->add_option("--perturb", perturb, "random vertex offsets, in mean edge lengths")->check(CLI::NonNegativeNumber);
  generate_command->add_option("--seed", seed, "random seed for --flips and --perturb");
  generate_command->add_flag("--ascii", options.ascii, "ASCII PLY");
  generate_command->add_flag("-q,--quiet", quiet, "Print nothing on success");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version are "errors" with code 0; every real command-line mistake exits 1.
    const int printed = app.exit(e);
    return printed == 0 ? 0 : static_cast<int>(spheremap::ExitCode::kUsage);
  }

  try {
    if (!chains.empty()) {
      std::stringstream list(chains);
      for (std::string chain; std::getline(list, chain, ',');)
        if (!chain.empty()) options.structure.chains.push_back(chain);
    }
    options.structure.keep_hetero = !no_hetero;
    if (!radii_file.empty()) options.structure.radii = spheremap::load_radius_table(radii_file);
    if (*surface_command) {
      spheremap::StructureReport report;
      const spheremap::Molecule molecule = spheremap::read_structure(input, options.structure);
      report = molecule.report;
      spheremap::TopologyRepair repair;
      const spheremap::Mesh surface = spheremap::repaired_surface(molecule.atoms, options.surface, options.keep_topology, &repair);
      spheremap::write_ply(surface_output, surface, spheremap::PlyWriteOptions{options.ascii});
      if (!quiet) {
        double area = 0;
        for (const auto& t : surface.triangles)
          area += spheremap::triangle_area(surface.positions[t[0]], surface.positions[t[1]], surface.positions[t[2]]);
        std::cout << fmt::format("{}: {} vertices, {} triangles, area {:.1f} Å² (all components; probe {} Å, grid {} Å)\n",
                                 surface_output, surface.vertex_count(), surface.triangle_count(), area,
                                 options.surface.probe, options.surface.grid);
        for (const auto& warning : report.warnings) std::cout << "  warning: " << warning << "\n";
        if (repair.method != "none")
          std::cout << fmt::format("  handle repair: {} ({} grid samples), area before {:.1f} Å²\n", repair.method,
                                   repair.samples_changed, repair.area_before);
      }
    }
    if (*generate_command) {
      spheremap::Mesh mesh = shape == "icosphere"   ? spheremap::make_icosphere(level)
                             : shape == "ellipsoid" ? spheremap::make_ellipsoid(level, 1, 1, stretch)
                             : shape == "dumbbell"  ? spheremap::make_dumbbell(separation, neck, rings, segments)
                                                    : spheremap::make_subdivided_cube(cube_n);
      if (flips > 0) mesh = spheremap::random_edge_flips(mesh, flips, seed);
      if (perturb > 0) mesh = spheremap::perturb_vertices(mesh, perturb, seed);
      spheremap::write_ply(generated_output, mesh, spheremap::PlyWriteOptions{options.ascii});
      if (!quiet)
        std::cout << fmt::format("{}: {} vertices, {} triangles\n", generated_output, mesh.vertex_count(), mesh.triangle_count());
    }
    if (*map_command) {
      options.map.weights = weights == "cotan"        ? spheremap::Weights::kCotangent
                            : weights == "mean-value" ? spheremap::Weights::kMeanValue
                                                      : spheremap::Weights::kUniform;
      options.map.solver = solver == "gauss-seidel" ? spheremap::Solver::kGaussSeidel : spheremap::Solver::kDirect;
      if (!poles.empty()) options.map.poles = parse_poles(poles);
      if (!component.empty()) options.prepare.component = parse_component(component);
      options.map.repair = !no_repair;
      const auto result = spheremap::run_map_job(input, options);
      spheremap::write_map_outputs(output, result, options);
      if (!quiet || !result.map.certificate.certified()) std::cout << spheremap::summary_text(result);
      if (!result.map.certificate.certified()) {
        const auto& c = result.map.certificate;
        const std::string coverage =
            std::abs(c.coverage - 1) < 1e-9 ? "" : fmt::format(", and the image covers the sphere {:.6f} times instead of once", c.coverage);
        std::cerr << fmt::format(
            "spheremap: {}: THE MAP IS NOT CERTIFIED: {} folded and {} collapsed triangles (listed in {}/report.json){}. "
            "It was written anyway; do not trust it.\n",
            input, c.folded, c.collapsed, output, coverage);
        return static_cast<int>(spheremap::ExitCode::kNotCertified);
      }
    }
    return 0;
  } catch (const spheremap::Error& e) {
    std::cerr << "spheremap: error: " << e.what() << "\n";
    return static_cast<int>(e.code());
  } catch (const std::exception& e) {
    std::cerr << "spheremap: internal error: " << e.what() << "\n";
    return 4;
  }
}
