#include "spheremap/molecule/structure.hpp"

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "../test_support.hpp"
#include "spheremap/error.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

class Structure : public testing_support::FolderTest {};

// A PDB record in fixed columns.
std::string record(const char* kind, int serial, const char* name, char altloc, const char* residue, char chain,
                   int number, double x, double y, double z, double occupancy, const char* element,
                   double b_factor = 0) {
  return fmt::format("{:<6}{:>5} {:<4}{}{:>3} {}{:>4}    {:>8.3f}{:>8.3f}{:>8.3f}{:>6.2f}{:>6.2f}          {:>2}\n",
                     kind, serial, name, altloc, residue, chain, number, x, y, z, occupancy, b_factor, element);
}

std::string small_pdb() {
  return record("ATOM", 1, " N", ' ', "ALA", 'A', 1, 11.104, 6.134, -6.504, 1, "N") +
         record("ATOM", 2, " CA", 'A', "ALA", 'A', 1, 11.639, 6.071, -5.147, 0.3, "C") +
         record("ATOM", 3, " CA", 'B', "ALA", 'A', 1, 11.700, 6.000, -5.100, 0.7, "C") +
         record("ATOM", 4, " H", ' ', "ALA", 'A', 1, 10.500, 6.500, -6.900, 1, "H") +
         record("ATOM", 5, " C", ' ', "GLY", 'B', 2, 12.000, 7.000, -4.000, 1, "C") +
         record("HETATM", 6, "FE", ' ', "HEM", 'A', 3, 10.000, 5.000, -4.000, 1, "FE") +
         record("HETATM", 7, " O", ' ', "HOH", 'A', 4, 9.000, 5.000, -4.000, 1, "O") + "END\n";
}

// gemmi reads connection records past the end of a short one (FUZZING.md, finding 4): they are not given to
// it, and a file with whole, short or mangled ones reads the same atoms as the file without them. (The
// over-read itself shows only under AddressSanitizer: fuzz/regressions/structure/.)
TEST_F(Structure, ConnectionRecordsOfAnyLengthChangeNothing) {
  const std::string connections =
      "SSBOND   1 CYS A    6    CYS A  127                          1555   1555  2.03  \n"
      "LINK         FE   HEM A   3                 N   ALA A   1     1555   1555  2.07  \n"
      "LINK         O   HOH A   4                 FE   HEM A   3     1555   1555  2.1\n"
      "link         \xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6"
      "\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6"
      "\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\xa6\n"
      "CISPEP   1 GLY A    2    PRO\n";
  const auto plain = read_structure(write("plain.pdb", small_pdb()));
  const auto linked = read_structure(write("linked.pdb", connections + small_pdb()));
  ASSERT_EQ(linked.atoms.size(), plain.atoms.size());
  for (std::size_t i = 0; i < plain.atoms.size(); ++i) {
    EXPECT_EQ(linked.atoms[i].serial, plain.atoms[i].serial);
    EXPECT_EQ(linked.atoms[i].position, plain.atoms[i].position);
    EXPECT_EQ(linked.atoms[i].residue_name, plain.atoms[i].residue_name);
  }
  EXPECT_EQ(linked.report.warnings, plain.report.warnings);
}

TEST_F(Structure, DefaultsKeepTheMostOccupiedAltlocAndDropHydrogensAndWaters) {
  const auto molecule = read_structure(write("small.pdb", small_pdb()));
  ASSERT_EQ(molecule.atoms.size(), 4u);  // N, CA (altloc B), C, FE
  EXPECT_EQ(molecule.report.alternate_locations_removed, 1);
  EXPECT_EQ(molecule.report.hydrogens_removed, 1);
  EXPECT_EQ(molecule.report.waters_removed, 1);
  const Atom& ca = molecule.atoms[1];
  EXPECT_EQ(ca.name, "CA");
  EXPECT_EQ(ca.serial, 3);
  EXPECT_DOUBLE_EQ(ca.position[0], 11.700);
  EXPECT_DOUBLE_EQ(ca.radius, 1.70);
  EXPECT_EQ(ca.residue_name, "ALA");
  EXPECT_EQ(ca.residue_number, 1);
  EXPECT_EQ(ca.chain, "A");
  EXPECT_EQ(ca.element, "C");
  const Atom& iron = molecule.atoms[3];
  EXPECT_TRUE(iron.hetero);
  EXPECT_DOUBLE_EQ(iron.radius, kUnknownElementRadius);
  ASSERT_EQ(molecule.report.warnings.size(), 1u);
  EXPECT_NE(molecule.report.warnings[0].find("'FE'"), std::string::npos) << molecule.report.warnings[0];
}

