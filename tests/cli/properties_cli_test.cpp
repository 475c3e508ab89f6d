// The surface properties as a user gets them from `spheremap map`: PLY columns, atoms.csv, residues.csv,
// report.json, --values, a PQR's charges and hydrogens, a potential map, bad input (exit 1, nothing written),
// and the PLY files read by the Python tools users have.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>
#include <sstream>

#include <nlohmann/json.hpp>

#include "../test_support.hpp"
#include "ply_columns.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;
using testing_support::read_ply_columns;
using testing_support::run_cli;
using testing_support::slurp;
using testing_support::write_text;

class Properties : public testing_support::FolderTest {};

// Four heavy atoms and a hydrogen of radius 0 (as pdb2pqr's AMBER output has them), charges summing to 0.
constexpr const char* kPqr =
    "ATOM      1  N   SER A   1       0.000   0.000   0.000 -0.3000 1.8240\n"
    "ATOM      2  CA  SER A   1       1.450   0.000   0.000  0.1000 1.9080\n"
    "ATOM      3  OG  SER A   1       2.000   1.300   0.000 -0.6000 1.7210\n"
    "ATOM      4  HG  SER A   1       2.900   1.300   0.300  0.4000 0.0000\n"
    "ATOM      5  C   SER A   1       2.000  -0.700   1.200  0.4000 1.9080\n";

// An OpenDX map of `value` everywhere on a 3 x 3 x 3 grid from -20 to 20 Å (`items` data values written).
std::string constant_dx(double value, int items) {
  std::ostringstream dx;
  dx << "object 1 class gridpositions counts 3 3 3\norigin -20 -20 -20\ndelta 20 0 0\ndelta 0 20 0\ndelta 0 0 20\n"
     << "object 2 class gridconnections counts 3 3 3\nobject 3 class array type double rank 0 items " << items
     << " data follows\n";
  for (int k = 0; k < items; ++k) dx << value << (k % 3 == 2 ? "\n" : " ");
  dx << "\nattribute \"dep\" string \"positions\"\nobject \"regular positions regular connections\" class field\n"
     << "component \"positions\" value 1\ncomponent \"connections\" value 2\ncomponent \"data\" value 3\n";
  return dx.str();
}

