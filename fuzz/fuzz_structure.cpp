// Fuzz target: structure files through read_structure (gemmi for PDB and mmCIF, our PQR reader, zlib for
// .gz). The first byte chooses the file name and options; the rest is the file. Names ending in .gz get
// the bytes as they are, so the gzip framing (members, CRC, length, trailing bytes) is fuzzed too.
#include <array>
#include <cstdint>

#include "fuzz_input.hpp"
#include "spheremap/error.hpp"
#include "spheremap/molecule/structure.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  if (size < 1) return 0;
  static constexpr std::array<const char*, 6> kNames = {"input.pdb",    "input.cif",    "input.pqr",
                                                        "input.pdb.gz", "input.cif.gz", "input.pqr.gz"};
  const std::uint8_t selector = data[0];
  spheremap::StructureOptions options;
  options.strict = (selector & 0x08) != 0;
  options.keep_waters = (selector & 0x10) != 0;
  if ((selector & 0x20) != 0) options.keep_hydrogens = true;
  if ((selector & 0x40) != 0) options.model = 2;
  try {
    const auto path = spheremap::fuzz::write_input(data + 1, size - 1, kNames[(selector & 0x07) % kNames.size()]);
    (void)spheremap::read_structure(path, options);
  } catch (const spheremap::Error&) {
    // A refusal with a message: what a bad file must give.
  }
  return 0;
}