TEST_F(Structure, OptionsSelectChainsAndKeepWhatIsAsked) {
  StructureOptions options;
  options.chains = {"A"};
  options.keep_hydrogens = true;
  options.keep_waters = true;
  options.keep_hetero = false;
  const auto molecule = read_structure(write("small.pdb", small_pdb()), options);
  // N, CA(B), H, HOH O; GLY is chain B, FE is HETATM.
  EXPECT_EQ(molecule.atoms.size(), 4u);
  EXPECT_EQ(molecule.report.other_chains_removed, 1);
  EXPECT_EQ(molecule.report.hetero_removed, 1);
  options.chains = {"Z"};
  try {
    read_structure(folder_ / "small.pdb", options);
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("chain 'Z' does not exist; the chains are: A, B"), std::string::npos)
        << e.what();
  }
  StructureOptions radii;
  radii.radii = std::map<std::string, double>{{"C", 2.0}, {"N", 1.5}, {"FE", 1.3}};
  const auto custom = read_structure(folder_ / "small.pdb", radii);
  EXPECT_DOUBLE_EQ(custom.atoms[1].radius, 2.0);
  EXPECT_DOUBLE_EQ(custom.atoms[3].radius, 1.3);
  EXPECT_TRUE(custom.report.warnings.empty());
}

TEST_F(Structure, ReadsPqrWithAndWithoutChains) {
  const auto path = write("small.pqr",
                          "REMARK   1 PQR file\n"
                          "ATOM      1  N   LYS A   1      -8.655   5.770   8.371  0.0966 1.8240\n"
                          "ATOM      2  HZ1 LYS A   1      -9.000   5.000   8.000  0.3400 0.6000\n"
                          "ATOM      3  CA  LYS    52A     -8.000   6.000   8.000  0.1000 1.9080\n"
                          "HETATM    4 ZN   ZN     90      -7.000   6.000   7.000  2.0000 1.3900\n");
  // A PQR's hydrogens are kept by default (they carry charge); --no-hydrogens leaves them out.
  const auto with_hydrogens = read_structure(path);
  ASSERT_EQ(with_hydrogens.atoms.size(), 4u);
  EXPECT_EQ(with_hydrogens.atoms[1].name, "HZ1");
  StructureOptions no_hydrogens;
  no_hydrogens.keep_hydrogens = false;
  const auto molecule = read_structure(path, no_hydrogens);
  ASSERT_EQ(molecule.atoms.size(), 3u);
  ASSERT_TRUE(molecule.atoms[0].charge.has_value());
  EXPECT_EQ(*molecule.atoms[0].charge, 0.0966);  // the decimal as written, to the last bit
  EXPECT_EQ(*molecule.atoms[2].charge, 2.0);
  EXPECT_FALSE(molecule.atoms[0].b_factor.has_value());  // PQR has no B-factor column
  EXPECT_DOUBLE_EQ(molecule.atoms[0].radius, 1.8240);
  EXPECT_EQ(molecule.atoms[0].chain, "A");
  EXPECT_EQ(molecule.atoms[1].residue_number, 52);
  EXPECT_EQ(molecule.atoms[1].insertion_code, 'A');
  EXPECT_EQ(molecule.atoms[1].chain, "");
  EXPECT_EQ(molecule.atoms[2].element, "ZN");
  EXPECT_EQ(molecule.report.hydrogens_removed, 1);
  const auto broken = write("broken.pqr", "ATOM      1  N   LYS A   1      -8.655   5.770   8.371\n");
  EXPECT_THROW(read_structure(broken), InputError);
}

