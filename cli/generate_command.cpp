// spheremap generate SHAPE -o OUTPUT.ply: generated closed genus-0 meshes.
#include <iostream>

#include <fmt/format.h>

#include "commands.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/shapes.hpp"

namespace spheremap::cli {
namespace {
struct GenerateState {
  std::string shape, output;
  int level = 3, cube_n = 10, rings = 60, segments = 32;
  double stretch = 20, separation = 3, neck = 0.3, flips = 0, perturb = 0;
  unsigned seed = 1;
  bool ascii = false, quiet = false;
};
}  // namespace

Command add_generate_command(CLI::App& app) {
  const auto made = new_command<GenerateState>(
      app, "generate", "Write a generated closed genus-0 mesh (for trying spheremap, tests and benchmarks) as PLY");
  auto& s = *made.state;
  CLI::App* command = made.app;
  command->add_option("shape", s.shape, "icosphere | ellipsoid | dumbbell | cube")
      ->required()
      ->check(CLI::IsMember({"icosphere", "ellipsoid", "dumbbell", "cube"}));
  add_output_option(command, s.output, "Output .ply file");
  command->add_option("--level", s.level, "icosphere/ellipsoid: subdivision level (10*4^level+2 vertices)")->check(CLI::Range(0, 10));
  command->add_option("--stretch", s.stretch, "ellipsoid: length of the z axis (x and y are 1)")->check(CLI::PositiveNumber);
  command->add_option("--n", s.cube_n, "cube: squares per face edge (6n^2+2 vertices)")->check(CLI::Range(1, 10000));
  command->add_option("--separation", s.separation, "dumbbell: distance between the two unit spheres' centres");
  command->add_option("--neck", s.neck, "dumbbell: radius of the neck (0..1)");
  command->add_option("--rings", s.rings, "dumbbell: vertex rings along the axis")->check(CLI::PositiveNumber);
  command->add_option("--segments", s.segments, "dumbbell: vertices per ring")->check(CLI::Range(3, 100000));
  command->add_option("--flips", s.flips, "probability of random edge flips (creates degree-3 vertices)")->check(CLI::Range(0.0, 1.0));
  command->add_option("--perturb", s.perturb, "random vertex offsets, in mean edge lengths")->check(CLI::NonNegativeNumber);
  command->add_option("--seed", s.seed, "random seed for --flips and --perturb");
  command->add_flag("--ascii", s.ascii, "ASCII PLY");
  add_quiet_flag(command, s.quiet);

  return {command, [state = made.state]() {
            auto& s = *state;
            Mesh mesh = s.shape == "icosphere"   ? make_icosphere(s.level)
                        : s.shape == "ellipsoid" ? make_ellipsoid(s.level, 1, 1, s.stretch)
                        : s.shape == "dumbbell"  ? make_dumbbell(s.separation, s.neck, s.rings, s.segments)
                                                 : make_subdivided_cube(s.cube_n);
            if (s.flips > 0) mesh = random_edge_flips(mesh, s.flips, s.seed);
            if (s.perturb > 0) mesh = perturb_vertices(mesh, s.perturb, s.seed);
            write_ply(s.output, mesh, PlyWriteOptions{s.ascii});
            if (!s.quiet) std::cout << fmt::format("{}: {} vertices, {} triangles\n", s.output, mesh.vertex_count(), mesh.triangle_count());
            return 0;
          }};
}

}  // namespace spheremap::cli
