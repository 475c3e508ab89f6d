#include <cmath>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "spheremap/error.hpp"

namespace spheremap::cli {
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
    throw InputError(fmt::format("--poles '{}': expected two vertex indices like 12,345", text));
  }
}

int parse_component(const std::string& text) {
  if (text == "largest") return kComponentLargest;
  try {
    std::size_t used = 0;
    const int k = std::stoi(text, &used);
    if (used == text.size() && k >= 0) return k;
  } catch (const std::exception&) {
  }
  throw InputError(fmt::format("--component '{}': expected 'largest' or a component number (0, 1, ...)", text));
}

struct MapState {
  std::string input, output, weights = "uniform", solver = "direct", poles, component, components = "outer";
  MapJobOptions options;
  StructureCliOptions structure;
  bool no_repair = false, quiet = false;
};

}  // namespace

Command add_map_command(CLI::App& app) {
  auto state = std::make_shared<MapState>();
  auto& s = *state;
  auto* command = app.add_subcommand(
      "map", "Map a closed genus-0 mesh (OBJ, OFF, PLY, STL), or the molecular surface of a structure (PDB, mmCIF, PQR), onto the unit sphere");
  command->add_option("input", s.input,
                      "Mesh file: .obj .off .ply (ASCII/binary) .stl (ASCII/binary); or structure file: .pdb .ent .cif .mmcif (also .gz) .pqr")
      ->required();
  command->add_option("-o,--output", s.output, "Output folder: surface.ply, sphere.ply, report.json")->required();
  command->add_option("--weights", s.weights, "Harmonic weights: uniform (the paper, default), cotan (may fold), mean-value")
      ->check(CLI::IsMember({"uniform", "cotan", "mean-value"}));
  command->add_option("--solver", s.solver, "direct (CHOLMOD/UMFPACK, default) or gauss-seidel (the paper's relaxation)")
      ->check(CLI::IsMember({"direct", "gauss-seidel"}));
  command->add_option("--poles", s.poles,
                      "North and south pole vertices 'i,j': 0-based indices in the input file's vertex order, at least 3 edges apart; default: the two vertices farthest apart");
  command->add_option("--component", s.component,
                      "Which connected component to map: 'largest' or a number (meshes: file order, default refuse; "
                      "structures: by decreasing area, default 0 = the outer surface)");
  command->add_option("--components", s.components,
                      "Structures: 'outer' (default: the outer surface; cavities and detached pieces reported) or 'all' "
                      "(every genus-0 component on its own sphere, in OUTPUT/component-K/, K by decreasing area)")
      ->check(CLI::IsMember({"outer", "all"}));
  command->add_option("--weld-tolerance", s.options.prepare.weld_tolerance, "Weld vertices closer than this (default 0: exactly coincident only)")
      ->check(CLI::NonNegativeNumber);
  command->add_option("--collapse-floor", s.options.map.collapse_floor,
                      "Normalized area ratio below which a triangle counts as collapsed (default 1e-6)")
      ->check(CLI::PositiveNumber);
  command->add_flag("--ascii", s.options.ascii, "Write ASCII PLY with full precision (%.17g), e.g. for PyMOL");
  add_equalizing_rounds_option(command, s.options.map);
  command->add_flag("--no-repair", s.no_repair, "The paper's algorithm only: no re-weighting, no untangling (the certificate still runs)");
  command->add_flag("-q,--quiet", s.quiet, "Print nothing on success");
  s.structure.add(command, s.options);

  return {command, [state]() {
            auto& s = *state;
            s.structure.apply(s.options);
            s.options.map.weights = parse_weights(s.weights);
            s.options.map.solver = s.solver == "gauss-seidel" ? Solver::kGaussSeidel : Solver::kDirect;
            if (!s.poles.empty()) s.options.map.poles = parse_poles(s.poles);
            if (!s.component.empty()) s.options.prepare.component = parse_component(s.component);
            s.options.map.repair = !s.no_repair;
            if (s.components == "all") {
              if (!s.component.empty()) throw InputError("--component and --components all exclude each other");
              const auto results = run_map_job_components(s.input, s.options);
              if (results.empty())
                throw MeshRefused(fmt::format("{}: no component of the molecular surface has genus 0 (--keep-topology?)", s.input));
              int code = 0;
              for (const auto& result : results) {
                const auto folder = std::filesystem::path(s.output) / fmt::format("component-{}", result.component_index);
                write_map_outputs(folder, result, s.options);
                if (!s.quiet || !result.map.certificate.certified())
                  std::cout << fmt::format("component {} ({}) -> {}\n", result.component_index,
                                           result.components[static_cast<std::size_t>(result.component_index)].kind,
                                           folder.string())
                            << summary_text(result);
                if (!result.map.certificate.certified()) code = static_cast<int>(ExitCode::kNotCertified);
              }
              if (code != 0) std::cerr << fmt::format("spheremap: {}: SOME COMPONENT MAPS ARE NOT CERTIFIED (see above)\n", s.input);
              return code;
            }
            const auto result = run_map_job(s.input, s.options);
            write_map_outputs(s.output, result, s.options);
            if (!s.quiet || !result.map.certificate.certified()) std::cout << summary_text(result);
            if (!result.map.certificate.certified()) {
              const auto& c = result.map.certificate;
              const std::string coverage = std::abs(c.coverage - 1) < 1e-9
                                               ? ""
                                               : fmt::format(", and the image covers the sphere {:.6f} times instead of once", c.coverage);
              std::cerr << fmt::format(
                  "spheremap: {}: THE MAP IS NOT CERTIFIED: {} folded and {} collapsed triangles (listed in {}/report.json){}. "
                  "It was written anyway; do not trust it.\n",
                  s.input, c.folded, c.collapsed, s.output, coverage);
              return static_cast<int>(ExitCode::kNotCertified);
            }
            return 0;
          }};
}

}  // namespace spheremap::cli
