// spheremap render / view / locate on a finished output folder, and the pictures `map` writes.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "../test_support.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/pipeline/map_folder.hpp"
#include "spheremap/render/plot.hpp"
#include "spheremap/render/projection.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;
using testing_support::run_cli;

// Trp-cage's first six residues (1L2Y, heavy atoms), split into chains A (1-4) and B (5-6); B-factor 10 + residue
// number.
constexpr const char* kPeptide =
    "ATOM      1  N   ASN A   1      -8.901   4.127  -0.555  1.00 11.00           N\n"
    "ATOM      2  CA  ASN A   1      -8.608   3.135  -1.618  1.00 11.00           C\n"
    "ATOM      3  C   ASN A   1      -7.117   2.964  -1.897  1.00 11.00           C\n"
    "ATOM      4  O   ASN A   1      -6.634   1.849  -1.758  1.00 11.00           O\n"
    "ATOM      5  CB  ASN A   1      -9.437   3.396  -2.889  1.00 11.00           C\n"
    "ATOM      6  CG  ASN A   1     -10.915   3.130  -2.611  1.00 11.00           C\n"
    "ATOM      7  OD1 ASN A   1     -11.269   2.700  -1.524  1.00 11.00           O\n"
    "ATOM      8  ND2 ASN A   1     -11.806   3.406  -3.543  1.00 11.00           N\n"
    "ATOM      9  N   LEU A   2      -6.379   4.031  -2.228  1.00 12.00           N\n"
    "ATOM     10  CA  LEU A   2      -4.923   4.002  -2.452  1.00 12.00           C\n"
    "ATOM     11  C   LEU A   2      -4.136   3.187  -1.404  1.00 12.00           C\n"
    "ATOM     12  O   LEU A   2      -3.391   2.274  -1.760  1.00 12.00           O\n"
    "ATOM     13  CB  LEU A   2      -4.411   5.450  -2.619  1.00 12.00           C\n"
    "ATOM     14  CG  LEU A   2      -4.795   6.450  -1.495  1.00 12.00           C\n"
    "ATOM     15  CD1 LEU A   2      -3.612   6.803  -0.599  1.00 12.00           C\n"
    "ATOM     16  CD2 LEU A   2      -5.351   7.748  -2.084  1.00 12.00           C\n"
    "ATOM     17  N   TYR A   3      -4.354   3.455  -0.111  1.00 13.00           N\n"
    "ATOM     18  CA  TYR A   3      -3.690   2.738   0.981  1.00 13.00           C\n"
    "ATOM     19  C   TYR A   3      -4.102   1.256   1.074  1.00 13.00           C\n"
    "ATOM     20  O   TYR A   3      -3.291   0.409   1.442  1.00 13.00           O\n"
    "ATOM     21  CB  TYR A   3      -3.964   3.472   2.302  1.00 13.00           C\n"
    "ATOM     22  CG  TYR A   3      -2.824   3.339   3.290  1.00 13.00           C\n"
    "ATOM     23  CD1 TYR A   3      -2.746   2.217   4.138  1.00 13.00           C\n"
    "ATOM     24  CD2 TYR A   3      -1.820   4.326   3.332  1.00 13.00           C\n"
    "ATOM     25  CE1 TYR A   3      -1.657   2.076   5.018  1.00 13.00           C\n"
    "ATOM     26  CE2 TYR A   3      -0.725   4.185   4.205  1.00 13.00           C\n"
    "ATOM     27  CZ  TYR A   3      -0.639   3.053   5.043  1.00 13.00           C\n"
    "ATOM     28  OH  TYR A   3       0.433   2.881   5.861  1.00 13.00           O\n"
    "ATOM     29  N   ILE A   4      -5.342   0.925   0.689  1.00 14.00           N\n"
    "ATOM     30  CA  ILE A   4      -5.857  -0.449   0.613  1.00 14.00           C\n"
    "ATOM     31  C   ILE A   4      -5.089  -1.221  -0.470  1.00 14.00           C\n"
    "ATOM     32  O   ILE A   4      -4.621  -2.334  -0.226  1.00 14.00           O\n"
    "ATOM     33  CB  ILE A   4      -7.386  -0.466   0.343  1.00 14.00           C\n"
    "ATOM     34  CG1 ILE A   4      -8.197   0.540   1.197  1.00 14.00           C\n"
    "ATOM     35  CG2 ILE A   4      -7.959  -1.884   0.501  1.00 14.00           C\n"
    "ATOM     36  CD1 ILE A   4      -8.019   0.412   2.715  1.00 14.00           C\n"
    "ATOM     37  N   GLN B   5      -4.907  -0.601  -1.645  1.00 15.00           N\n"
    "ATOM     38  CA  GLN B   5      -4.122  -1.167  -2.743  1.00 15.00           C\n"
    "ATOM     39  C   GLN B   5      -2.629  -1.321  -2.390  1.00 15.00           C\n"
    "ATOM     40  O   GLN B   5      -1.986  -2.240  -2.884  1.00 15.00           O\n"
    "ATOM     41  CB  GLN B   5      -4.292  -0.313  -4.013  1.00 15.00           C\n"
    "ATOM     42  CG  GLN B   5      -4.244  -1.171  -5.290  1.00 15.00           C\n"
    "ATOM     43  CD  GLN B   5      -5.576  -1.860  -5.585  1.00 15.00           C\n"
    "ATOM     44  OE1 GLN B   5      -5.769  -3.044  -5.335  1.00 15.00           O\n"
    "ATOM     45  NE2 GLN B   5      -6.532  -1.146  -6.152  1.00 15.00           N\n"
    "ATOM     46  N   TRP B   6      -2.074  -0.459  -1.528  1.00 16.00           N\n"
    "ATOM     47  CA  TRP B   6      -0.716  -0.631  -0.993  1.00 16.00           C\n"
    "ATOM     48  C   TRP B   6      -0.631  -1.766   0.044  1.00 16.00           C\n"
    "ATOM     49  O   TRP B   6       0.295  -2.579  -0.004  1.00 16.00           O\n"
    "ATOM     50  CB  TRP B   6      -0.221   0.703  -0.417  1.00 16.00           C\n"
    "ATOM     51  CG  TRP B   6       1.148   0.652   0.194  1.00 16.00           C\n"
    "ATOM     52  CD1 TRP B   6       2.319   0.664  -0.482  1.00 16.00           C\n"
    "ATOM     53  CD2 TRP B   6       1.508   0.564   1.606  1.00 16.00           C\n"
    "ATOM     54  NE1 TRP B   6       3.371   0.560   0.411  1.00 16.00           N\n"
    "ATOM     55  CE2 TRP B   6       2.928   0.515   1.710  1.00 16.00           C\n"
    "ATOM     56  CE3 TRP B   6       0.779   0.524   2.812  1.00 16.00           C\n"
    "ATOM     57  CZ2 TRP B   6       3.599   0.445   2.938  1.00 16.00           C\n"
    "ATOM     58  CZ3 TRP B   6       1.439   0.433   4.053  1.00 16.00           C\n"
    "ATOM     59  CH2 TRP B   6       2.842   0.407   4.120  1.00 16.00           C\n";

