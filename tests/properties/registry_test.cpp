// The property registry: names, lookup, and compute_properties on a small structure with known answers.
#include "spheremap/properties/registry.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"
#include "spheremap/properties/residue_scales.hpp"
#include "spheremap/properties/shape.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

// An icosphere whose vertices belong, by octant, to the atoms of three residues of two chains (a vertex's
// atom: its octant mod 4).
struct Toy {
  Mesh mesh = make_icosphere(3);
  std::vector<Atom> atoms;
  Toy() {
    const std::vector<std::tuple<std::string, int, std::string>> residues = {
        {"A", 1, "ILE"}, {"A", 2, "PRO"}, {"A", 3, "MSE"}, {"B", 1, "ARG"}};
    for (const auto& [chain, number, name] : residues) {
      Atom a;
      a.chain = chain, a.residue_number = number, a.residue_name = name, a.name = "CA", a.radius = 1.7;
      a.b_factor = 10.0 * number;
      atoms.push_back(a);
    }
    auto& ids = mesh.integer_attributes[attributes::kAtomId];
    for (const auto& p : mesh.positions) ids.push_back((p[0] < 0) + 2 * (p[1] < 0));
  }
};

const SurfaceProperty& named(const PropertySet& set, const std::string& name) {
  for (const auto& p : set.properties)
    if (p.info.name == name) return p;
  throw std::runtime_error("no property " + name);
}

TEST(Registry, NamesUnitsAndLookup) {
  ASSERT_NE(find_property("electrostatics"), nullptr);
  EXPECT_EQ(find_property("electrostatics")->unit, "kT/e");
  EXPECT_EQ(find_property("electrostatics")->scale, ScaleKind::diverging);
  EXPECT_EQ(find_property("octant")->scale, ScaleKind::categorical);
  EXPECT_EQ(find_property("conservation"), nullptr);
  EXPECT_EQ(property_registry().front().info.name, "electrostatics");
}

TEST(Registry, PerAtomPropertiesFollowAtomIdAndTheTables) {
  const Toy toy;
  PropertyOptions options;
  options.only = std::vector<std::string>{"hydrophobicity", "sequence_position", "chain_index",
                                          "b_factor",       "shape_index",       "octant"};
  const std::vector<Vec3> sphere = toy.mesh.positions;
  PropertyInputs inputs{&toy.mesh, &toy.atoms, {}, &sphere};
  const PropertySet set = compute_properties(inputs, options);
  ASSERT_EQ(set.properties.size(), 6u);
  EXPECT_EQ(set.properties.back().info.name, "octant");  // registry order
  const auto& ids = toy.mesh.integer_attributes.at(attributes::kAtomId);
  const auto& kd = named(set, "hydrophobicity").values;
  const auto& position = named(set, "sequence_position").values;
  for (std::size_t v = 0; v < toy.mesh.vertex_count(); ++v) {
    const Atom& atom = toy.atoms[static_cast<std::size_t>(ids[v])];
    const auto table = residue_scale_value(ResidueScale::kKyteDoolittle, atom.residue_name);
    if (table) {
      EXPECT_EQ(kd[v], *table) << v;
    } else {
      EXPECT_TRUE(std::isnan(kd[v])) << v;  // MSE: no value, never a made-up zero
    }
    EXPECT_EQ(position[v], (std::vector<double>{0, 0.5, 1, 0})[static_cast<std::size_t>(ids[v])]) << v;
    EXPECT_EQ(named(set, "b_factor").values[v], *atom.b_factor);
    EXPECT_EQ(named(set, "chain_index").values[v], atom.chain == "A" ? 0 : 1);
    EXPECT_EQ(named(set, "octant").values[v], octant_of(sphere[v]));
    EXPECT_NEAR(named(set, "shape_index").values[v], 1, 0.05);  // a sphere is a cap everywhere
  }
  EXPECT_EQ(named(set, "chain_index").info.categories, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(set.report.unknown_residues.residues, 1);
  EXPECT_EQ(set.report.unknown_residues.names, std::vector<std::string>{"MSE"});
  ASSERT_EQ(set.report.warnings.size(), 1u);
  EXPECT_NE(set.report.warnings[0].find("MSE"), std::string::npos);
}

TEST(Registry, MeshWithoutAtomsGetsShapeAndMapProperties) {
  const Toy toy;
  const std::vector<Vec3> sphere = toy.mesh.positions;
  PropertySet set = compute_properties({&toy.mesh, nullptr, {}, nullptr}, {});
  std::vector<std::string> names;
  for (const auto& p : set.properties) names.push_back(p.info.name);
  EXPECT_EQ(names, (std::vector<std::string>{"shape_index", "curvedness"}));
  add_map_properties(set, toy.mesh, sphere, {});
  ASSERT_EQ(set.properties.size(), 4u);
  EXPECT_EQ(set.properties[2].info.name, "area_distortion");
  EXPECT_EQ(colour_property(set.properties, "")->info.name, "octant");
  EXPECT_EQ(colour_property(set.properties, "curvedness")->info.name, "curvedness");
  EXPECT_THROW(colour_property(set.properties, "electrostatics"), InputError);
}

TEST(Registry, UnknownNamesAndMissingSurfaceAreRefused) {
  const Toy toy;
  PropertyOptions options;
  options.only = std::vector<std::string>{"hydrophobicty"};
  EXPECT_THROW(compute_properties({&toy.mesh, &toy.atoms, {}, nullptr}, options), InputError);
  EXPECT_THROW(compute_properties({}, {}), std::invalid_argument);
  options.only.reset();
  options.values_files = {"values.csv"};
  EXPECT_THROW(compute_properties({&toy.mesh, nullptr, {}, nullptr}, options), InputError);  // a mesh has no atoms
}

}  // namespace
}  // namespace spheremap
