// Using spheremap as a library, without the command line: read a mesh, map it, check the certificate,
// write the sphere. Built with the project (target example_map_mesh):
//   ./build/example_map_mesh examples/dumbbell.ply out/sphere-from-cpp.ply
// or against an installed spheremap with find_package (examples/CMakeLists.txt).
#include <cstdio>

#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/metrics/distortion.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/prepare.hpp"

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr, "usage: %s INPUT_MESH OUTPUT.ply\n", argv[0]);
    return 1;
  }
  try {
    spheremap::PrepareOptions prepare;
    prepare.source_name = argv[1];
    const spheremap::PreparedMesh prepared = spheremap::prepare_mesh(spheremap::read_polygon_soup(argv[1]), prepare);

    spheremap::MapOptions options;
    options.weights = spheremap::Weights::kMeanValue;
    const spheremap::SphereMap map = spheremap::map_to_sphere(prepared.mesh, options);
    const spheremap::DistortionMetrics metrics = spheremap::measure_distortion(prepared.mesh, map.sphere);

    spheremap::Mesh sphere = prepared.mesh;
    sphere.positions = map.sphere;
    sphere.real_attributes[spheremap::attributes::kTheta] = map.theta;
    sphere.real_attributes[spheremap::attributes::kPhi] = map.phi;
    spheremap::write_ply(argv[2], sphere);

    std::printf("%s: %s, %lld folded, %lld collapsed, angle distortion %.1f degrees (mean)\n", argv[1],
                map.certificate.certified() ? "certified" : "NOT certified",
                static_cast<long long>(map.certificate.folded), static_cast<long long>(map.certificate.collapsed),
                metrics.angle_distortion_mean_degrees);
    return map.certificate.certified() ? 0 : 3;
  } catch (const spheremap::Error& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return static_cast<int>(e.code());
  }
}