// One row of atoms.csv per atom: its fields by column name.
std::vector<std::map<std::string, std::string>> read_atoms_csv(const fs::path& path) {
  std::istringstream text(testing_support::slurp(path));
  std::vector<std::map<std::string, std::string>> rows;
  std::vector<std::string> header;
  for (std::string line; std::getline(text, line);) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    std::vector<std::string> fields;
    std::istringstream split(line);
    for (std::string field; std::getline(split, field, ',');) fields.push_back(field);
    if (header.empty()) {
      header = fields;
      continue;
    }
    std::map<std::string, std::string> row;
    for (std::size_t k = 0; k < header.size(); ++k) row[header[k]] = k < fields.size() ? fields[k] : "";
    rows.push_back(row);
  }
  return rows;
}

class PictureCommands : public testing_support::FolderTest {
 protected:
  // A finished map folder as `spheremap map` writes it today (properties as PLY floats, the provenance in
  // atoms.csv by atomid), so that the commands are tested on the layout users have.
  void SetUp() override {
    FolderTest::SetUp();
    testing_support::write_text(folder_ / "peptide.pdb", kPeptide);
    map_ = folder_ / "map";
    const auto run = run_cli("map " + (folder_ / "peptide.pdb").string() + " -q --no-pictures -o " + map_.string());
    ASSERT_EQ(run.exit_code, 0) << run.output;
    surface_ = read_ply_mesh(map_ / "surface.ply");
    sphere_ = read_ply_mesh(map_ / "sphere.ply").positions;
    atoms_ = read_atoms_csv(map_ / "atoms.csv");
    ASSERT_EQ(surface_.integer_attributes.count("atomid"), 1u);
  }
  // "A:3 TYR": the residue of vertex v's atom, as atoms.csv names it.
  std::string residue_of(std::size_t v) const {
    const auto& atom = atoms_.at(static_cast<std::size_t>(surface_.integer_attributes.at("atomid")[v]));
    return atom.at("chain") + ":" + atom.at("residue_number") + " " + atom.at("residue_name");
  }
  fs::path map_;
  std::vector<Vec3> sphere_;
  Mesh surface_;
  std::vector<std::map<std::string, std::string>> atoms_;
};

