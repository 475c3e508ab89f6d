// spheremap render / view / locate on a finished output folder, and the pictures `map` writes.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>

#include "../test_support.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/render/plot.hpp"
#include "spheremap/render/projection.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;
using testing_support::run_cli;

Vec3 unit(const Vec3& v) {
  const double n = std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]);
  return {v[0] / n, v[1] / n, v[2] / n};
}

class PictureCommands : public testing_support::FolderTest {
 protected:
  // A finished map folder written by hand: an icosphere of radius 20 (the surface) over the unit one (the
  // globe); vertex v belongs to residue A:(1 + v / 6), B-factor = z.
  void SetUp() override {
    FolderTest::SetUp();
    const Mesh ico = make_icosphere(3);
    Mesh surface;
    surface.triangles = ico.triangles;
    TextAttribute chain{{"A"}, {}}, name{{"ALA"}, {}};
    std::vector<std::int32_t> number, atom;
    std::vector<double> b;
    for (std::size_t v = 0; v < ico.vertex_count(); ++v) {
      const Vec3 u = unit(ico.positions[v]);
      sphere_.push_back(u);
      surface.positions.push_back({20 * u[0], 20 * u[1], 20 * u[2]});
      chain.codes.push_back(0);
      name.codes.push_back(0);
      number.push_back(1 + static_cast<std::int32_t>(v / 6));
      atom.push_back(static_cast<std::int32_t>(v / 2));
      b.push_back(u[2]);
    }
    surface.text_attributes["vertex_chain"] = chain;
    surface.text_attributes["vertex_residue_name"] = name;
    surface.integer_attributes["vertex_residue_number"] = number;
    surface.integer_attributes["atomid"] = atom;
    surface.real_attributes["vertex_b_factor"] = b;
    map_ = folder_ / "map";
    fs::create_directories(map_);
    write_ply(map_ / "surface.ply", surface);
    Mesh sphere = surface;
    sphere.positions = sphere_;
    write_ply(map_ / "sphere.ply", sphere);
    testing_support::write_text(map_ / "report.json", R"({"input": "/data/test.pdb"})");
    surface_ = surface;
  }
  fs::path map_;
  std::vector<Vec3> sphere_;
  Mesh surface_;
};

TEST_F(PictureCommands, TheMapFolderReadsBackWithItsAttributes) {
  const Mesh back = read_ply_mesh(map_ / "surface.ply");
  EXPECT_EQ(back.positions, surface_.positions);
  EXPECT_EQ(back.triangles, surface_.triangles);
  EXPECT_EQ(back.real_attributes, surface_.real_attributes);
  EXPECT_EQ(back.integer_attributes, surface_.integer_attributes);
  ASSERT_EQ(back.text_attributes.count("vertex_chain"), 1u);
  EXPECT_EQ(back.text_attributes.at("vertex_chain").at(100), "A");
  EXPECT_EQ(back.text_attributes.at("vertex_residue_name").at(7), "ALA");
}

TEST_F(PictureCommands, LocateGivesTheResidueOfAVertexAtItsLatitudeAndLongitude) {
  for (const std::size_t v : {0u, 100u, 333u, 641u}) {
    const GeoPoint g = geo_point_of(sphere_[v]);
    const auto run = run_cli(fmt::format("locate {} --lat {:.10f} --lon {:.10f}", map_.string(), g.latitude / kDegree,
                                         g.longitude / kDegree));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find(fmt::format("residue A:{} ALA\n", 1 + v / 6)), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(fmt::format("nearest vertex {}\n", v)), std::string::npos) << run.output;
  }
  const auto where = run_cli("locate " + map_.string() + " --residue A:5");
  EXPECT_EQ(where.exit_code, 0) << where.output;
  EXPECT_NE(where.output.find("residue A:5 ALA: centre latitude"), std::string::npos) << where.output;
  EXPECT_NE(where.output.find("6 vertices"), std::string::npos) << where.output;
  EXPECT_EQ(run_cli("locate " + map_.string() + " --residue B:5").exit_code, 1);
  EXPECT_EQ(run_cli("locate " + map_.string() + " --lat 91 --lon 0").exit_code, 1);
  EXPECT_EQ(run_cli("locate " + map_.string()).exit_code, 1);
  EXPECT_EQ(run_cli("locate " + (folder_ / "nothing").string() + " --residue A:5").exit_code, 1);
}

