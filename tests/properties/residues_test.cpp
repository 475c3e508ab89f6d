// Residue tables (Kyte-Doolittle, Wimley-White, Eisenberg), residues and chains, sequence positions.
#include "spheremap/properties/residues.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "spheremap/properties/residue_scales.hpp"

namespace spheremap {
namespace {

Atom atom(const std::string& chain, int number, const std::string& residue, bool hetero = false) {
  Atom a;
  a.chain = chain;
  a.residue_number = number;
  a.residue_name = residue;
  a.hetero = hetero;
  a.name = "CA";
  return a;
}

TEST(ResidueScales, PublishedValues) {
  using enum ResidueScale;
  EXPECT_EQ(residue_scale_value(kKyteDoolittle, "ILE"), 4.5);
  EXPECT_EQ(residue_scale_value(kKyteDoolittle, "ARG"), -4.5);
  EXPECT_EQ(residue_scale_value(kKyteDoolittle, "PRO"), -1.6);
  EXPECT_EQ(residue_scale_value(kKyteDoolittle, "HSE"), -3.2);  // CHARMM's histidine
  EXPECT_EQ(residue_scale_value(kKyteDoolittle, "CYX"), 2.5);
  EXPECT_FALSE(residue_scale_value(kKyteDoolittle, "MSE"));
  EXPECT_FALSE(residue_scale_value(kKyteDoolittle, "NTE"));
  EXPECT_FALSE(residue_scale_value(kKyteDoolittle, "HOH"));
  EXPECT_EQ(residue_scale_value(kWimleyWhite, "TRP"), -1.85);
  EXPECT_EQ(residue_scale_value(kWimleyWhite, "GLU"), 2.02);
  EXPECT_EQ(residue_scale_value(kWimleyWhite, "GLH"), -0.01);
  EXPECT_EQ(residue_scale_value(kEisenberg, "ARG"), -2.53);
  EXPECT_EQ(residue_scale_value(kEisenberg, "ILE"), 1.38);
  EXPECT_EQ(residue_scale_bounds(kKyteDoolittle), std::make_pair(-4.5, 4.5));
}

TEST(Residues, ChainsResiduesAndSequencePositions) {
  const std::vector<Atom> atoms = {atom("A", 1, "MET"), atom("A", 1, "MET"), atom("A", 2, "MSE", true),
                                   atom("A", 3, "GLY"), atom("A", 4, "LYS"), atom("A", 101, "HEM", true),
                                   atom("B", 7, "ALA"), atom("B", 8, "SER")};
  const ResidueIndex index = index_residues(atoms);
  ASSERT_EQ(index.residues.size(), 7u);
  EXPECT_EQ(index.chains, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(index.residue_of_atom[1], 0);
  EXPECT_TRUE(index.residues[1].polymer);   // MSE between ATOM residues
  EXPECT_FALSE(index.residues[4].polymer);  // the haem after the chain's last ATOM residue
  const std::vector<double> position = sequence_positions(index);
  EXPECT_EQ(position[0], 0);
  EXPECT_DOUBLE_EQ(position[1], 1.0 / 3);
  EXPECT_EQ(position[3], 1);
  EXPECT_TRUE(std::isnan(position[4]));
  EXPECT_EQ(position[5], 0);
  EXPECT_EQ(position[6], 1);
  for (std::size_t r = 1; r < 4; ++r) EXPECT_LT(position[r - 1], position[r]);
  EXPECT_EQ(residue_label(index.residues[3]), "A:LYS4");
}

}  // namespace
}  // namespace spheremap