TEST_F(PictureCommands, TheMapFolderReadsBackWithItsResiduesAndProperties) {
  const MapFolder map = read_map_folder(map_);
  EXPECT_EQ(map.surface.positions, surface_.positions);
  EXPECT_EQ(map.sphere, sphere_);
  EXPECT_TRUE(map.no_residues_reason.empty());
  // The provenance joined from atoms.csv by atomid.
  ASSERT_EQ(map.surface.text_attributes.count("vertex_chain"), 1u);
  ASSERT_EQ(map.surface.integer_attributes.count("vertex_residue_number"), 1u);
  for (std::size_t v = 0; v < map.surface.vertex_count(); v += 37)
    EXPECT_EQ(map.surface.text_attributes.at("vertex_chain").at(v) + ":" +
                  std::to_string(map.surface.integer_attributes.at("vertex_residue_number")[v]) + " " +
                  map.surface.text_attributes.at("vertex_residue_name").at(v),
              residue_of(v))
        << v;
  // Every property of the report, with the PLY's values and the registry's scale and unit.
  const auto report = nlohmann::json::parse(testing_support::slurp(map_ / "report.json"));
  ASSERT_EQ(map.properties.size(), report["properties"].size());
  for (const SurfaceProperty& p : map.properties) {
    EXPECT_TRUE(report["properties"].contains(p.info.name)) << p.info.name;
    const auto& column = surface_.real_attributes.at("vertex_" + p.info.name);
    ASSERT_EQ(p.values.size(), column.size());
    for (std::size_t v = 0; v < column.size(); ++v)
      if (!std::isnan(column[v])) EXPECT_EQ(p.values[v], column[v]) << p.info.name;
  }
  EXPECT_EQ(map.properties.front().info.name, "electrostatics");  // the registry's order
  const auto chain = std::find_if(map.properties.begin(), map.properties.end(),
                                  [](const SurfaceProperty& p) { return p.info.name == "chain_index"; });
  ASSERT_NE(chain, map.properties.end());
  EXPECT_EQ(chain->info.categories, (std::vector<std::string>{"A", "B"}));
  EXPECT_EQ(chain->info.scale, ScaleKind::categorical);
}