TEST_F(Properties, PqrKeepsItsHydrogensChargesAndPotentialMap) {
  write_text(folder_ / "ser.pqr", kPqr);
  const std::string pqr = (folder_ / "ser.pqr").string();
  const auto run = run_cli("map " + pqr + " -o " + (folder_ / "out").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const auto surface = read_ply_columns(folder_ / "out" / "surface.ply");
  // The hydrogen (radius 0) is atom 3 of atoms.csv but owns no vertex.
  EXPECT_NE(slurp(folder_ / "out" / "atoms.csv").find("\r\n3,4,1,A,1,,SER,HG,H,"), std::string::npos);
  for (const double id : surface.vertex.at("atomid")) EXPECT_NE(id, 3);
  ASSERT_TRUE(surface.vertex.count("vertex_charge"));
  const auto report = nlohmann::json::parse(slurp(folder_ / "out" / "report.json"));
  const auto& e = report["properties"]["electrostatics"];
  EXPECT_EQ(e["unit"], "kT/e");
  EXPECT_EQ(e["electrostatics"]["method"], "coulomb");
  EXPECT_NE(e["electrostatics"]["charges"].get<std::string>().find("ser.pqr"), std::string::npos) << e;
  EXPECT_NEAR(e["electrostatics"]["net_charge"].get<double>(), 0, 1e-12);
  EXPECT_EQ(e["electrostatics"]["atoms_charged"], 5);
  EXPECT_EQ(report["properties"]["hydrophobicity"]["range"]["min"], -0.8);  // serine

  // --no-hydrogens: four atoms; --potential-map: the map's constant everywhere.
  ASSERT_EQ(run_cli("map " + pqr + " -o " + (folder_ / "noh").string() + " --no-hydrogens").exit_code, 0);
  EXPECT_EQ(slurp(folder_ / "noh" / "atoms.csv").find("SER,HG"), std::string::npos);
  write_text(folder_ / "half.dx", constant_dx(0.5, 27));
  const auto mapped =
      run_cli("map " + pqr + " -o " + (folder_ / "dx").string() + " --potential-map " + (folder_ / "half.dx").string());
  ASSERT_EQ(mapped.exit_code, 0) << mapped.output;
  const auto dx = read_ply_columns(folder_ / "dx" / "sphere.ply");
  for (const double v : dx.vertex.at("vertex_electrostatics")) EXPECT_EQ(v, 0.5);

  // Bad input: exit 1, the output folder untouched.
  write_text(folder_ / "short.dx", constant_dx(0.5, 20));
  for (const std::string& bad :
       std::vector<std::string>{" --potential-map " + (folder_ / "short.dx").string(),
                                " --apbs --potential-map " + (folder_ / "half.dx").string(), " --dielectric 4x",
                                " --color nothing", " --properties hydrophobicty"}) {
    const auto refused = run_cli("map " + pqr + " -o " + (folder_ / "bad").string() + bad);
    EXPECT_EQ(refused.exit_code, 1) << bad << "\n" << refused.output;
    EXPECT_FALSE(fs::exists(folder_ / "bad")) << bad;
  }
  // --apbs without APBS (nor pdb2pqr) on the PATH: a message naming what to install, exit 1, nothing written.
  const std::string no_apbs = "PATH=/var/empty " + std::string(SPHEREMAP_CLI_PATH) + " map " + pqr + " -o " +
                              (folder_ / "bad").string() + " --apbs > " + (folder_ / "apbs.txt").string() + " 2>&1";
  const int status = std::system(no_apbs.c_str());
  EXPECT_EQ(WIFEXITED(status) ? WEXITSTATUS(status) : -1, 1) << slurp(folder_ / "apbs.txt");
  EXPECT_NE(slurp(folder_ / "apbs.txt").find("apbs"), std::string::npos) << slurp(folder_ / "apbs.txt");
  EXPECT_FALSE(fs::exists(folder_ / "bad"));
}

// The PyMOL script loads a map (Debian's pymol, headless): the surface overlays the structure, the sphere
// stands beside it, the colour bar exists, and a ray-traced PNG is written.
TEST_F(Properties, PymolScriptOverlaysTheSurfaceOnTheStructure) {
  if (std::system("PATH=/usr/bin:/bin command -v pymol > /dev/null 2>&1") != 0)
    GTEST_SKIP() << "pymol not installed (skipped on purpose; scripts/install-deps.sh installs it)";
  write_text(folder_ / "ser.pqr", kPqr);
  ASSERT_EQ(run_cli("map " + (folder_ / "ser.pqr").string() + " -o " + (folder_ / "out").string()).exit_code, 0);
  const fs::path script = fs::path(SPHEREMAP_SOURCE_DIR) / "python" / "spheremap_pymol.py";
  const fs::path png = folder_ / "ser.png";
  write_text(folder_ / "check.pml",
             "run " + script.string() + "\nspheremap_load " + (folder_ / "out").string() +
                 ", property=hydrophobicity, prefix=ser\n"
                 "python\n"
                 "from pymol import cmd\n"
                 "s, m, p = (cmd.get_extent(n) for n in ('ser_surface', 'ser_structure', 'ser_sphere'))\n"
                 "inside = all(s[0][k] < m[0][k] and m[1][k] < s[1][k] and m[0][k] - s[0][k] < 3 and "
                 "s[1][k] - m[1][k] < 3 for k in range(3))\n"
                 "beside = p[0][0] > s[1][0]\n"
                 "print('OVERLAY', 'yes' if inside else 'no', 'BESIDE', 'yes' if beside else 'no', "
                 "'BAR', 'yes' if 'ser_bar' in cmd.get_names('all') else 'no')\n"
                 "python end\n"
                 "png " +
                 png.string() + ", width=400, height=300, ray=1\n");
  const std::string command = "cd " + folder_.string() + " && PATH=/usr/bin:/bin pymol -cq check.pml > pymol.txt 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0) << slurp(folder_ / "pymol.txt");
  const std::string output = slurp(folder_ / "pymol.txt");
  EXPECT_NE(output.find("OVERLAY yes BESIDE yes BAR yes"), std::string::npos) << output;
  ASSERT_TRUE(fs::exists(png)) << output;
  EXPECT_GT(fs::file_size(png), 2000u);
}

class DataProperties : public Properties {};

// Crambin with a values file: every output, the values round trip, the areas, the two PLYs' agreement.
TEST_F(DataProperties, CrambinOutputsAgreeAndAddUp) {
  const fs::path cif = fs::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb" / "misc" / "1crn.cif";
  if (!fs::exists(cif)) GTEST_SKIP() << "shared data not found: " << cif << " (skipped on purpose)";
  std::string values = "chain,residue_number,double_number\n";
  for (int r = 1; r <= 40; ++r) values += "A," + std::to_string(r) + "," + std::to_string(2 * r) + "\n";
  values += "A,99,1\n";  // matches no residue: counted
  write_text(folder_ / "values.csv", values);
  const std::string command = "map " + cif.string() + " --values " + (folder_ / "values.csv").string() + " -o ";
  const auto run = run_cli(command + (folder_ / "a").string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  ASSERT_EQ(run_cli(command + (folder_ / "b").string()).exit_code, 0);
  for (const char* file : {"surface.ply", "sphere.ply", "surface.glb", "sphere.glb", "atoms.csv", "residues.csv"})
    EXPECT_EQ(slurp(folder_ / "a" / file), slurp(folder_ / "b" / file)) << file;  // deterministic

  const auto surface = read_ply_columns(folder_ / "a" / "surface.ply");
  const auto sphere = read_ply_columns(folder_ / "a" / "sphere.ply");
  for (const auto& [name, column] : surface.vertex) {
    if (name == "x" || name == "y" || name == "z") continue;
    const auto& other = sphere.vertex.at(name);
    ASSERT_EQ(column.size(), other.size()) << name;
    for (std::size_t v = 0; v < column.size(); ++v)
      EXPECT_TRUE(column[v] == other[v] || (std::isnan(column[v]) && std::isnan(other[v]))) << name << " " << v;
  }
  const auto& twice = surface.vertex.at("vertex_double_number");
  const auto& number = surface.vertex.at("vertex_residue_number");
  for (std::size_t v = 0; v < number.size(); ++v) {
    if (number[v] <= 40) {
      EXPECT_EQ(twice[v], 2 * number[v]) << v;
    } else {
      EXPECT_TRUE(std::isnan(twice[v])) << v;  // residues 41-46 have no row: no value, not zero
    }
  }
  for (const char* name : {"vertex_electrostatics", "vertex_hydrophobicity", "vertex_shape_index", "vertex_curvedness",
                           "vertex_area_distortion", "vertex_octant", "nx", "red"})
    ASSERT_TRUE(surface.vertex.count(name)) << name;
  EXPECT_EQ(surface.type.at("vertex_hydrophobicity"), "float");
  EXPECT_EQ(surface.type.at("x"), "double");
  EXPECT_EQ(surface.type.at("theta"), "double");
  EXPECT_EQ(surface.type.at("red"), "uchar");

  // residues.csv: the residues' areas add up to the surface's and the sphere's (4π).
  double surface_area = 0, sphere_area = 0, residue_surface = 0, residue_sphere = 0;
  const auto& x = surface.vertex.at("x");
  const auto& y = surface.vertex.at("y");
  const auto& z = surface.vertex.at("z");
  for (const auto& f : surface.faces)
    surface_area +=
        triangle_area({x[f[0]], y[f[0]], z[f[0]]}, {x[f[1]], y[f[1]], z[f[1]]}, {x[f[2]], y[f[2]], z[f[2]]});
  std::istringstream rows(slurp(folder_ / "a" / "residues.csv"));
  std::string line;
  std::getline(rows, line);
  EXPECT_EQ(line.rfind("chain,residue_number,insertion_code,residue_name,surface_area,sphere_area,mean_electrostatics,"
                       "mean_hydrophobicity",
                       0),
            0u)
      << line;
  int residues = 0;
  while (std::getline(rows, line)) {
    std::istringstream cells(line);
    std::string cell;
    for (int k = 0; k < 5; ++k) std::getline(cells, cell, ',');
    residue_surface += std::stod(cell);
    std::getline(cells, cell, ',');
    residue_sphere += std::stod(cell);
    ++residues;
  }
  EXPECT_EQ(residues, 46);
  EXPECT_NEAR(residue_surface, surface_area, 1e-9 * surface_area);
  sphere_area = 4 * std::numbers::pi;
  EXPECT_NEAR(residue_sphere, sphere_area, 1e-6);

  const auto report = nlohmann::json::parse(slurp(folder_ / "a" / "report.json"));
  const auto& column = report["properties"]["double_number"];
  EXPECT_EQ(column["source"], "values file");
  EXPECT_EQ(column["values_file"]["rows"], 41);
  EXPECT_EQ(column["values_file"]["rows_unmatched"], 1);
  EXPECT_GT(column["values_file"]["atoms_without_value"], 0);  // residues 41-46
  EXPECT_LT(column["values_file"]["atoms_without_value"], 100);
  EXPECT_EQ(report["properties"]["electrostatics"]["electrostatics"]["charges"], "formal");

  // Debian's meshio and Open3D read both files with every property (run with the system's python3).
  const fs::path script = fs::path(SPHEREMAP_SOURCE_DIR) / "tests" / "python" / "read_outputs.py";
  const std::string python = "PATH=/usr/bin:/bin python3 " + script.string() + " " + (folder_ / "a").string() +
                             " electrostatics hydrophobicity shape_index octant double_number > " +
                             (folder_ / "python.txt").string() + " 2>&1";
  const int status = std::system(python.c_str());
  const int code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  if (code == 77) GTEST_SKIP() << "python3-meshio and python3-open3d not installed (skipped on purpose)";
  EXPECT_EQ(code, 0) << slurp(folder_ / "python.txt");
}

}  // namespace
}  // namespace spheremap
