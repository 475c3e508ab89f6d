// Fuzz target: OpenDX potential maps (APBS's `write pot dx`) through read_dx.
#include <cstdint>

#include "fuzz_input.hpp"
#include "spheremap/error.hpp"
#include "spheremap/io/opendx.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)spheremap::read_dx(spheremap::fuzz::write_input(data, size, "input.dx"));
  } catch (const spheremap::Error&) {
    // A refusal with a message: what a bad file must give.
  }
  return 0;
}