TEST_F(PictureCommands, AStructureFolderWithoutAtomsCsvSaysSo) {
  fs::remove(map_ / "atoms.csv");
  const auto run = run_cli("locate " + map_.string() + " --residue A:3");
  EXPECT_EQ(run.exit_code, 1) << run.output;
  EXPECT_NE(run.output.find("has no atoms.csv"), std::string::npos) << run.output;
  EXPECT_EQ(run.output.find("mesh file"), std::string::npos) << run.output;
  // What needs no residue still works.
  EXPECT_EQ(
      run_cli("render " + map_.string() + " --property hydrophobicity -o " + (folder_ / "h.png").string()).exit_code,
      0);
}

TEST_F(PictureCommands, LocateGivesTheResidueOfAVertexAtItsLatitudeAndLongitude) {
  for (const std::size_t v : {0u, 100u, 333u, 641u, 1000u}) {
    ASSERT_LT(v, sphere_.size());
    const GeoPoint g = geo_point_of(sphere_[v]);
    const auto run = run_cli(fmt::format("locate {} --lat {:.10f} --lon {:.10f}", map_.string(), g.latitude / kDegree,
                                         g.longitude / kDegree));
    EXPECT_EQ(run.exit_code, 0) << run.output;
    EXPECT_NE(run.output.find(fmt::format("residue {}\n", residue_of(v))), std::string::npos) << run.output;
    EXPECT_NE(run.output.find(fmt::format("nearest vertex {}\n", v)), std::string::npos) << run.output;
    EXPECT_NE(run.output.find("\nhydrophobicity "), std::string::npos) << run.output;
  }
  std::size_t on_a3 = 0;
  for (std::size_t v = 0; v < surface_.vertex_count(); ++v) on_a3 += residue_of(v).rfind("A:3 ", 0) == 0;
  ASSERT_GT(on_a3, 0u);
  const auto where = run_cli("locate " + map_.string() + " --residue A:3");
  EXPECT_EQ(where.exit_code, 0) << where.output;
  EXPECT_NE(where.output.find("residue A:3 TYR: centre latitude"), std::string::npos) << where.output;
  EXPECT_NE(where.output.find(fmt::format("; {} vertices", on_a3)), std::string::npos) << where.output;
  EXPECT_EQ(run_cli("locate " + map_.string() + " --residue B:2").exit_code, 1);
  EXPECT_EQ(run_cli("locate " + map_.string() + " --lat 91 --lon 0").exit_code, 1);
  EXPECT_EQ(run_cli("locate " + map_.string()).exit_code, 1);
  EXPECT_EQ(run_cli("locate " + (folder_ / "nothing").string() + " --residue A:3").exit_code, 1);
}

TEST_F(PictureCommands, RenderWritesThePictureOfTheRequestedSizeAndItsGrid) {
  const auto run = run_cli("render " + map_.string() +
                           " --property b_factor --projection equirectangular --range 10,17 --size 800x400 "
                           "--outline A:3-4,B:6");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const RgbImage image = read_png(map_ / "pictures" / "b_factor-equirectangular.png");
  EXPECT_EQ(image.width, 800);
  EXPECT_EQ(image.height, 400);
  EXPECT_TRUE(fs::exists(map_ / "pictures" / "b_factor-equirectangular.tsv"));
  ASSERT_EQ(
      run_cli("render " + map_.string() + " --hemispheres --format pdf -o " + (folder_ / "h.pdf").string()).exit_code,
      0);
  EXPECT_EQ(testing_support::slurp(folder_ / "h.pdf").substr(0, 5), "%PDF-");
  const auto trace = run_cli("render " + map_.string() + " --hemispheres --trace --property sequence_position -o " +
                             (folder_ / "t.png").string());
  EXPECT_EQ(trace.exit_code, 0) << trace.output;
}