TEST_F(Structure, BadInputsGiveAClearError) {
  auto message = [&](const fs::path& path) -> std::string {
    try {
      read_structure(path);
    } catch (const InputError& e) {
      return e.what();
    }
    return "(accepted)";
  };
  EXPECT_NE(message(folder_ / "missing.pdb").find("no such file"), std::string::npos);
  EXPECT_NE(message(write("empty.pdb", "")).find("empty"), std::string::npos);
  EXPECT_NE(message(write("x.xyz", "1\n")).find("unknown structure format"), std::string::npos);
  EXPECT_NE(message(write("garbage.cif", std::string("\x01\x02\x03\xff data_ loop_", 17))).find("garbage.cif"),
            std::string::npos);
  EXPECT_NE(
      message(write("one.pdb", record("ATOM", 1, " CA", ' ', "ALA", 'A', 1, 0, 0, 0, 1, "C"))).find("at least two"),
      std::string::npos);
  EXPECT_NE(message(write("far.pdb", record("ATOM", 1, " CA", ' ', "ALA", 'A', 1, 0, 0, 0, 1, "C") +
                                         record("ATOM", 2, " CB", ' ', "ALA", 'A', 1, 9999999, 0, 0, 1, "C")))
                .find("not a real position"),
            std::string::npos);
  EXPECT_NE(
      message(write("water.pdb", record("HETATM", 1, " O", ' ', "HOH", 'A', 1, 0, 0, 0, 1, "O") +
                                     record("HETATM", 2, " O", ' ', "HOH", 'A', 2, 3, 0, 0, 1, "O")))
          .find("left after filtering (hydrogens, waters); a molecular surface needs at least two. Check --chains "
                "and --model, or keep more atoms (--keep-waters, --keep-hydrogens)"),
      std::string::npos);
}

// A file cut short: the last line without its line break, or the last record shorter than the others, is a
// warning (quoting the line); StructureOptions::strict makes it an error naming the file.
TEST_F(Structure, SignsOfATruncatedFileAreWarningsAndStrictMakesThemErrors) {
  const std::string body = record("ATOM", 1, " N", ' ', "ALA", 'A', 1, 1, 2, 3, 1, "N") +
                           record("ATOM", 2, " CA", ' ', "ALA", 'A', 1, 2.4, 2, 3, 1, "C");
  const std::string last = record("ATOM", 3, " C", ' ', "ALA", 'A', 1, 3.8, 2, 3, 1, "C");
  const auto whole = read_structure(write("whole.pdb", body + last));
  EXPECT_TRUE(whole.report.warnings.empty());
  const auto no_break = read_structure(write("no-break.pdb", body + last.substr(0, last.size() - 1)));
  ASSERT_EQ(no_break.report.warnings.size(), 1u);
  EXPECT_NE(no_break.report.warnings[0].find("does not end with a line break"), std::string::npos);
  EXPECT_EQ(no_break.atoms.size(), 3u);
  const auto short_record = read_structure(write("short.pdb", body + last.substr(0, 66) + "\n"));
  ASSERT_EQ(short_record.report.warnings.size(), 1u);
  EXPECT_NE(short_record.report.warnings[0].find("shorter than the file's 2 other ones"), std::string::npos);
  StructureOptions strict;
  strict.strict = true;
  EXPECT_NO_THROW(read_structure(folder_ / "whole.pdb", strict));
  for (const char* name : {"no-break.pdb", "short.pdb"}) {
    try {
      read_structure(folder_ / name, strict);
      ADD_FAILURE() << name << ": no error";
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(name), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("--strict"), std::string::npos) << e.what();
    }
  }
}

