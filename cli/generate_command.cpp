// spheremap generate SHAPE -o OUTPUT.ply: generated closed genus-0 meshes.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "commands.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/shapes/hard_cases.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap::cli {
namespace {

constexpr double kMaxVertices = 2e7;  // about 1.5 GB while written: more is a mistake, not a test mesh
constexpr double kUnbounded = std::numeric_limits<double>::infinity();

struct GenerateCommand {
  static constexpr const char* kName = "generate";
  static constexpr const char* kDescription =
      "Write a generated closed genus-0 mesh (for trying spheremap, tests and benchmarks) as PLY";
  std::string shape, output;
  int level = 3, cube_n = 10, rings = 60, segments = 32, vertices = 1000, spikes = 12, spike_rings = 6;
  double stretch = 20, separation = 3, neck = 0.3, flips = 0, perturb = 0, nesting = 0, length = 2;
  unsigned seed = 1;
  bool ascii = false, quiet = false;

  void add(CLI::App* command) {
    command->add_option("shape", shape, "icosphere | ellipsoid | dumbbell | cube | stacked | tube-u | tube-c | spiky")
        ->required()
        ->check(CLI::IsMember({"icosphere", "ellipsoid", "dumbbell", "cube", "stacked", "tube-u", "tube-c", "spiky"}));
    add_output_option(command, output, "Output .ply file");
    command->add_option("--level", level, "icosphere/ellipsoid/spiky: subdivision level (10*4^level+2 vertices)")
        ->check(CLI::Range(0, 10));  // level 10: 10.5 million vertices
    command->add_option("--stretch", stretch, "ellipsoid: length of the z axis (x and y are 1)")
        ->check(finite_number(0, 1e6, LowEnd::kExcluded));
    command->add_option("--n", cube_n, "cube: squares per face edge (6n^2+2 vertices)")->check(CLI::Range(1, 1800));
    command->add_option("--separation", separation, "dumbbell: distance between the two unit spheres' centres")
        ->check(finite_number(0, 1e6));
    command->add_option("--neck", neck, "dumbbell: radius of the neck (0..1)")
        ->check(finite_number(0, 1, LowEnd::kExcluded));
    command->add_option("--rings", rings, "dumbbell, tube-u, tube-c: vertex rings along the axis")
        ->check(CLI::Range(2, 100000));
    command->add_option("--segments", segments, "dumbbell, tube-u, tube-c: vertices per ring")
        ->check(CLI::Range(3, 1000));
    command
        ->add_option("--vertices", vertices, "stacked: vertices (a tetrahedron with vertices inserted into triangles)")
        ->check(CLI::Range(4, 10000000));
    command->add_option("--nesting", nesting, "stacked: probability of inserting into a triangle just made (depth)")
        ->check(finite_number(0, 1));
    command->add_option("--spikes", spikes, "spiky: thin tubes grown from vertices of the icosphere --level")
        ->check(CLI::Range(0, 100000));
    command->add_option("--length", length, "spiky: how far the spikes reach beyond the unit sphere")
        ->check(finite_number(0, 1e6, LowEnd::kExcluded));
    command->add_option("--spike-rings", spike_rings, "spiky: rings of vertices along each spike")
        ->check(CLI::Range(1, 10000));
    command->add_option("--flips", flips, "probability of random edge flips (creates degree-3 vertices)")
        ->check(finite_number(0, 1));
    command->add_option("--perturb", perturb, "random vertex offsets, in mean edge lengths")
        ->check(finite_number(0, kUnbounded));
    command->add_option("--seed", seed, "random seed for --flips, --perturb, stacked and spiky");
    command->add_flag("--ascii", ascii, "ASCII PLY");
    add_quiet_flag(command, quiet);
  }

  // The vertices asked for, before the mesh is made (spiky: its sphere only).
  double vertices_asked() const {
    if (shape == "dumbbell" || shape == "tube-u" || shape == "tube-c") return static_cast<double>(rings) * segments + 2;
    if (shape == "cube") return 6.0 * cube_n * cube_n + 2;
    if (shape == "stacked") return vertices;
    return 10 * std::pow(4.0, shape == "spiky" ? std::min(level, 6) : level) + 2;
  }

  int run() const {
    if (vertices_asked() > kMaxVertices)
      throw InputError(
          fmt::format("generate {}: {:.3g} vertices asked for, more than the {:.0e} generate writes; "
                      "choose a smaller size",
                      shape, vertices_asked(), kMaxVertices));
    try {
      return generate();
    } catch (const std::invalid_argument& e) {  // a combination of options the shape does not take
      throw InputError(fmt::format("generate {}: {}", shape, e.what()));
    }
  }

  int generate() const {
    Mesh mesh = shape == "icosphere"   ? make_icosphere(level)
                : shape == "ellipsoid" ? make_ellipsoid(level, 1, 1, stretch)
                : shape == "dumbbell"  ? make_dumbbell(separation, neck, rings, segments)
                : shape == "stacked"   ? make_stacked_triangulation(vertices, nesting, seed)
                : shape == "tube-u"    ? make_bent_tube(TubeBend::kU, segments, rings)
                : shape == "tube-c"    ? make_bent_tube(TubeBend::kC, segments, rings)
                : shape == "spiky"     ? make_spiky_sphere(std::min(level, 6), spikes, length, spike_rings, seed)
                                       : make_subdivided_cube(cube_n);
    if (flips > 0) mesh = random_edge_flips(mesh, flips, seed);
    if (perturb > 0) mesh = perturb_vertices(mesh, perturb, seed);
    PlyWriteOptions ply;
    ply.ascii = ascii;
    write_ply(output, mesh, ply);
    if (!quiet)
      std::cout << fmt::format("{}: {} vertices, {} triangles\n", output, mesh.vertex_count(), mesh.triangle_count());
    return 0;
  }
};

}  // namespace

Command add_generate_command(CLI::App& app) { return make_command<GenerateCommand>(app); }

}  // namespace spheremap::cli
