// Fuzz target: --values tables (CSV or TSV) through read_values_file, then matched to a small structure
// (match_values) as `map --values` does.
#include <cstdint>
#include <string>
#include <vector>

#include "fuzz_input.hpp"
#include "spheremap/error.hpp"
#include "spheremap/properties/values_file.hpp"

namespace {

std::vector<spheremap::Atom> atoms() {
  std::vector<spheremap::Atom> result;
  const char* names[] = {"N", "CA", "C", "O"};
  for (int residue = 1; residue <= 3; ++residue) {
    for (const char* name : names) {
      spheremap::Atom atom;
      atom.name = name;
      atom.element = std::string(name).substr(0, 1);
      atom.residue_name = "ALA";
      atom.residue_number = residue;
      atom.chain = residue == 3 ? "B" : "A";
      atom.insertion_code = residue == 2 ? 'A' : ' ';
      result.push_back(atom);
    }
  }
  return result;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  static const std::vector<spheremap::Atom> kAtoms = atoms();
  try {
    const auto table = spheremap::read_values_file(spheremap::fuzz::write_input(data, size, "values.csv"));
    (void)spheremap::match_values(table, kAtoms);
  } catch (const spheremap::Error&) {
    // A refusal with a message: what a bad file must give.
  }
  return 0;
}