TEST_F(PictureCommands, BadRenderOptionsExitOneAndWriteNothing) {
  for (const char* options : {"--property nope", "--range 5,1", "--size 10x10", "--format gif", "--projection mercator",
                              "--outline Z:1", "--outline A:x"}) {
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
  // A structure: maps of the default properties only (render draws the others), two hemisphere figures.
  const auto peptide =
      run_cli("map " + (folder_ / "peptide.pdb").string() + " -q -o " + (folder_ / "peptide").string());
  ASSERT_EQ(peptide.exit_code, 0) << peptide.output;
  std::set<std::string> pictures;
  for (const auto& entry : fs::directory_iterator(folder_ / "peptide" / "pictures"))
    pictures.insert(entry.path().filename().string());
  std::set<std::string> expected{"electrostatics-hemispheres.png", "octant-hemispheres.png"};
  for (const char* name : {"electrostatics", "hydrophobicity", "sequence_position", "octant"})
    for (const char* ext : {".png", ".tsv"}) expected.insert(std::string(name) + "-mollweide" + ext);
  EXPECT_EQ(pictures, expected);
  // The same input gives the same pictures.
  ASSERT_EQ(run_cli("map " + (folder_ / "ball.ply").string() + " -q -o " + (folder_ / "again").string()).exit_code, 0);
  EXPECT_EQ(testing_support::slurp(folder_ / "with" / "pictures" / "octant-mollweide.png"),
            testing_support::slurp(folder_ / "again" / "pictures" / "octant-mollweide.png"));
  EXPECT_EQ(testing_support::slurp(folder_ / "with" / "pictures" / "octant-hemispheres.png"),
            testing_support::slurp(folder_ / "again" / "pictures" / "octant-hemispheres.png"));
}

// batch writes each run's pictures and viewer as `map` does (the same bytes), before report.json; --no-pictures
// turns them off, and a root made with it refuses to resume with pictures.
TEST_F(PictureCommands, BatchWritesThePicturesMapWritesUnlessTold) {
  const fs::path inputs = folder_ / "inputs";
  fs::create_directories(inputs);
  testing_support::write_text(inputs / "peptide.pdb", kPeptide);
  write_ply(inputs / "ball.ply", make_icosphere(2));
  const auto batch = run_cli("batch " + inputs.string() + " -q --jobs 2 -o " + (folder_ / "b").string());
  ASSERT_EQ(batch.exit_code, 0) << batch.output;
  const auto map = run_cli("map " + (inputs / "peptide.pdb").string() + " -q -o " + (folder_ / "m").string());
  ASSERT_EQ(map.exit_code, 0) << map.output;
  std::set<std::string> pictures;
  for (const auto& entry : fs::directory_iterator(folder_ / "b" / "peptide" / "pictures"))
    pictures.insert(entry.path().filename().string());
  EXPECT_EQ(pictures.size(), 10u);
  for (const std::string& name : pictures)
    EXPECT_EQ(testing_support::slurp(folder_ / "b" / "peptide" / "pictures" / name),
              testing_support::slurp(folder_ / "m" / "pictures" / name))
        << name;
  EXPECT_EQ(testing_support::slurp(folder_ / "b" / "peptide" / "index.html"),
            testing_support::slurp(folder_ / "m" / "index.html"));
  EXPECT_TRUE(fs::exists(folder_ / "b" / "ball" / "pictures" / "octant-mollweide.png"));
  EXPECT_TRUE(fs::exists(folder_ / "b" / "ball" / "index.html"));

  const auto without = run_cli("batch " + inputs.string() + " -q --no-pictures -o " + (folder_ / "n").string());
  ASSERT_EQ(without.exit_code, 0) << without.output;
  EXPECT_TRUE(fs::exists(folder_ / "n" / "peptide" / "report.json"));
  EXPECT_FALSE(fs::exists(folder_ / "n" / "peptide" / "pictures"));
  EXPECT_FALSE(fs::exists(folder_ / "n" / "ball" / "index.html"));
  const auto resumed = run_cli("batch " + inputs.string() + " -q -o " + (folder_ / "n").string());
  EXPECT_EQ(resumed.exit_code, 1) << resumed.output;
  EXPECT_NE(resumed.output.find("pictures"), std::string::npos) << resumed.output;
}

}  // namespace
}  // namespace spheremap
