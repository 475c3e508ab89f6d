// Fuzz target: PLY meshes (ASCII, binary little- and big-endian) through read_polygon_soup, and through
// read_ply_mesh, which also reads the vertex attributes (what `spheremap` reads back from its own outputs).
#include <cstdint>

#include "fuzz_input.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const auto path = spheremap::fuzz::write_input(data, size, "input.ply");
  try {
    (void)spheremap::read_polygon_soup(path);
  } catch (const spheremap::Error&) {
    // A refusal with a message: what a bad file must give.
  }
  try {
    (void)spheremap::read_ply_mesh(path);
  } catch (const spheremap::Error&) {
  }
  return 0;
}
