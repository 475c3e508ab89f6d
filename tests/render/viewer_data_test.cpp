// The viewer's data for a mapped surface: atoms from the provenance attributes, properties it carries.
#include "spheremap/render/viewer_data.hpp"

#include <gtest/gtest.h>

#include <stdexcept>

#include "spheremap/attributes.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

Mesh surface_with_provenance() {
  Mesh mesh = make_icosphere(2);
  const std::size_t n = mesh.vertex_count();
  auto& atom = mesh.integer_attributes[attributes::kAtomId];
  auto& number = mesh.integer_attributes[attributes::kResidueNumber];
  auto& b = mesh.real_attributes[attributes::kBFactor];
  TextAttribute chain{{"A", "B"}, {}}, name{{"CA", "N"}, {}}, residue{{"GLY"}, {}}, insertion{{"", "A"}, {}};
  for (std::size_t v = 0; v < n; ++v) {
    atom.push_back(static_cast<std::int32_t>(100 - v % 7));  // atom ids need not start at 0 or be in order
    number.push_back(static_cast<std::int32_t>(v % 7) + 10);
    b.push_back(static_cast<double>(v % 7) * 2);
    chain.codes.push_back(v % 7 < 3 ? 0 : 1);
    name.codes.push_back(v % 7 == 0 ? 1 : 0);
    residue.codes.push_back(0);
    insertion.codes.push_back(v % 7 == 6 ? 1 : 0);
  }
  mesh.text_attributes[attributes::kChain] = chain;
  mesh.text_attributes[attributes::kAtomName] = name;
  mesh.text_attributes[attributes::kResidueName] = residue;
  mesh.text_attributes[attributes::kInsertionCode] = insertion;
  return mesh;
}

TEST(ViewerData, AtomsComeFromTheProvenanceAttributes) {
  const Mesh mesh = surface_with_provenance();
  const ViewerData data = viewer_data_for_map(mesh, mesh.positions, "t");
  ASSERT_EQ(data.atoms.size(), 7u);
  ASSERT_EQ(data.vertex_atoms.size(), mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const ViewerAtom& a = data.atoms[data.vertex_atoms[v]];
    EXPECT_EQ(data.vertex_atoms[v], static_cast<std::int32_t>(v % 7));  // first appearance order
    EXPECT_EQ(a.residue_number, static_cast<std::int32_t>(v % 7) + 10);
    EXPECT_EQ(a.chain, v % 7 < 3 ? "A" : "B");
    EXPECT_EQ(a.atom_name, v % 7 == 0 ? "N" : "CA");
    EXPECT_EQ(a.residue_name, "GLY");
    EXPECT_EQ(a.insertion_code, v % 7 == 6 ? "A" : "");
  }
  EXPECT_EQ(data.title, "t");
  EXPECT_EQ(data.triangles, mesh.triangles);
}

TEST(ViewerData, PropertiesAreTheOnesTheSurfaceCarries) {
  const Mesh mesh = surface_with_provenance();
  const ViewerData data = viewer_data_for_map(mesh, mesh.positions, "t");
  ASSERT_EQ(data.properties.size(), 4u);
  EXPECT_EQ(data.properties[0].name, "octant");
  EXPECT_EQ(data.properties[1].name, "chain");
  EXPECT_EQ(data.properties[2].name, "residue number");
  EXPECT_EQ(data.properties[3].name, "B-factor");
  EXPECT_EQ(data.properties[3].unit, "Å²");
  EXPECT_EQ(data.properties[1].categories, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(data.properties[1].scale, ScaleKind::categorical);
  EXPECT_EQ(data.properties[3].range.lo, 0);
  EXPECT_EQ(data.properties[3].range.hi, 12);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    const Vec3& s = mesh.positions[v];
    EXPECT_EQ(data.properties[0].values[v], (s[0] < 0) + 2 * (s[1] < 0) + 4 * (s[2] < 0));
    EXPECT_EQ(data.properties[1].values[v], v % 7 < 3 ? 0 : 1);
  }
  EXPECT_NO_THROW((void)viewer_html(data));
}

TEST(ViewerData, APlainMeshHasNoAtomsAndOnlyOctants) {
  Mesh mesh = make_icosphere(1);
  mesh.real_attributes[attributes::kCharge] = std::vector<double>(mesh.vertex_count(), -0.5);
  const ViewerData data = viewer_data_for_map(mesh, mesh.positions, "mesh");
  EXPECT_TRUE(data.atoms.empty());
  EXPECT_TRUE(data.vertex_atoms.empty());
  ASSERT_EQ(data.properties.size(), 2u);
  EXPECT_EQ(data.properties[1].name, "charge");
  EXPECT_EQ(data.properties[1].scale, ScaleKind::diverging);
  EXPECT_EQ(data.properties[1].range.lo, -0.5);
  EXPECT_EQ(data.properties[1].range.hi, 0.5);
  EXPECT_NO_THROW((void)viewer_html(data));
  EXPECT_THROW((void)viewer_data_for_map(mesh, {}, "x"), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
