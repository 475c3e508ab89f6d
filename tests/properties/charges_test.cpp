#include "spheremap/properties/charges.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <numeric>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/properties/pdb2pqr.hpp"

namespace spheremap {
namespace {

Atom atom(const char* name, const char* residue, int number, const char* chain = "A", const char* element = "") {
  Atom a;
  a.name = name;
  a.residue_name = residue;
  a.residue_number = number;
  a.chain = chain;
  a.element = *element ? element : std::string(1, name[0]);
  a.position = {static_cast<double>(number), 0, 0};
  return a;
}

// A tripeptide LYS-ASP-GLU with both termini, a calcium, a chloride, a water and a ligand.
std::vector<Atom> peptide() {
  std::vector<Atom> atoms;
  for (const char* name : {"N", "CA", "C", "O", "CB", "CG", "CD", "CE", "NZ"}) atoms.push_back(atom(name, "LYS", 1));
  for (const char* name : {"N", "CA", "C", "O", "CB", "CG", "OD1", "OD2"}) atoms.push_back(atom(name, "ASP", 2));
  for (const char* name : {"N", "CA", "C", "O", "CB", "CG", "CD", "OE1", "OE2", "OXT"})
    atoms.push_back(atom(name, "GLU", 3));
  atoms.push_back(atom("CA", "CA", 101, "A", "CA"));
  atoms.push_back(atom("CL", "CL", 102, "A", "CL"));
  atoms.push_back(atom("O", "HOH", 201));
  atoms.push_back(atom("C1", "LIG", 301));
  return atoms;
}

double charge_of(const std::vector<Atom>& atoms, const ChargeAssignment& charges, const char* residue,
                 const char* name) {
  for (std::size_t i = 0; i < atoms.size(); ++i)
    if (atoms[i].residue_name == residue && atoms[i].name == name) return charges.atom_charges[i];
  ADD_FAILURE() << "no atom " << residue << " " << name;
  return NAN;
}

TEST(FormalCharges, IonizableGroupsTerminiAndIons) {
  const auto atoms = peptide();
  const ChargeAssignment charges = formal_charges(atoms);
  EXPECT_EQ(charges.source, "formal");
  EXPECT_EQ(charge_of(atoms, charges, "LYS", "N"), 1.0);  // N-terminus
  EXPECT_EQ(charge_of(atoms, charges, "LYS", "NZ"), 1.0);
  EXPECT_EQ(charge_of(atoms, charges, "LYS", "O"), 0.0);
  EXPECT_EQ(charge_of(atoms, charges, "ASP", "N"), 0.0);  // not a terminus
  EXPECT_EQ(charge_of(atoms, charges, "ASP", "OD1"), -0.5);
  EXPECT_EQ(charge_of(atoms, charges, "ASP", "OD2"), -0.5);
  EXPECT_EQ(charge_of(atoms, charges, "GLU", "OE1"), -0.5);
  EXPECT_EQ(charge_of(atoms, charges, "GLU", "O"), -0.5);  // C-terminus with OXT
  EXPECT_EQ(charge_of(atoms, charges, "GLU", "OXT"), -0.5);
  EXPECT_EQ(charge_of(atoms, charges, "CA", "CA"), 2.0);
  EXPECT_EQ(charge_of(atoms, charges, "CL", "CL"), -1.0);
  EXPECT_EQ(charge_of(atoms, charges, "HOH", "O"), 0.0);
  // +1 (N-term) +1 (LYS) -1 (ASP) -1 (GLU) -1 (C-term) +2 (Ca) -1 (Cl) = 0
  EXPECT_DOUBLE_EQ(charges.net_charge, 0.0);
  EXPECT_DOUBLE_EQ(std::accumulate(charges.atom_charges.begin(), charges.atom_charges.begin() + 27, 0.0), -1.0);
  EXPECT_EQ(charges.atoms_unmatched, 1);  // the ligand
  EXPECT_EQ(charges.atoms_charged, static_cast<std::int64_t>(atoms.size()) - 1);
  ASSERT_EQ(charges.warnings.size(), 1u);
  EXPECT_NE(charges.warnings[0].find("LIG (1 atoms)"), std::string::npos) << charges.warnings[0];
  EXPECT_EQ(charges.points.charges.size(), atoms.size());
}

TEST(FormalCharges, TableEntries) {
  EXPECT_EQ(formal_charge("ARG", "NH1", {}), 0.5);
  EXPECT_EQ(formal_charge("ARG", "NH2", {}), 0.5);
  EXPECT_EQ(formal_charge("ARG", "NE", {}), 0.0);
  EXPECT_EQ(formal_charge("HIS", "NE2", {}), 0.0);  // neutral at pH 7
  EXPECT_EQ(formal_charge("HIP", "NE2", {}), 0.5);
  EXPECT_EQ(formal_charge("HSP", "ND1", {}), 0.5);
  EXPECT_EQ(formal_charge("CYM", "SG", {}), -1.0);
  EXPECT_EQ(formal_charge("DA", "OP1", {}), -0.5);
  EXPECT_EQ(formal_charge("DG", "O2P", {}), -0.5);  // old name
  EXPECT_EQ(formal_charge("U", "OP2", {}), -0.5);
  EXPECT_EQ(formal_charge("DT", "P", {}), 0.0);
  EXPECT_EQ(formal_charge("MG", "MG", {}), 2.0);
  EXPECT_EQ(formal_charge("ZN", "ZN", {}), 2.0);
  EXPECT_EQ(formal_charge("NA", "NA", {}), 1.0);
  EXPECT_EQ(formal_charge("IOD", "I", {}), -1.0);
  EXPECT_EQ(formal_charge("GLY", "O", {false, true, false}), -1.0);  // C-terminus without OXT
  EXPECT_EQ(formal_charge("PRO", "N", {true, false, false}), 1.0);
  EXPECT_EQ(formal_charge("asp", "od1", {}), -0.5);  // any case
  EXPECT_EQ(formal_charge("HEM", "FE", {}), 0.0);
  EXPECT_TRUE(formal_table_knows("HOH"));
  EXPECT_FALSE(formal_table_knows("HEM"));
}

TEST(FormalCharges, CappedChainsHaveNoChargedTerminus) {
  std::vector<Atom> atoms = {atom("C", "ACE", 0), atom("N", "ALA", 1), atom("O", "ALA", 1), atom("N", "NME", 2)};
  const auto charges = formal_charges(atoms);
  EXPECT_EQ(charges.net_charge, 0.0);
  // Two chains: each has its own termini.
  atoms = {atom("N", "GLY", 1, "A"), atom("O", "GLY", 1, "A"), atom("N", "GLY", 1, "B"), atom("O", "GLY", 1, "B")};
  EXPECT_EQ(formal_charges(atoms).atom_charges, (std::vector<double>{1, -1, 1, -1}));
}

Atom charged(Atom a, double q) {
  a.charge = q;
  return a;
}

TEST(PqrCharges, MatchedByChainResidueAndNameHydrogensAdded) {
  const std::vector<Atom> atoms = {atom("N", "LYS", 1), atom("NZ", "LYS", 1), atom("O5*", "DA", 2),
                                   atom("O1P", "DA", 2), atom("CA", "GLY", 3)};
  const std::vector<Atom> pqr = {charged(atom("N", "LYS", 1), 0.1),    charged(atom("NZ", "LYS", 1), -0.3),
                                 charged(atom("HZ1", "LYS", 1), 0.33), charged(atom("HZ2", "LYS", 1), 0.33),
                                 charged(atom("O5'", "DA", 2), -0.5),  charged(atom("OP1", "DA", 2), -0.7),
                                 charged(atom("OXT", "DA", 2), -0.2),  charged(atom("N", "GLY", 9), 1.0)};
  const ChargeAssignment c = match_pqr_charges(atoms, pqr, "test.pqr");
  EXPECT_EQ(c.atom_charges, (std::vector<double>{0.1, -0.3, -0.5, -0.7, 0.0}));
  EXPECT_EQ(c.atom_matched, (std::vector<bool>{true, true, true, true, false}));
  EXPECT_EQ(c.atoms_charged, 4);
  EXPECT_EQ(c.atoms_unmatched, 1);
  EXPECT_EQ(c.added_atoms, 3);  // two hydrogens and an OXT, in residues of the structure
  EXPECT_EQ(c.added_hydrogens, 2);
  EXPECT_EQ(c.pqr_atoms_unused, 1);  // GLY 9 is not in the structure
  ASSERT_EQ(c.points.charges.size(), 8u);
  EXPECT_EQ(c.points.charges[5], 0.33);
  EXPECT_NEAR(c.net_charge, 0.1 - 0.3 - 0.5 - 0.7 + 0.33 + 0.33 - 0.2, 1e-12);
  EXPECT_EQ(c.warnings.size(), 2u);

  ChargeAssignment filled = c;
  std::vector<Atom> with_ion = atoms;
  with_ion[4] = atom("ZN", "ZN", 3, "A", "ZN");  // the unmatched atom is an ion pdb2pqr would drop
  filled = match_pqr_charges(with_ion, pqr, "test.pqr");
  fill_unmatched_with_formal(filled, with_ion);
  EXPECT_EQ(filled.atom_charges[4], 2.0);
  EXPECT_NEAR(filled.net_charge, c.net_charge + 2, 1e-12);
}

TEST(PqrCharges, APqrWithoutChainsMatchesAOneChainStructure) {
  Atom no_chain = charged(atom("NZ", "LYS", 1, ""), 1.0);
  EXPECT_EQ(match_pqr_charges({atom("NZ", "LYS", 1, "A")}, {no_chain}, "x").atoms_charged, 1);
  EXPECT_EQ(match_pqr_charges({atom("NZ", "LYS", 1, "A"), atom("NZ", "LYS", 1, "B")}, {no_chain}, "x").atoms_charged,
            0);
  EXPECT_THROW(match_pqr_charges({atom("NZ", "LYS", 1)}, {atom("NZ", "LYS", 1)}, "x"), std::invalid_argument);
}

TEST(PqrCharges, AFileOfAnotherStructureIsAnError) {
  const auto path = std::filesystem::temp_directory_path() / fmt::format("spheremap-charges-{}.pqr", ::getpid());
  std::ofstream(path) << "ATOM      1  N   ALA A  50      1.000   2.000   3.000 -0.3000 1.8240\n"
                         "ATOM      2  H   ALA A  50      1.500   2.000   3.000  0.3000 0.0000\n";
  try {
    read_pqr_charges({atom("N", "ALA", 1)}, path);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("no atom of the PQR file matches"), std::string::npos) << e.what();
  }
  const ChargeAssignment c = read_pqr_charges({atom("N", "ALA", 50)}, path);
  EXPECT_EQ(c.atom_charges, (std::vector<double>{-0.3}));
  EXPECT_EQ(c.added_hydrogens, 1);  // the zero-radius hydrogen still carries its charge
  EXPECT_NEAR(c.net_charge, 0.0, 1e-15);
  std::filesystem::remove(path);
}

TEST(Pdb2pqrInput, OldDnaNamesAndLongChainNames) {
  std::vector<Atom> atoms = {atom("P", "T", 1, "DNA1"), atom("O2'", "A", 2, "RNA1"), atom("P", "A", 2, "RNA1"),
                             atom("P", "G", 3, "DNA1"), atom("CA", "ALA", 4, "PROT")};
  const Pdb2pqrInput input = pdb2pqr_input(atoms, "x.cif");
  EXPECT_EQ(input.atoms[0].residue_name, "DT");
  EXPECT_EQ(input.atoms[1].residue_name, "A");  // RNA keeps its name
  EXPECT_EQ(input.atoms[3].residue_name, "DG");
  EXPECT_EQ(input.atoms[4].residue_name, "ALA");
  EXPECT_EQ(input.dna_residues_renamed, 2);
  EXPECT_EQ(input.atoms[0].chain, "A");
  EXPECT_EQ(input.atoms[1].chain, "B");
  EXPECT_EQ(input.atoms[4].chain, "C");
  EXPECT_EQ(input.original_chain.at("B"), "RNA1");
  atoms[4].residue_number = 10000;
  EXPECT_THROW(pdb2pqr_input(atoms, "x.cif"), InputError);
  std::vector<Atom> many;
  for (int c = 0; c < 63; ++c) many.push_back(atom("CA", "ALA", 1, fmt::format("C{}", c).c_str()));
  EXPECT_THROW(pdb2pqr_input(many, "x.cif"), InputError);
}

}  // namespace
}  // namespace spheremap
