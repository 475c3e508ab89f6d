// spheremap map INPUT -o OUTPUT: one mesh or structure to its sphere map (or every component of a
// structure's molecular surface to its own).
#include <cmath>
#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "pictures.hpp"
#include "spheremap/error.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/pipeline/output_folder.hpp"
#include "spheremap/text.hpp"

namespace spheremap::cli {
namespace {

struct MapCommand {
  static constexpr const char* kName = "map";
  static constexpr const char* kDescription =
      "Map a closed genus-0 mesh (OBJ, OFF, PLY, STL), or the molecular surface of a structure (PDB, mmCIF, PQR), "
      "onto the unit sphere";

  std::string input, output, poles, components = "outer";
  MapCliOptions map;
  bool quiet = false, force = false;
  bool no_pictures = false;
  void add(CLI::App* command);
  int run();
};

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

// The reader's warnings (a truncated last line, unknown elements), on stderr even with -q.
void print_warnings(const std::string& input, const MapJobResult& result) {
  for (const auto& warning : result.structure.warnings)
    std::cerr << fmt::format("spheremap: warning: {}: {}\n", valid_utf8(input), valid_utf8(warning));
}

// --components all: every genus-0 component of the molecular surface into OUTPUT/component-K.
int map_every_component(const MapCommand& s) {
  if (!s.map.component.empty()) throw InputError("--component and --components all exclude each other");
  const auto results = run_map_job_components(s.input, s.map.job);
  if (results.empty())
    throw MeshRefused(fmt::format("{}: no component of the molecular surface has genus 0 (--keep-topology?)", s.input));
  print_warnings(s.input, results.front());
  if (s.force) remove_map_outputs(s.output);
  try {
    for (const auto& result : results) {
      const auto folder = std::filesystem::path(s.output) / fmt::format("component-{}", result.component_index);
      write_map_outputs(folder, result, s.map.job);
      if (!s.no_pictures) write_pictures(folder, result);
    }
  } catch (...) {
    remove_map_outputs(s.output);  // no partial output: the components written so far go too, whatever the error
    throw;
  }
  int code = 0;
  for (const auto& result : results) {
    const auto folder = std::filesystem::path(s.output) / fmt::format("component-{}", result.component_index);
    const bool certified = result.map.certificate.certified();
    if (!s.quiet || !certified)
      std::cout << fmt::format("component {} ({}) -> {}\n", result.component_index,
                               to_string(result.components[static_cast<std::size_t>(result.component_index)].kind),
                               valid_utf8(folder.string()))
                << summary_text(result);
    if (!certified) code = static_cast<int>(ExitCode::kNotCertified);
  }
  if (code != 0)
    std::cerr << fmt::format("spheremap: {}: SOME COMPONENT MAPS ARE NOT CERTIFIED (see above)\n", s.input);
  return code;
}

int map_one(const MapCommand& s) {
  const auto result = run_map_job(s.input, s.map.job);
  print_warnings(s.input, result);
  if (s.force) remove_map_outputs(s.output);
  write_map_outputs(s.output, result, s.map.job);
  if (!s.no_pictures) write_pictures(s.output, result);
  const auto& c = result.map.certificate;
  if (!s.quiet || !c.certified()) std::cout << summary_text(result);
  if (c.certified()) return 0;
  const std::string coverage =
      std::abs(c.coverage - 1) < 1e-9
          ? ""
          : fmt::format(", and the image covers the sphere {:.6f} times instead of once", c.coverage);
  std::cerr << fmt::format(
      "spheremap: {}: THE MAP IS NOT CERTIFIED: {} folded and {} collapsed triangles (listed in {}/report.json){}. "
      "It was written anyway; do not trust it.\n",
      s.input, c.folded, c.collapsed, s.output, coverage);
  return static_cast<int>(ExitCode::kNotCertified);
}

void MapCommand::add(CLI::App* command) {
  command
      ->add_option("input", input,
                   "Mesh file: .obj .off .ply (ASCII/binary) .stl (ASCII/binary); or structure file: .pdb .ent "
                   ".cif .mmcif (also .gz) .pqr")
      ->required();
  add_output_option(command, output,
                    "Output folder: surface.ply, sphere.ply, report.json, pictures/ (maps and hemisphere figures), "
                    "index.html (the viewer)");
  command->add_flag("--no-pictures", no_pictures, "Write no pictures/ and no index.html (only the map and report)");
  command->add_option("--poles", poles,
                      "North and south pole vertices 'i,j': 0-based indices in the input file's vertex order, at "
                      "least 3 edges apart; default: the two vertices farthest apart");
  command
      ->add_option("--components", components,
                   "Structures: 'outer' (default: the outer surface; cavities and detached pieces reported) or "
                   "'all' (every genus-0 component on its own sphere, in OUTPUT/component-K/, K by decreasing "
                   "area)")
      ->check(CLI::IsMember({"outer", "all"}));
  add_quiet_flag(command, quiet);
  command->add_flag("--force", force,
                    "Replace the outputs of an earlier run in the output folder (surface/sphere .ply and .glb, "
                    "atoms.csv, residues.csv, report.json, index.html, pictures/, component-K/), removed once the "
                    "new map is made; without it such a folder is refused. Other files are kept");
  map.add(command, WeightingCount::kOne);
}

int MapCommand::run() {
  check_map_output_folder(output, force);
  map.apply();
  if (!poles.empty()) map.job.map.poles = parse_poles(poles);
  return components == "all" ? map_every_component(*this) : map_one(*this);
}

}  // namespace

Command add_map_command(CLI::App& app) { return make_command<MapCommand>(app); }

}  // namespace spheremap::cli
