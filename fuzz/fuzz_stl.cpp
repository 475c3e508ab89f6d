// Fuzz target: STL meshes through read_polygon_soup (the reader, then the checks every format gets).
#include <cstdint>

#include "fuzz_input.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/mesh_io.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)spheremap::read_polygon_soup(spheremap::fuzz::write_input(data, size, "input.stl"));
  } catch (const spheremap::Error&) {
    // A refusal with a message: what a bad file must give.
  }
  return 0;
}