// Names from the file reach JSON and CSV: ill-formed UTF-8 becomes U+FFFD there.
TEST_F(Structure, NamesAreMadeValidUtf8) {
  const auto molecule =
      read_structure(write("latin1.pdb", record("ATOM", 1, " N\xE9", ' ', "ALA", 'A', 1, 1, 2, 3, 1, "N") +
                                             record("ATOM", 2, " CA", ' ', "AL\xFF", 'A', 1, 2.4, 2, 3, 1, "C")));
  ASSERT_EQ(molecule.atoms.size(), 2u);
  EXPECT_EQ(molecule.atoms[0].name, "N\xEF\xBF\xBD");
  EXPECT_EQ(molecule.atoms[1].residue_name, "AL\xEF\xBF\xBD");
}

// B-factors are the column users fill with any per-atom value: each must come out as the decimal in the
// file (gemmi holds it as a float; 15.23f widened is 15.229999542236328).
TEST_F(Structure, BFactorsAreReadAsTheFileWritesThem) {
  const auto pdb = read_structure(
      write("b.pdb", record("ATOM", 1, " N", ' ', "ALA", 'A', 1, 1.0, 0, 0, 1, "N", 15.23) +
                         record("ATOM", 2, " CA", ' ', "ALA", 'A', 1, 2.5, 0, 0, 1, "C", 7.5) +
                         record("ATOM", 3, " C", ' ', "ALA", 'A', 1, 4.0, 0, 0, 1, "C", -0.01) + "END\n"));
  ASSERT_EQ(pdb.atoms.size(), 3u);
  for (const auto& a : pdb.atoms) ASSERT_TRUE(a.b_factor.has_value());
  EXPECT_EQ(*pdb.atoms[0].b_factor, 15.23);
  EXPECT_EQ(*pdb.atoms[1].b_factor, 7.5);
  EXPECT_EQ(*pdb.atoms[2].b_factor, -0.01);
  EXPECT_FALSE(pdb.atoms[0].charge.has_value());  // PDB: no partial charges
  // mmCIF through gemmi's structure model, and through the bare _atom_site table (no auth_seq_id).
  const std::string labels =
      "data_test\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.type_symbol\n_atom_site.label_atom_id\n"
      "_atom_site.label_comp_id\n_atom_site.label_asym_id\n_atom_site.label_entity_id\n_atom_site.label_seq_id\n";
  const std::string values =
      "_atom_site.Cartn_x\n_atom_site.Cartn_y\n_atom_site.Cartn_z\n_atom_site.occupancy\n_atom_site.B_iso_or_equiv\n";
  const std::string header = labels + values;
  const std::string with_auth =
      labels + "_atom_site.auth_seq_id\n_atom_site.auth_asym_id\n_atom_site.pdbx_PDB_model_num\n" + values +
      "ATOM 1 N N ALA A 1 1 1 A 1 1.000 0.000 0.000 1.00 12.345\n"
      "ATOM 2 C CA ALA A 1 1 1 A 1 2.500 0.000 0.000 1.00 99.99\n";
  const auto cif = read_structure(write("b.cif", with_auth));
  ASSERT_EQ(cif.atoms.size(), 2u);
  EXPECT_EQ(*cif.atoms[0].b_factor, 12.345);
  EXPECT_EQ(*cif.atoms[1].b_factor, 99.99);
  const auto bare = read_structure(write("bare.cif", header + "ATOM 1 N N ALA A 1 1 1.000 0.000 0.000 1.00 12.345\n"
                                                              "ATOM 2 C CA ALA A 1 1 2.500 0.000 0.000 1.00 99.99\n"));
  ASSERT_EQ(bare.atoms.size(), 2u);
  EXPECT_EQ(*bare.atoms[0].b_factor, 12.345);
  EXPECT_EQ(*bare.atoms[1].b_factor, 99.99);
  // A table without the column (or with '?' in it) gives no B-factor, not a zero.
  const auto without = read_structure(write("none.cif", header.substr(0, header.rfind("_atom_site.B_iso_or_equiv")) +
                                                            "ATOM 1 N N ALA A 1 1 1.000 0.000 0.000 1.00\n"
                                                            "ATOM 2 C CA ALA A 1 1 2.500 0.000 0.000 1.00\n"));
  ASSERT_EQ(without.atoms.size(), 2u);
  EXPECT_FALSE(without.atoms[0].b_factor.has_value());
  const auto unknown =
      read_structure(write("unknown.cif", header + "ATOM 1 N N ALA A 1 1 1.000 0.000 0.000 1.00 ?\n"
                                                   "ATOM 2 C CA ALA A 1 1 2.500 0.000 0.000 1.00 4.5\n"));
  EXPECT_FALSE(unknown.atoms[0].b_factor.has_value());
  EXPECT_EQ(*unknown.atoms[1].b_factor, 4.5);
}

