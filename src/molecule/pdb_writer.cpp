// gemmi's PDB writer (the reader is in structure.cpp; gemmi stays inside molecule/). Debian's gemmi formats
// numbers with Debian's stb_sprintf (package libstb-dev) instead of its bundled copy, and says so in a #warning
// (silenced for this file in CMakeLists.txt).
#define GEMMI_WRITE_IMPLEMENTATION
#include <gemmi/to_pdb.hpp>

#include <fstream>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/molecule/pdb_writer.hpp"

namespace spheremap {

void write_pdb(const std::vector<Atom>& atoms, const std::filesystem::path& path) {
  gemmi::Structure structure;
  structure.models.emplace_back("1");
  gemmi::Model& model = structure.models.back();
  for (const Atom& a : atoms) {
    if (model.chains.empty() || model.chains.back().name != a.chain) model.chains.emplace_back(a.chain);
    auto& residues = model.chains.back().residues;
    const gemmi::SeqId seqid(a.residue_number, a.insertion_code);
    if (residues.empty() || residues.back().seqid != seqid || residues.back().name != a.residue_name) {
      residues.emplace_back(gemmi::ResidueId{seqid, "", a.residue_name});
      residues.back().het_flag = a.hetero ? 'H' : 'A';
    }
    gemmi::Atom atom;
    atom.name = a.name;
    atom.element = gemmi::Element(a.element);
    atom.pos = gemmi::Position(a.position[0], a.position[1], a.position[2]);
    atom.occ = 1;
    atom.b_iso = 0;
    residues.back().atoms.push_back(atom);
  }
  gemmi::PdbWriteOptions options;
  options.seqres_records = options.ssbond_records = options.cryst1_record = options.link_records = false;
  options.cispep_records = false;
  std::ofstream out(path);
  if (out) gemmi::write_pdb(structure, out, options);
  if (!out)
    throw InputError(fmt::format("{}: cannot write the file; check the folder's permissions and space", path.string()));
}

}  // namespace spheremap
