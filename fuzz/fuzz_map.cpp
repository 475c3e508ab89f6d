// Fuzz target: read -> prepare -> map of tiny meshes, as `spheremap map MESH` does. The first byte chooses
// the format (OBJ, OFF, PLY, STL) and the weights; the rest is the file. Meshes beyond kMaxVertices or
// kMaxFaces are skipped so that each run stays fast (what larger meshes do is the data tests' work).
// A map that is returned must have one finite unit vector per vertex, and its certificate must be that of
// those points (certified or not: the command exits 3 for a map that is not).
#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>

#include "fuzz_input.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/prepare.hpp"

namespace {

constexpr std::size_t kMaxVertices = 64;
constexpr std::size_t kMaxFaces = 128;

void check(bool condition) {
  if (!condition) std::abort();  // a finding: libFuzzer saves the input
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static constexpr std::array<const char*, 4> kNames = {"input.obj", "input.off", "input.ply", "input.stl"};
  const std::uint8_t selector = data[0];
  try {
    const auto soup =
        spheremap::read_polygon_soup(spheremap::fuzz::write_input(data + 1, size - 1, kNames[selector % 4]));
    std::size_t corners = 0;
    for (const auto& face : soup.faces) corners += face.size();
    if (soup.positions.size() > kMaxVertices || soup.faces.size() > kMaxFaces || corners > 4 * kMaxFaces) return 0;
    const auto prepared = spheremap::prepare_mesh(soup);
    spheremap::MapOptions options;
    if ((selector & 0x04) != 0) options.weights = spheremap::Weights::kMeanValue;
    const auto map = spheremap::map_to_sphere(prepared.mesh, options);
    check(map.sphere.size() == prepared.mesh.positions.size());
    for (const auto& p : map.sphere) {
      check(std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]));
      check(std::abs(p[0] * p[0] + p[1] * p[1] + p[2] * p[2] - 1) < 1e-9);
    }
    // The certificate returned is that of the points returned.
    const auto again = spheremap::certify_sphere_map(prepared.mesh, map.sphere, map.certificate.collapse_floor);
    check(again.certified() == map.certificate.certified() && again.folded == map.certificate.folded);
  } catch (const spheremap::Error&) {
    // A refusal with a message: what a bad or unmappable mesh must give.
  }
  return 0;
}