TEST_F(Structure, RadiusTableFile) {
  const auto table = load_radius_table(write("radii.txt", "# element radius\nC 1.7\nfe 1.3  # iron\n\n"));
  EXPECT_DOUBLE_EQ(table.at("FE"), 1.3);
  try {
    load_radius_table(write("bad.txt", "C 1.7\nN\n"));
    FAIL();
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("bad.txt:2"), std::string::npos) << e.what();
  }
}

const fs::path kPdb = fs::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb";

TEST(DataStructure, SharedStructuresReadWithTheDefaults) {
  if (!fs::exists(kPdb)) GTEST_SKIP() << "shared data not found: " << kPdb << " (skipped on purpose)";
  // 1crn: 327 heavy atoms, no waters, no altlocs.
  EXPECT_EQ(read_structure(kPdb / "misc" / "1crn.cif").atoms.size(), 327u);
  // 3lzt: 1398 atoms, 250 of them water, 259 with an altloc flag, no hydrogens.
  const auto lysozyme = read_structure(kPdb / "paper77" / "3lzt.pdb");
  EXPECT_EQ(static_cast<std::int64_t>(lysozyme.atoms.size()) + lysozyme.report.waters_removed +
                lysozyme.report.alternate_locations_removed,
            1398);
  EXPECT_GT(lysozyme.report.alternate_locations_removed, 0);
  for (const auto& a : lysozyme.atoms) ASSERT_NE(a.residue_name, "HOH");
  // 1bna (written by PyMOL, read through the _atom_site table): 566 atoms, 80 of them water.
  const auto dna = read_structure(kPdb / "misc" / "1bna.cif");
  EXPECT_EQ(static_cast<std::int64_t>(dna.atoms.size()) + dna.report.waters_removed, 566);
  EXPECT_EQ(dna.report.waters_removed, 80);
  // 1hpv (old PDB with line numbers in columns 73-80): read up to column 72, with a warning.
  const auto protease = read_structure(kPdb / "misc" / "1hpv.pdb");
  EXPECT_FALSE(protease.report.warnings.empty());
  for (const auto& a : protease.atoms) ASSERT_TRUE(bondi_radius(a.element) || a.radius == kUnknownElementRadius);
  // 1brf: 375 hydrogens.
  EXPECT_EQ(read_structure(kPdb / "paper77" / "1brf.pdb").report.hydrogens_removed, 375);
  // NMR ensemble: 20 models.
  StructureOptions second;
  second.model = 2;
  const auto model2 = read_structure(kPdb / "misc" / "1tap.pdb", second);
  EXPECT_EQ(model2.report.models_in_file, 20);
  EXPECT_EQ(model2.atoms.front().model, 2);
  second.model = 21;
  EXPECT_THROW(read_structure(kPdb / "misc" / "1tap.pdb", second), InputError);
}

TEST(DataStructure, EveryStructureInTheSharedSetReads) {
  if (!fs::exists(kPdb)) GTEST_SKIP() << "shared data not found: " << kPdb << " (skipped on purpose)";
  int files = 0;
  for (const auto* folder : {"paper77", "misc"}) {
    for (const auto& entry : fs::directory_iterator(kPdb / folder)) {
      ++files;
      const auto molecule = read_structure(entry.path());
      EXPECT_GE(molecule.atoms.size(), 2u) << entry.path();
      for (const auto& a : molecule.atoms) {
        ASSERT_GT(a.radius, 0) << entry.path();
        ASSERT_NE(a.element, "H") << entry.path();
      }
    }
  }
  EXPECT_EQ(files, 88);
}

}  // namespace
}  // namespace spheremap
