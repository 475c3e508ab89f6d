// write_ply's float and uchar columns, and the order readers such as Open3D need (red, green, blue last).
#include <gtest/gtest.h>

#include <stdexcept>

#include "../cli/ply_columns.hpp"
#include "../test_support.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

class PlyTypes : public testing_support::FolderTest {};

TEST_F(PlyTypes, FloatAndUcharColumnsInReaderOrder) {
  Mesh mesh = make_icosphere(1);
  const std::size_t n = mesh.vertex_count();
  mesh.real_attributes["vertex_score"] = std::vector<double>(n, 0.1);
  mesh.real_attributes["theta"] = std::vector<double>(n, 0.1);
  for (const char* channel : {"blue", "green", "red"})
    mesh.integer_attributes[channel] = std::vector<std::int32_t>(n, 200);
  mesh.integer_attributes["atomid"] = std::vector<std::int32_t>(n, 7);
  PlyWriteOptions options;
  options.float_attributes = {"vertex_score"};
  options.uchar_attributes = {"red", "green", "blue"};
  write_ply(folder_ / "a.ply", mesh, options);
  const std::string text = testing_support::slurp(folder_ / "a.ply");
  const std::string header = text.substr(0, text.find("end_header"));
  EXPECT_NE(header.find("property double theta\nproperty float vertex_score\nproperty int atomid\n"
                        "property uchar red\nproperty uchar green\nproperty uchar blue\n"),
            std::string::npos)
      << header;
  const auto columns = testing_support::read_ply_columns(folder_ / "a.ply");
  EXPECT_EQ(columns.vertex.at("vertex_score")[0], static_cast<double>(0.1f));
  EXPECT_EQ(columns.vertex.at("theta")[0], 0.1);
  EXPECT_EQ(columns.vertex.at("red")[n - 1], 200);
  EXPECT_EQ(columns.vertex.at("atomid")[n - 1], 7);
  EXPECT_EQ(columns.faces.size(), mesh.triangle_count());

  options.ascii = true;
  write_ply(folder_ / "b.ply", mesh, options);
  EXPECT_NE(testing_support::slurp(folder_ / "b.ply").find(" 0.100000001 "), std::string::npos);

  mesh.integer_attributes["red"][0] = 256;
  EXPECT_THROW(write_ply(folder_ / "c.ply", mesh, options), std::invalid_argument);
  EXPECT_FALSE(std::filesystem::exists(folder_ / "c.ply"));
}

}  // namespace
}  // namespace spheremap
