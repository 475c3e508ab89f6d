// write_glb checked by a reader of its own (no Khronos validator offline): the GLB header and chunks, the
// buffer views' alignment and extents, every accessor's size, POSITION's min and max against the data,
// indices in range, colours and a custom attribute with a missing value.
#include "spheremap/io/gltf.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <limits>

#include <nlohmann/json.hpp>

#include "../test_support.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

class Gltf : public testing_support::FolderTest {};

std::uint32_t u32(const std::string& bytes, std::size_t at) {
  std::uint32_t v = 0;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

float f32(const std::string& bytes, std::size_t at) {
  float v = 0;
  std::memcpy(&v, bytes.data() + at, 4);
  return v;
}

TEST_F(Gltf, WritesAValidBinaryGltf) {
  const Mesh sphere = make_icosphere(2);
  GlbMesh glb;
  glb.name = "sphere";
  glb.positions = sphere.positions;
  for (auto& p : glb.positions) p = {3 * p[0] + 10, 3 * p[1], 3 * p[2] - 5};
  glb.normals = sphere.positions;
  glb.triangles = sphere.triangles;
  glb.colours.assign(sphere.vertex_count(), {10, 20, 30});
  std::vector<double> score(sphere.vertex_count(), 0.25);
  score[1] = std::numeric_limits<double>::quiet_NaN();
  glb.attributes.emplace_back(glb_attribute_name("shape_index"), score);
  write_glb(folder_ / "a.glb", glb);
  const std::string bytes = testing_support::slurp(folder_ / "a.glb");

  // Header and chunks.
  ASSERT_GE(bytes.size(), 28u);
  EXPECT_EQ(bytes.substr(0, 4), "glTF");
  EXPECT_EQ(u32(bytes, 4), 2u);
  EXPECT_EQ(u32(bytes, 8), bytes.size());
  const std::uint32_t json_length = u32(bytes, 12);
  EXPECT_EQ(json_length % 4, 0u);
  EXPECT_EQ(bytes.substr(16, 4), "JSON");
  const auto gltf = nlohmann::json::parse(bytes.substr(20, json_length));
  const std::size_t bin_header = 20 + json_length;
  const std::uint32_t bin_length = u32(bytes, bin_header);
  EXPECT_EQ(bin_length % 4, 0u);
  EXPECT_EQ(bytes.substr(bin_header + 4, 4), std::string("BIN\0", 4));
  EXPECT_EQ(bin_header + 8 + bin_length, bytes.size());
  const std::string bin = bytes.substr(bin_header + 8);
  EXPECT_EQ(gltf["asset"]["version"], "2.0");
  EXPECT_EQ(gltf["buffers"][0]["byteLength"], bin_length);

  // Buffer views: aligned, inside the buffer; accessors: exactly their view.
  for (const auto& view : gltf["bufferViews"]) {
    EXPECT_EQ(view["byteOffset"].get<std::size_t>() % 4, 0u);
    EXPECT_LE(view["byteOffset"].get<std::size_t>() + view["byteLength"].get<std::size_t>(), bin_length);
  }
  const auto components = [](const std::string& type) { return type == "VEC3" ? 3u : type == "VEC4" ? 4u : 1u; };
  for (const auto& a : gltf["accessors"]) {
    const auto& view = gltf["bufferViews"][a["bufferView"].get<std::size_t>()];
    const std::size_t size = a["componentType"] == 5121 ? 1 : 4;
    EXPECT_EQ(a["count"].get<std::size_t>() * size * components(a["type"]), view["byteLength"].get<std::size_t>());
  }
  const auto& primitive = gltf["meshes"][0]["primitives"][0];
  EXPECT_EQ(primitive["mode"], 4);
  const auto& attributes = primitive["attributes"];
  for (const char* name : {"POSITION", "NORMAL", "COLOR_0", "_SHAPE_INDEX"}) ASSERT_TRUE(attributes.contains(name));
  const auto offset_of = [&](const nlohmann::json& accessor) {
    return gltf["bufferViews"][accessor["bufferView"].get<std::size_t>()]["byteOffset"].get<std::size_t>();
  };

  // POSITION: min and max are those of the floats written.
  const auto& position = gltf["accessors"][attributes["POSITION"].get<std::size_t>()];
  for (std::size_t k = 0; k < 3; ++k) {
    float lo = std::numeric_limits<float>::infinity(), hi = -lo;
    for (std::size_t v = 0; v < glb.positions.size(); ++v) {
      const float x = f32(bin, offset_of(position) + 12 * v + 4 * k);
      EXPECT_EQ(x, static_cast<float>(glb.positions[v][k]));
      lo = std::min(lo, x), hi = std::max(hi, x);
    }
    EXPECT_EQ(position["min"][k].get<float>(), lo);
    EXPECT_EQ(position["max"][k].get<float>(), hi);
  }
  // Colours, the attribute (NaN as the missing value), indices.
  const auto& colour = gltf["accessors"][attributes["COLOR_0"].get<std::size_t>()];
  EXPECT_TRUE(colour["normalized"].get<bool>());
  EXPECT_EQ(static_cast<unsigned char>(bin[offset_of(colour) + 4 * 7 + 2]), 30);
  EXPECT_EQ(static_cast<unsigned char>(bin[offset_of(colour) + 4 * 7 + 3]), 255);
  const auto& shape = gltf["accessors"][attributes["_SHAPE_INDEX"].get<std::size_t>()];
  EXPECT_EQ(f32(bin, offset_of(shape)), 0.25F);
  EXPECT_EQ(f32(bin, offset_of(shape) + 4), kGlbMissingValue);
  EXPECT_EQ(shape["extras"]["missing_value"].get<float>(), kGlbMissingValue);
  const auto& indices = gltf["accessors"][primitive["indices"].get<std::size_t>()];
  EXPECT_EQ(indices["componentType"], 5125);
  EXPECT_EQ(indices["count"], 3 * glb.triangles.size());
  for (std::size_t i = 0; i < 3 * glb.triangles.size(); ++i)
    EXPECT_EQ(u32(bin, offset_of(indices) + 4 * i), static_cast<std::uint32_t>(glb.triangles[i / 3][i % 3]));

  // Deterministic; bad input writes nothing.
  write_glb(folder_ / "b.glb", glb);
  EXPECT_EQ(testing_support::slurp(folder_ / "b.glb"), bytes);
  glb.attributes.emplace_back("NO_UNDERSCORE", score);
  EXPECT_THROW(write_glb(folder_ / "c.glb", glb), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(folder_ / "c.glb"));
  EXPECT_EQ(glb_attribute_name("electrostatics"), "_ELECTROSTATICS");
}

}  // namespace
}  // namespace spheremap
