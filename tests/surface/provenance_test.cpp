#include "spheremap/surface/provenance.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "spheremap/attributes.hpp"

namespace spheremap {
namespace {

Atom make_atom(std::int32_t serial, const char* name, const char* element, const char* residue, std::int32_t number,
               char insertion, const char* chain, std::int32_t model) {
  Atom atom;
  atom.serial = serial;
  atom.name = name;
  atom.element = element;
  atom.residue_name = residue;
  atom.residue_number = number;
  atom.insertion_code = insertion;
  atom.chain = chain;
  atom.model = model;
  return atom;
}

TEST(Provenance, EveryVertexGetsEveryFieldOfItsAtom) {
  const std::vector<Atom> atoms = {make_atom(7, "CA", "C", "LYS", 42, ' ', "A", 1),
                                   make_atom(9, "OG", "O", "SER", 52, 'B', "B", 2)};
  Mesh mesh;
  mesh.positions.resize(4);
  mesh.integer_attributes[attributes::kAtomId] = {1, 0, 1, 1};
  add_atom_provenance(mesh, atoms);
  EXPECT_EQ(mesh.integer_attributes.at(attributes::kAtomSerial), (std::vector<std::int32_t>{9, 7, 9, 9}));
  EXPECT_EQ(mesh.integer_attributes.at(attributes::kResidueNumber), (std::vector<std::int32_t>{52, 42, 52, 52}));
  EXPECT_EQ(mesh.integer_attributes.at(attributes::kModel), (std::vector<std::int32_t>{2, 1, 2, 2}));
  const auto text = [&](const char* name, std::size_t v) { return mesh.text_attributes.at(name).at(v); };
  EXPECT_EQ(text(attributes::kAtomName, 0), "OG");
  EXPECT_EQ(text(attributes::kAtomName, 1), "CA");
  EXPECT_EQ(text(attributes::kElement, 3), "O");
  EXPECT_EQ(text(attributes::kResidueName, 1), "LYS");
  EXPECT_EQ(text(attributes::kInsertionCode, 0), "B");
  EXPECT_EQ(text(attributes::kInsertionCode, 1), "");
  EXPECT_EQ(text(attributes::kChain, 2), "B");
  // Dictionary-coded: two distinct names, not one string per vertex.
  EXPECT_EQ(mesh.text_attributes.at(attributes::kAtomName).dictionary.size(), 2u);
}

// B-factors (PDB, mmCIF) and charges (PQR) follow each vertex's atom; a value the atoms do not have is
// not written (no made-up zeros), and one left from an earlier call is removed.
TEST(Provenance, BFactorsAndChargesFollowTheAtomsThatHaveThem) {
  std::vector<Atom> atoms = {make_atom(7, "CA", "C", "LYS", 42, ' ', "A", 1),
                             make_atom(9, "OG", "O", "SER", 52, ' ', "A", 1)};
  atoms[0].b_factor = 15.23, atoms[1].b_factor = 7.5;
  Mesh mesh;
  mesh.positions.resize(3);
  mesh.integer_attributes[attributes::kAtomId] = {1, 0, 1};
  add_atom_provenance(mesh, atoms);
  EXPECT_EQ(mesh.real_attributes.at(attributes::kBFactor), (std::vector<double>{7.5, 15.23, 7.5}));
  EXPECT_EQ(mesh.real_attributes.count(attributes::kCharge), 0u);
  for (auto& a : atoms) a.b_factor.reset();
  atoms[0].charge = -0.5, atoms[1].charge = 0.25;
  add_atom_provenance(mesh, atoms);
  EXPECT_EQ(mesh.real_attributes.at(attributes::kCharge), (std::vector<double>{0.25, -0.5, 0.25}));
  EXPECT_EQ(mesh.real_attributes.count(attributes::kBFactor), 0u);
  atoms[1].charge.reset();  // not every atom has one: none is written
  add_atom_provenance(mesh, atoms);
  EXPECT_EQ(mesh.real_attributes.count(attributes::kCharge), 0u);
}

TEST(Provenance, RefusesAMeshWithoutValidAtomIndices) {
  Mesh mesh;
  mesh.positions.resize(1);
  EXPECT_THROW(add_atom_provenance(mesh, {}), std::invalid_argument);
  mesh.integer_attributes[attributes::kAtomId] = {3};
  EXPECT_THROW(add_atom_provenance(mesh, {Atom{}}), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
