// spheremap surface INPUT -o OUTPUT.ply: a structure's molecular surface, every component, as PLY.
#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/pipeline/molecular_surface.hpp"
#include "spheremap/text.hpp"

namespace spheremap::cli {
namespace {

// What `surface` prints: sizes, components, simplification, repair, timings (warnings: on stderr).
void print_surface(const std::string& output, const MapJobOptions& options, const MolecularSurface& result,
                   const HandleRepairReport& repair, const SimplifyReport& simplification) {
  const Mesh& surface = result.mesh;
  double area = 0;
  for (const auto& c : result.components) area += c.area;
  std::cout << fmt::format(
      "{}: {} vertices, {} triangles; contour area {:.1f} Å² (all components; probe {} Å, grid "
      "{} Å)\n",
      output, surface.vertex_count(), surface.triangle_count(), area, options.surface.probe, options.surface.grid);
  for (std::size_t c = 0; c < result.reports.size(); ++c) {
    const auto& r = result.reports[c];
    std::cout << fmt::format(
        "  component {}: {}, {} triangles, area {:.1f} Å², volume {:.1f} Å³, genus {}, {} "
        "residues\n",
        c, to_string(r.kind), r.triangles, r.area, r.volume, r.genus, r.residue_count);
  }
  if (options.simplify.target_edge_length > 0)
    std::cout << fmt::format(
        "  simplified: {} -> {} vertices (mean edge {:.3g} -> {:.3g} Å), area {:.1f} -> {:.1f} "
        "Å², every removed vertex within {:.3g} Å of the result\n",
        simplification.vertices_before, simplification.vertices_after, simplification.mean_edge_before,
        simplification.mean_edge_after, simplification.area_before, simplification.area_after,
        simplification.max_vertex_distance);
  if (repair.method != RepairMethod::kNone)
    std::cout << fmt::format(
        "  handle repair ({}): outer genus {} -> 0, {} change(s), {} grid samples; outer area "
        "{:.1f} -> {:.1f} Å² ({:+.2f}%)\n",
        to_string(repair.method), repair.genus_before, repair.closures.size(), repair.samples_changed,
        repair.area_before, repair.area_after, 100 * (repair.area_after / repair.area_before - 1));
  else if (repair.genus_before != 0)
    std::cout << fmt::format("  outer surface genus {} (--keep-topology: not repaired)\n", repair.genus_before);
  std::string stages;
  for (const auto& t : result.timings)
    stages += fmt::format("{}{} {:.2f} s", stages.empty() ? "" : ", ", t.stage, t.seconds);
  std::cout << "  timings: " << stages << "\n";
}

struct SurfaceCommand {
  static constexpr const char* kName = "surface";
  static constexpr const char* kDescription =
      "Write the solvent-excluded surface of a structure (PDB, mmCIF, PQR) as PLY, every component, with atom "
      "provenance (and each atom's B-factor, or PQR charge, per vertex)";

  std::string input, output;
  MapJobOptions options;
  StructureCliOptions structure;
  bool quiet = false;

  void add(CLI::App* command) {
    command->add_option("input", input, "Structure file: .pdb .ent .cif .mmcif (also .gz) .pqr")->required();
    add_output_option(command, output, "Output .ply file");
    command->add_flag("--ascii", options.ascii, "ASCII PLY with full precision (%.17g)");
    add_quiet_flag(command, quiet);
    structure.add(command, options, PresetScope::kSurface);
  }

  int run() {
    structure.apply(options);
    const Molecule molecule = read_structure(input, options.structure);
    for (const auto& warning : molecule.report.warnings)
      std::cerr << fmt::format("spheremap: warning: {}: {}\n", valid_utf8(input), valid_utf8(warning));  // even with -q
    HandleRepairReport repair;
    MolecularSurface result;
    try {
      result = repaired_surface(molecule.atoms, options.surface, options.keep_topology, &repair);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: {}", input, e.what()));
    }
    SimplifyReport simplification;
    if (options.simplify.target_edge_length > 0)
      result.mesh = simplify_surface(std::move(result.mesh), options.simplify, &simplification);
    PlyWriteOptions ply;
    ply.ascii = options.ascii;
    write_ply(output, result.mesh, ply);
    if (!quiet) print_surface(output, options, result, repair, simplification);
    return 0;
  }
};

}  // namespace

Command add_surface_command(CLI::App& app) { return make_command<SurfaceCommand>(app); }

}  // namespace spheremap::cli