TEST_F(PictureCommands, RenderWritesThePictureOfTheRequestedSizeAndItsGrid) {
  const auto run = run_cli("render " + map_.string() +
                           " --property b_factor --projection equirectangular --range -0.5,0.5 --size 800x400 "
                           "--outline A:3-20");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const RgbImage image = read_png(map_ / "pictures" / "b_factor-equirectangular.png");
  EXPECT_EQ(image.width, 800);
  EXPECT_EQ(image.height, 400);
  EXPECT_TRUE(fs::exists(map_ / "pictures" / "b_factor-equirectangular.tsv"));
  ASSERT_EQ(run_cli("render " + map_.string() + " --hemispheres --format pdf -o " + (folder_ / "h.pdf").string())
                .exit_code,
            0);
  EXPECT_EQ(testing_support::slurp(folder_ / "h.pdf").substr(0, 5), "%PDF-");
}

TEST_F(PictureCommands, BadRenderOptionsExitOneAndWriteNothing) {
  for (const char* options : {"--property nope", "--range 5,1", "--size 10x10", "--format gif",
                              "--projection mercator", "--outline Z:1", "--outline A:x"}) {
    const auto run = run_cli("render " + map_.string() + " " + options);
    EXPECT_EQ(run.exit_code, 1) << options << ": " << run.output;
    EXPECT_NE(run.output.find("error"), std::string::npos) << options << ": " << run.output;
    EXPECT_FALSE(fs::exists(map_ / "pictures" / "octant-mollweide.png")) << options;
    EXPECT_FALSE(fs::exists(map_ / "pictures" / "nope-mollweide.png")) << options;
  }
}

TEST_F(PictureCommands, ViewWritesTheViewerAndMapWritesPicturesUnlessTold) {
  const auto view = run_cli("view " + map_.string());
  EXPECT_EQ(view.exit_code, 0) << view.output;
  EXPECT_GT(testing_support::slurp(map_ / "index.html").size(), 1000u);

  const Mesh ico = make_icosphere(2);
  write_ply(folder_ / "ball.ply", ico);
  const auto with = run_cli("map " + (folder_ / "ball.ply").string() + " -q -o " + (folder_ / "with").string());
  ASSERT_EQ(with.exit_code, 0) << with.output;
  EXPECT_TRUE(fs::exists(folder_ / "with" / "index.html"));
  EXPECT_TRUE(fs::exists(folder_ / "with" / "pictures" / "octant-mollweide.png"));
  EXPECT_TRUE(fs::exists(folder_ / "with" / "pictures" / "octant-mollweide.tsv"));
  EXPECT_TRUE(fs::exists(folder_ / "with" / "pictures" / "octant-hemispheres.png"));
  const auto without =
      run_cli("map " + (folder_ / "ball.ply").string() + " -q --no-pictures -o " + (folder_ / "without").string());
  ASSERT_EQ(without.exit_code, 0) << without.output;
  EXPECT_TRUE(fs::exists(folder_ / "without" / "sphere.ply"));
  EXPECT_FALSE(fs::exists(folder_ / "without" / "pictures"));
  EXPECT_FALSE(fs::exists(folder_ / "without" / "index.html"));
  // The same input gives the same pictures.
  ASSERT_EQ(run_cli("map " + (folder_ / "ball.ply").string() + " -q -o " + (folder_ / "again").string()).exit_code, 0);
  EXPECT_EQ(testing_support::slurp(folder_ / "with" / "pictures" / "octant-mollweide.png"),
            testing_support::slurp(folder_ / "again" / "pictures" / "octant-mollweide.png"));
  EXPECT_EQ(testing_support::slurp(folder_ / "with" / "pictures" / "octant-hemispheres.png"),
            testing_support::slurp(folder_ / "again" / "pictures" / "octant-hemispheres.png"));
}

}  // namespace
}  // namespace spheremap
