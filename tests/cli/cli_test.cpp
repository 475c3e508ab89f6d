// The command line as a user runs it: exit codes, files written (or not), byte-identical reruns.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <tuple>
#include <vector>

#include <nlohmann/json.hpp>

#include "../test_support.hpp"
#include "spheremap/attributes.hpp"
#include "spheremap/io/mesh_io.hpp"
#include "spheremap/io/ply.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

namespace fs = std::filesystem;

using testing_support::run_cli;
using testing_support::slurp;
using testing_support::write_text;

class Cli : public testing_support::FolderTest {};

std::string write_obj(const fs::path& path, const Mesh& mesh) {
  std::ofstream out(path);
  for (const auto& p : mesh.positions) out << "v " << p[0] << " " << p[1] << " " << p[2] << "\n";
  for (const auto& t : mesh.triangles) out << "f " << t[0] + 1 << " " << t[1] + 1 << " " << t[2] + 1 << "\n";
  return path.string();
}

TEST_F(Cli, HelpListsTheOptions) {
  const auto top = run_cli("--help");
  EXPECT_EQ(top.exit_code, 0);
  EXPECT_NE(top.output.find("map"), std::string::npos);
  const auto map = run_cli("map --help");
  EXPECT_EQ(map.exit_code, 0);
  for (const char* option : {"--weights", "--solver", "--poles", "--component", "--ascii", "--weld-tolerance",
                             "--no-repair", "--equalizing-rounds"})
    EXPECT_NE(map.output.find(option), std::string::npos) << option;
}

// map and batch share their map options (registered once): the same options, the same words.
TEST_F(Cli, MapAndBatchShareTheMapOptions) {
  const auto map = run_cli("map --help").output;
  const auto batch = run_cli("batch --help").output;
  auto line_of = [](const std::string& help, const std::string& option) -> std::string {
    const auto start = help.find("  " + option + " ");
    if (start == std::string::npos) return "missing " + option;
    return help.substr(start, help.find('\n', start) - start);
  };
  for (const char* option : {"--solver", "--component", "--weld-tolerance", "--collapse-floor", "--ascii",
                             "--equalizing-rounds", "--objective", "--objective-iterations", "--no-repair", "--probe",
                             "--grid", "--preset", "--mesh-edge", "--keep-topology"})
    EXPECT_EQ(line_of(map, option), line_of(batch, option)) << option;
}

TEST_F(Cli, MapsAMeshAndWritesThreeFilesIdenticallyTwice) {
  const auto input = write_obj(folder_ / "ico.obj", make_icosphere(2));
  const auto first = run_cli("map " + input + " -o " + (folder_ / "a").string());
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("CERTIFIED"), std::string::npos) << first.output;
  for (const char* name : {"surface.ply", "sphere.ply", "report.json"})
    EXPECT_TRUE(fs::exists(folder_ / "a" / name)) << name;
  const auto second = run_cli("map " + input + " -o " + (folder_ / "b").string());
  ASSERT_EQ(second.exit_code, 0);
  EXPECT_EQ(slurp(folder_ / "a" / "sphere.ply"), slurp(folder_ / "b" / "sphere.ply"));
  EXPECT_EQ(slurp(folder_ / "a" / "surface.ply"), slurp(folder_ / "b" / "surface.ply"));
  // The PLY files share vertex count and triangles, and carry theta and phi.
  const auto sphere = read_polygon_soup(folder_ / "a" / "sphere.ply");
  const auto surface = read_polygon_soup(folder_ / "a" / "surface.ply");
  EXPECT_EQ(sphere.positions.size(), surface.positions.size());
  EXPECT_EQ(sphere.faces, surface.faces);
  const auto header = slurp(folder_ / "a" / "sphere.ply").substr(0, 600);
  EXPECT_NE(header.find("binary_little_endian"), std::string::npos);
  EXPECT_NE(header.find(std::string("property double ") + attributes::kTheta), std::string::npos);
  EXPECT_NE(header.find(std::string("property double ") + attributes::kPhi), std::string::npos);
}

// The command replaces libgomp's GOMP_parallel with a call on the calling thread (cli/serial_openmp.cpp);
// this test binary does not, so CHOLMOD's supernodal factorizations here go through libgomp. A dumbbell
// with a thin neck needs re-weighting and equalizing rounds: dozens of factorizations of a 7k-vertex
// system, every one of whose supernodes opens a parallel region. The maps must agree to the last bit.
TEST_F(Cli, TheCommandMapsAMeshExactlyAsTheLibraryDoes) {
  const auto input = folder_ / "dumbbell.ply";
  const Mesh dumbbell = make_dumbbell(3.0, 0.3, 120, 60);
  write_ply(input, dumbbell);
  // Poles at the top and bottom of one sphere: the other is a limb that leads to neither.
  std::int32_t north = 0, south = 0;
  for (std::int32_t v = 0; v < static_cast<std::int32_t>(dumbbell.positions.size()); ++v) {
    const Vec3& p = dumbbell.positions[v];
    if (p[0] > 0) continue;
    if (p[2] > dumbbell.positions[north][2] || dumbbell.positions[north][0] > 0) north = v;
    if (p[2] < dumbbell.positions[south][2] || dumbbell.positions[south][0] > 0) south = v;
  }
  const auto run = run_cli("map " + input.string() + " -o " + (folder_ / "cli").string() + " --poles " +
                           std::to_string(north) + "," + std::to_string(south));
  ASSERT_EQ(run.exit_code, 0) << run.output;
  MapJobOptions options;
  options.map.poles = std::make_pair(north, south);
  const MapJobResult library = run_map_job(input, options);
  ASSERT_TRUE(library.map.certificate.certified());
  ASSERT_GT(library.map.diagnostics.repair.reweighting_rounds, 0);
  const auto written = read_polygon_soup(folder_ / "cli" / "sphere.ply");
  ASSERT_EQ(written.positions.size(), library.map.sphere.size());
  std::size_t different = 0;
  for (std::size_t v = 0; v < written.positions.size(); ++v) different += written.positions[v] != library.map.sphere[v];
  EXPECT_EQ(different, 0u);
}

TEST_F(Cli, AsciiAndEveryWeighting) {
  const auto input = write_obj(folder_ / "ico.obj", make_icosphere(2));
  for (const char* weights : {"uniform", "cotan", "mean-value"}) {
    const auto run = run_cli("map " + input + " -o " + (folder_ / weights).string() + " --ascii --weights " + weights);
    EXPECT_EQ(run.exit_code, 0) << weights << run.output;
    EXPECT_NE(slurp(folder_ / weights / "sphere.ply").find("format ascii 1.0"), std::string::npos);
    EXPECT_NE(slurp(folder_ / weights / "report.json").find(std::string("\"weights\": \"") + weights),
              std::string::npos);
  }
}

TEST_F(Cli, RefusedMeshExitsTwoAndWritesNothing) {
  Mesh open = make_icosphere(1);
  open.triangles.pop_back();
  const auto input = write_obj(folder_ / "open.obj", open);
  const auto run = run_cli("map " + input + " -o " + (folder_ / "out").string());
  EXPECT_EQ(run.exit_code, 2) << run.output;
  EXPECT_NE(run.output.find("open.obj"), std::string::npos) << run.output;
  EXPECT_NE(run.output.find("3 boundary edges"), std::string::npos) << run.output;
  EXPECT_FALSE(fs::exists(folder_ / "out" / "sphere.ply"));
  EXPECT_FALSE(fs::exists(folder_ / "out" / "report.json"));
}

TEST_F(Cli, UncertifiedMapExitsThreeButIsWrittenWithItsBadTriangles) {
  // The bundled example folds two triangles under the plain algorithm (a dividing edge at a pole).
  const std::string example = std::string(SPHEREMAP_SOURCE_DIR) + "/examples/dumbbell.ply";
  const auto plain = run_cli("map " + example + " -o " + (folder_ / "plain").string() + " --no-repair");
  EXPECT_EQ(plain.exit_code, 3) << plain.output;
  EXPECT_NE(plain.output.find("NOT CERTIFIED"), std::string::npos) << plain.output;
  EXPECT_TRUE(fs::exists(folder_ / "plain" / "sphere.ply"));
  const auto report = slurp(folder_ / "plain" / "report.json");
  EXPECT_NE(report.find("\"certified\": false"), std::string::npos);
  EXPECT_EQ(report.find("\"folded_triangles\": []"), std::string::npos) << "the folded triangles must be listed";
  const auto repaired = run_cli("map " + example + " -o " + (folder_ / "repaired").string());
  EXPECT_EQ(repaired.exit_code, 0) << repaired.output;
}

TEST_F(Cli, GeneratedHardCaseIsCertifiedByTheFallbackAndSaysSo) {
  // A coarse U-shaped tube (3 vertices per ring): the plain map and its repair end uncertified.
  const auto tube = (folder_ / "tube.ply").string();
  const auto generated = run_cli("generate tube-u --segments 3 --rings 40 -o " + tube);
  ASSERT_EQ(generated.exit_code, 0) << generated.output;
  const auto mapped = run_cli("map " + tube + " -o " + (folder_ / "tube").string());
  ASSERT_EQ(mapped.exit_code, 0) << mapped.output;
  EXPECT_NE(mapped.output.find("fallback (the map above was not certified): progressive embedding"), std::string::npos)
      << mapped.output;
  const auto report = nlohmann::json::parse(slurp(folder_ / "tube" / "report.json"));
  EXPECT_EQ(report["map"]["method"], "fallback-progressive");
  EXPECT_TRUE(report["certificate"]["certified"].get<bool>());
  EXPECT_FALSE(report["plain_algorithm_certificate"]["certified"].get<bool>());
  EXPECT_TRUE(report["map"]["fallback"]["valid"].get<bool>());
  EXPECT_GT(report["map"]["fallback"]["levels"].get<int>(), 0);
  EXPECT_TRUE(report["timings_seconds"].contains("fallback"));
  // A map certified without it carries no fallback entry at all.
  const auto ico = (folder_ / "ico.ply").string();
  ASSERT_EQ(run_cli("generate icosphere --level 2 -o " + ico).exit_code, 0);
  ASSERT_EQ(run_cli("map " + ico + " -o " + (folder_ / "ico").string()).exit_code, 0);
  const auto plain = nlohmann::json::parse(slurp(folder_ / "ico" / "report.json"));
  EXPECT_FALSE(plain["map"].contains("fallback"));
  EXPECT_FALSE(plain["timings_seconds"].contains("fallback"));
  // The other generated hard cases.
  for (const char* shape : {"stacked --vertices 200 --nesting 0.5", "tube-c --segments 4 --rings 20",
                            "spiky --level 1 --spikes 4 --spike-rings 8"}) {
    const auto made = run_cli(std::string("generate ") + shape + " -q -o " + (folder_ / "shape.ply").string());
    EXPECT_EQ(made.exit_code, 0) << shape;
  }
  EXPECT_EQ(run_cli("generate stacked --vertices 3 -o " + (folder_ / "bad.ply").string()).exit_code, 1);
}

TEST_F(Cli, EqualizingRoundsOptionReachesTheMapAndTheReport) {
  const auto input = write_obj(folder_ / "ico.obj", make_icosphere(2));
  const auto none = run_cli("map " + input + " -o " + (folder_ / "none").string() + " --equalizing-rounds 0");
  ASSERT_EQ(none.exit_code, 0) << none.output;
  const auto report = slurp(folder_ / "none" / "report.json");
  EXPECT_NE(report.find("\"max_equalizing_rounds\": 0"), std::string::npos);
  EXPECT_NE(report.find("\"equalizing_rounds\": 0"), std::string::npos);
  const auto by_default = run_cli("map " + input + " -o " + (folder_ / "default").string());
  ASSERT_EQ(by_default.exit_code, 0) << by_default.output;
  EXPECT_NE(slurp(folder_ / "default" / "report.json").find("\"max_equalizing_rounds\": 12"), std::string::npos);
  EXPECT_EQ(run_cli("map " + input + " -o " + (folder_ / "bad").string() + " --equalizing-rounds -1").exit_code, 1);
}

TEST_F(Cli, ObjectiveOptionOptimizesTheCertifiedMapAndSaysSo) {
  const auto input = write_obj(folder_ / "dumbbell.obj", make_dumbbell(3.0, 0.4, 24, 16));
  const auto area = run_cli("map " + input + " -o " + (folder_ / "area").string() + " --objective area");
  ASSERT_EQ(area.exit_code, 0) << area.output;
  EXPECT_NE(area.output.find("objective area (log-area-ratio)"), std::string::npos) << area.output;
  const auto report = nlohmann::json::parse(slurp(folder_ / "area" / "report.json"));
  EXPECT_EQ(report["options"]["objective"], "area");
  EXPECT_EQ(report["map"]["objective"]["outcome"], "optimized");
  EXPECT_TRUE(report["certificate"]["certified"].get<bool>());
  const auto plain = run_cli("map " + input + " -o " + (folder_ / "plain").string());
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  const auto paper = nlohmann::json::parse(slurp(folder_ / "plain" / "report.json"));
  EXPECT_FALSE(paper["map"].contains("objective"));
  EXPECT_LT(report["distortion"]["area_log_ratio_mean"].get<double>(),
            paper["distortion"]["area_log_ratio_mean"].get<double>());
  // --objective paper is the default, byte for byte.
  ASSERT_EQ(run_cli("map " + input + " -o " + (folder_ / "paper").string() + " --objective paper").exit_code, 0);
  EXPECT_EQ(slurp(folder_ / "paper" / "sphere.ply"), slurp(folder_ / "plain" / "sphere.ply"));
  EXPECT_EQ(run_cli("map " + input + " -o " + (folder_ / "bad").string() + " --objective equal").exit_code, 1);
}

TEST_F(Cli, UnreadableInputAndBadOptionsExitOne) {
  EXPECT_EQ(run_cli("map " + (folder_ / "missing.obj").string() + " -o " + folder_.string()).exit_code, 1);
  const auto input = write_obj(folder_ / "ico.obj", make_icosphere(1));
  EXPECT_EQ(run_cli("map " + input + " -o " + folder_.string() + " --weights magic").exit_code, 1);
  EXPECT_EQ(run_cli("map").exit_code, 1);
  const auto poles = run_cli("map " + input + " -o " + folder_.string() + " --poles 1");
  EXPECT_EQ(poles.exit_code, 1) << poles.output;
  EXPECT_NE(poles.output.find("--poles"), std::string::npos);
}

// Bad structure files: a message naming the file and the problem, exit 1, and nothing written.
TEST_F(Cli, BadStructureFilesExitOneAndWriteNothing) {
  const std::string atom = "ATOM      1  CA  ALA A   1       1.000   2.000   3.000  1.00  0.00           C\n";
  const std::string second = "ATOM      2  CB  ALA A   1       2.000   2.500   3.000  1.00  0.00           C\n";
  const std::string nan_atom = "ATOM      2  CB  ALA A   1       nan     2.000   3.000  1.00  0.00           C\n";
  const std::string water = "HETATM    3  O   HOH A   2       5.000   2.000   3.000  1.00  0.00           O\n";
  std::string binary(2000, '\0');
  for (std::size_t k = 0; k < binary.size(); ++k) binary[k] = static_cast<char>((k * 7919u) % 251u);
  const std::vector<std::tuple<std::string, std::string, std::string, std::string>> cases = {
      {"empty.pdb", "", "", "empty"},
      {"binary.pdb", binary, "", "no atoms"},
      {"truncated.cif",
       "data_x\nloop_\n_atom_site.group_PDB\n_atom_site.id\n_atom_site.Cartn_x\nATOM 1 'unterminated\n", "",
       "cannot read"},
      {"one.pdb", atom + "END\n", "", "at least two"},
      {"nan.pdb", atom + nan_atom + "END\n", "", "nan"},
      {"waters.pdb", water + "END\n", "", "0 atom(s) left"},
      {"chains.pdb", atom + second + "END\n", " --chains Z", "Z"},
      {"budget.pdb", atom + second + "END\n", " --grid 0.05 --probe 100", "--grid"},
  };
  for (const auto& [name, contents, options, expected] : cases) {
    std::ofstream(folder_ / name, std::ios::binary) << contents;
    const fs::path output = folder_ / ("out-" + name);
    const auto run = run_cli("map " + (folder_ / name).string() + " -o " + output.string() + options);
    EXPECT_EQ(run.exit_code, 1) << name << ": " << run.output;
    EXPECT_NE(run.output.find(name), std::string::npos) << name << ": " << run.output;
    EXPECT_NE(run.output.find(expected), std::string::npos) << name << ": " << run.output;
    EXPECT_FALSE(fs::exists(output)) << name;
    const auto surface =
        run_cli("surface " + (folder_ / name).string() + " -o " + (folder_ / (name + ".ply")).string() + options);
    EXPECT_EQ(surface.exit_code, 1) << name << ": " << surface.output;
    EXPECT_FALSE(fs::exists(folder_ / (name + ".ply"))) << name;
  }
}

// A structure with a detached ion: by default the outer surface is mapped and the piece reported; with
// --components all each closed component gets its own certified sphere.
TEST_F(Cli, ComponentsOfAMolecularSurface) {
  const fs::path input = folder_ / "two.pdb";
  std::ofstream(input) << "ATOM      1  CA  ALA A   1       1.000   2.000   3.000  1.00  0.00           C\n"
                          "ATOM      2  CB  ALA A   1       2.000   2.500   3.000  1.00  0.00           C\n"
                          "HETATM    3 ZN    ZN A 101      21.000   2.000   3.000  1.00  0.00          ZN\nEND\n";
  const auto outer = run_cli("map " + input.string() + " -o " + (folder_ / "outer").string());
  ASSERT_EQ(outer.exit_code, 0) << outer.output;
  const auto report = nlohmann::json::parse(slurp(folder_ / "outer" / "report.json"));
  const auto& components = report["structure"]["components"];
  ASSERT_EQ(components.size(), 2u);
  EXPECT_EQ(components[0]["kind"], "outer");
  EXPECT_TRUE(components[0]["mapped"]);
  EXPECT_EQ(components[1]["kind"], "piece");
  EXPECT_FALSE(components[1]["mapped"]);
  EXPECT_EQ(components[1]["residues"], nlohmann::json::array({"A:ZN101"}));
  EXPECT_GT(components[0]["area"].get<double>(), components[1]["area"].get<double>());

  const auto all = run_cli("map " + input.string() + " -o " + (folder_ / "all").string() + " --components all");
  ASSERT_EQ(all.exit_code, 0) << all.output;
  for (int k = 0; k < 2; ++k) {
    const auto component =
        nlohmann::json::parse(slurp(folder_ / "all" / ("component-" + std::to_string(k)) / "report.json"));
    EXPECT_EQ(component["structure"]["component_mapped"], k);
    EXPECT_TRUE(component["certificate"]["certified"]);
    // Each component is simplified before it is mapped (the default --mesh-edge 1).
    EXPECT_EQ(component["simplification"]["triangles_before"], components[k]["triangles"]);
    EXPECT_EQ(component["mesh"]["triangles"], component["simplification"]["triangles_after"]);
    EXPECT_LT(component["mesh"]["triangles"].get<int>(), components[k]["triangles"].get<int>());
  }
  const auto piece = run_cli("map " + input.string() + " -o " + (folder_ / "piece").string() + " --component 1");
  ASSERT_EQ(piece.exit_code, 0) << piece.output;
  EXPECT_EQ(run_cli("map " + input.string() + " -o " + (folder_ / "none").string() + " --component 2").exit_code, 1);
  EXPECT_FALSE(fs::exists(folder_ / "none"));
}

// A three-atom PDB file (a quick structure for the preset tests).
fs::path write_three_atoms(const fs::path& path) {
  std::ofstream(path) << "ATOM      1  N   ALA A   1       1.000   2.000   3.000  1.00  0.00           N\n"
                         "ATOM      2  CA  ALA A   1       2.400   2.300   3.100  1.00  0.00           C\n"
                         "ATOM      3  C   ALA A   1       3.100   3.500   2.600  1.00  0.00           C\nEND\n";
  return path;
}

// The report.json of `spheremap map input -o folder/<hash of options> options` (expected to succeed).
nlohmann::json map_report(const fs::path& input, const fs::path& folder, const std::string& options) {
  const fs::path out = folder / ("run" + std::to_string(std::hash<std::string>{}(options)));
  const auto run = run_cli("map " + input.string() + " -o " + out.string() + " " + options);
  EXPECT_EQ(run.exit_code, 0) << run.output;
  return nlohmann::json::parse(slurp(out / "report.json"));
}

TEST_F(Cli, PaperPresetSetsProbeGridAndMidpointContourAndExplicitOptionsWin) {
  const fs::path input = write_three_atoms(folder_ / "three.pdb");
  auto settings = [&](const std::string& options) {
    const auto report = map_report(input, folder_ / "paper", options);
    return std::make_tuple(report["structure"]["probe"].get<double>(), report["structure"]["grid"].get<double>(),
                           report["structure"]["contour_minimum_fraction"].get<double>());
  };
  EXPECT_EQ(settings(""), std::make_tuple(1.4, 0.5, 0.1));
  EXPECT_EQ(settings("--preset paper"), std::make_tuple(1.8, 2.5, 0.5));
  EXPECT_EQ(settings("--preset paper --grid 1.5"), std::make_tuple(1.8, 1.5, 0.5));
}

TEST_F(Cli, FastPresetSetsGridMeshEdgeAndFewEqualizingRoundsAndExplicitOptionsWin) {
  const fs::path input = write_three_atoms(folder_ / "three.pdb");
  // grid, target edge, simplification tolerance, equalizing rounds, probe
  auto settings = [&](const std::string& options) {
    const auto report = map_report(input, folder_ / "fast", options);
    return std::make_tuple(
        report["structure"]["grid"].get<double>(), report["simplification"]["target_edge_length"].get<double>(),
        report["simplification"]["max_error"].get<double>(), report["options"]["max_equalizing_rounds"].get<int>(),
        report["structure"]["probe"].get<double>());
  };
  EXPECT_EQ(settings(""), std::make_tuple(0.5, 1.0, 0.1, 12, 1.4));
  EXPECT_EQ(settings("--preset fast"), std::make_tuple(1.0, 2.0, 0.2, 4, 1.4));
  EXPECT_EQ(settings("--preset fast --grid 0.7 --mesh-edge 1.5 --equalizing-rounds 3"),
            std::make_tuple(0.7, 1.5, 0.15, 3, 1.4));
  EXPECT_EQ(settings("--preset fast --equalizing-rounds 0"), std::make_tuple(1.0, 2.0, 0.2, 0, 1.4));
  // The surface command has no map options: the preset sets its grid, and the contour is written as it is.
  const fs::path surface = folder_ / "fast-surface.ply";
  const auto run = run_cli("surface " + input.string() + " -o " + surface.string() + " --preset fast");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_TRUE(fs::exists(surface));
}

TEST_F(Cli, PolesAreInputIndicesAndMustBeFarEnoughApart) {
  const Mesh ico = make_icosphere(2);
  const auto input = write_obj(folder_ / "ico.obj", ico);
  const auto run = run_cli("map " + input + " -o " + (folder_ / "poles").string() + " --poles 5,17");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(slurp(folder_ / "poles" / "report.json").find("\"north_pole\": 5,"), std::string::npos);
  const auto neighbour = ico.triangles[0];
  const auto close = run_cli("map " + input + " -o " + (folder_ / "close").string() + " --poles " +
                             std::to_string(neighbour[0]) + "," + std::to_string(neighbour[1]));
  EXPECT_EQ(close.exit_code, 1) << close.output;
  EXPECT_NE(close.output.find("joined by an edge"), std::string::npos) << close.output;
  EXPECT_EQ(run_cli("map " + input + " -o " + (folder_ / "none").string() + " --poles 5,100000").exit_code, 1);
}

TEST_F(Cli, ComponentOptionChoosesAPiece) {
  Mesh two = make_icosphere(1);
  const Mesh other = make_icosphere(1);
  const auto offset = static_cast<std::int32_t>(two.positions.size());
  for (auto p : other.positions) two.positions.push_back({p[0] + 3, p[1], p[2]});
  for (auto t : other.triangles) two.triangles.push_back({t[0] + offset, t[1] + offset, t[2] + offset});
  const auto input = write_obj(folder_ / "two.obj", two);
  EXPECT_EQ(run_cli("map " + input + " -o " + (folder_ / "refused").string()).exit_code, 2);
  EXPECT_EQ(run_cli("map " + input + " -o " + (folder_ / "largest").string() + " --component largest").exit_code, 0);
  EXPECT_EQ(run_cli("map " + input + " -o " + (folder_ / "one").string() + " --component 1").exit_code, 0);
}

}  // namespace
}  // namespace spheremap

namespace spheremap {
namespace {

class DataCli : public Cli {};

// From a structure file to a certified sphere map in one command, and the surface alone.
TEST_F(DataCli, StructureToCertifiedMapAndSurface) {
  const fs::path pdb = fs::path(SPHEREMAP_SHARED_DATA_DIR) / "pdb";
  if (!fs::exists(pdb)) GTEST_SKIP() << "shared data not found: " << pdb << " (skipped on purpose)";
  const auto map = run_cli("map " + (pdb / "misc" / "1crn.cif").string() + " -o " + (folder_ / "crambin").string());
  ASSERT_EQ(map.exit_code, 0) << map.output;
  EXPECT_NE(map.output.find("327 atoms"), std::string::npos) << map.output;
  const auto header = slurp(folder_ / "crambin" / "sphere.ply").substr(0, 2000);
  using namespace attributes;
  // The PLY holds numbers only (atomid, float properties, normals, colours); the names are in atoms.csv.
  EXPECT_NE(header.find(std::string("property int ") + kAtomId + "\n"), std::string::npos);
  EXPECT_EQ(header.find("property list uchar uchar vertex_"), std::string::npos) << header;
  for (const char* name : {kResidueNumber, kBFactor, "vertex_hydrophobicity", "vertex_electrostatics", "nx", "nz"})
    EXPECT_NE(header.find(std::string("property float ") + name + "\n"), std::string::npos) << name;
  for (const char* name : {"red", "green", "blue"})
    EXPECT_NE(header.find(std::string("property uchar ") + name + "\n"), std::string::npos) << name;
  EXPECT_EQ(header.find(kCharge), std::string::npos);  // an mmCIF file has no partial charges
  EXPECT_EQ(
      slurp(folder_ / "crambin" / "atoms.csv")
          .rfind("atomid,serial,model,chain,residue_number,insertion_code,residue_name,atom_name,element,x,y,z,radius",
                 0),
      0u);
  EXPECT_NE(slurp(folder_ / "crambin" / "report.json").find("\"probe\": 1.4"), std::string::npos);

  const auto surface = run_cli("surface " + (pdb / "misc" / "1crn.cif").string() + " -o " +
                               (folder_ / "crn.ply").string() + " --probe 1.8 --grid 0.6");
  ASSERT_EQ(surface.exit_code, 0) << surface.output;
  EXPECT_NE(slurp(folder_ / "crn.ply").substr(0, 400).find(std::string("property int ") + kAtomId), std::string::npos);

  // --cavities: crambin's buried cavity (at 0.5 Å, probe 1.4 Å) becomes a reported component; the outer
  // surface, which is mapped, is the same as without it.
  const auto cavities =
      run_cli("map " + (pdb / "misc" / "1crn.cif").string() + " -o " + (folder_ / "crn-cav").string() + " --cavities");
  ASSERT_EQ(cavities.exit_code, 0) << cavities.output;
  const auto with = nlohmann::json::parse(slurp(folder_ / "crn-cav" / "report.json"));
  const auto without = nlohmann::json::parse(slurp(folder_ / "crambin" / "report.json"));
  ASSERT_EQ(with["structure"]["components"].size(), 2u);
  EXPECT_EQ(with["structure"]["components"][1]["kind"], "cavity");
  EXPECT_GT(with["structure"]["components"][1]["residue_count"], 0);
  EXPECT_EQ(with["mesh"]["triangles"], without["mesh"]["triangles"]);

  // A surface with handles (4hhb has 13 at a 1 Å grid: 8 before sub-grid channels were passed) is
  // repaired and maps certified; with --keep-topology (the paper's filter) it is refused with its
  // genus and nothing is written.
  const std::string haemoglobin = (pdb / "misc" / "4hhb.cif").string() + " --grid 1.0";
  const auto repaired = run_cli("map " + haemoglobin + " -o " + (folder_ / "hb").string());
  EXPECT_EQ(repaired.exit_code, 0) << repaired.output;
  EXPECT_NE(repaired.output.find("handle repair (per-handle): genus 13 -> 0"), std::string::npos) << repaired.output;
  const auto report = nlohmann::json::parse(slurp(folder_ / "hb" / "report.json"));
  const auto& repair = report["structure"]["topology_repair"];
  EXPECT_EQ(repair["genus_before"], 13);
  EXPECT_EQ(repair["method"], "per-handle");
  EXPECT_GE(repair["rounds"], 1);
  EXPECT_LE(repair["rounds"], 4);
  EXPECT_EQ(repair["changes"].size(), 13u);
  for (const auto& change : repair["changes"]) EXPECT_FALSE(change["lining_residues"].empty()) << change;
  const auto& components = report["structure"]["components"];
  ASSERT_GE(components.size(), 1u);
  EXPECT_EQ(components[0]["kind"], "outer");
  EXPECT_TRUE(components[0]["mapped"]);
  EXPECT_EQ(components[0]["genus"], 0);
  const auto kept = run_cli("map " + haemoglobin + " -o " + (folder_ / "hb-kept").string() + " --keep-topology");
  EXPECT_EQ(kept.exit_code, 2) << kept.output;
  EXPECT_NE(kept.output.find("genus 13"), std::string::npos) << kept.output;
  EXPECT_FALSE(fs::exists(folder_ / "hb-kept" / "sphere.ply"));

  const auto bad =
      run_cli("map " + (pdb / "misc" / "1crn.cif").string() + " -o " + (folder_ / "x").string() + " --chains Q");
  EXPECT_EQ(bad.exit_code, 1) << bad.output;
  EXPECT_NE(bad.output.find("chain 'Q' does not exist"), std::string::npos) << bad.output;
}

// -o into a folder of an earlier run: refused (nothing touched) unless --force, which replaces the earlier
// outputs as a whole (a stale component-3/ goes) and keeps other files.
TEST_F(Cli, AnEarlierRunsFolderIsRefusedOrReplacedWithForce) {
  const auto input = write_obj(folder_ / "ico.obj", make_icosphere(1));
  const fs::path out = folder_ / "out";
  ASSERT_EQ(run_cli("map " + input + " -o " + out.string() + " -q").exit_code, 0);
  fs::create_directories(out / "component-3");
  write_text(out / "component-3" / "report.json", "{}");
  write_text(out / "notes.txt", "mine");
  const std::string report = slurp(out / "report.json");
  const auto refused = run_cli("map " + input + " -o " + out.string() + " -q");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.output.find("earlier run"), std::string::npos) << refused.output;
  EXPECT_NE(refused.output.find("--force"), std::string::npos) << refused.output;
  EXPECT_TRUE(fs::exists(out / "component-3" / "report.json"));
  EXPECT_EQ(slurp(out / "report.json"), report);                                // untouched
  ASSERT_TRUE(fs::exists(out / "pictures") && fs::exists(out / "index.html"));  // the first run's
  const auto forced = run_cli("map " + input + " -o " + out.string() + " -q --force --no-pictures");
  EXPECT_EQ(forced.exit_code, 0) << forced.output;
  EXPECT_FALSE(fs::exists(out / "component-3"));
  EXPECT_FALSE(fs::exists(out / "pictures"));  // no stale pictures beside a run that drew none
  EXPECT_FALSE(fs::exists(out / "index.html"));
  EXPECT_EQ(slurp(out / "notes.txt"), "mine");
  for (const char* name : {"surface.ply", "sphere.ply"}) EXPECT_TRUE(fs::exists(out / name)) << name;
}

// --components all --force over an earlier run of more components (and of a single map): the earlier
// component-K/ folders beyond the new count and the earlier top-level outputs are gone, the new components
// are there and complete; when the new run fails, the earlier outputs stay as they were.
TEST_F(Cli, ComponentsAllWithForceReplacesAnEarlierRunOfMoreComponents) {
  const fs::path input = folder_ / "two.pdb";
  std::ofstream(input) << "ATOM      1  CA  ALA A   1       1.000   2.000   3.000  1.00  0.00           C\n"
                          "ATOM      2  CB  ALA A   1       2.000   2.500   3.000  1.00  0.00           C\n"
                          "HETATM    3 ZN    ZN A 101      21.000   2.000   3.000  1.00  0.00          ZN\nEND\n";
  const fs::path out = folder_ / "out";
  for (int k = 0; k < 5; ++k) {
    fs::create_directories(out / ("component-" + std::to_string(k)));
    write_text(out / ("component-" + std::to_string(k)) / "report.json", "{\"earlier\": true}");
  }
  write_text(out / "surface.ply", "earlier");
  write_text(out / "notes.txt", "mine");
  const auto failed = run_cli("map " + (folder_ / "missing.pdb").string() + " -o " + out.string() +
                              " --components all --force -q --no-pictures");
  EXPECT_EQ(failed.exit_code, 1) << failed.output;
  for (int k = 0; k < 5; ++k)
    EXPECT_EQ(slurp(out / ("component-" + std::to_string(k)) / "report.json"), "{\"earlier\": true}") << k;
  EXPECT_EQ(slurp(out / "surface.ply"), "earlier");

  const auto forced =
      run_cli("map " + input.string() + " -o " + out.string() + " --components all --force -q --no-pictures");
  ASSERT_EQ(forced.exit_code, 0) << forced.output;
  for (int k = 0; k < 2; ++k) {
    const auto report = nlohmann::json::parse(slurp(out / ("component-" + std::to_string(k)) / "report.json"));
    EXPECT_EQ(report["structure"]["component_mapped"], k);
    EXPECT_TRUE(fs::exists(out / ("component-" + std::to_string(k)) / "sphere.ply")) << k;
  }
  for (int k = 2; k < 5; ++k) EXPECT_FALSE(fs::exists(out / ("component-" + std::to_string(k)))) << k;
  EXPECT_FALSE(fs::exists(out / "surface.ply"));
  EXPECT_EQ(slurp(out / "notes.txt"), "mine");
  std::vector<std::string> left;
  for (const auto& entry : fs::directory_iterator(out)) left.push_back(entry.path().filename().string());
  std::sort(left.begin(), left.end());
  EXPECT_EQ(left, (std::vector<std::string>{"component-0", "component-1", "notes.txt"}));
}

// The reader's warnings reach stderr, report.json and the batch summary's message column.
TEST_F(Cli, StructureWarningsReachStderrTheReportAndTheBatchSummary) {
  const std::string pdb =
      "ATOM      1  N   ALA A   1      11.104   6.134  -6.504  1.00  0.00           N\n"
      "ATOM      2  CA  ALA A   1      11.639   6.071  -5.147  1.00  0.00           C\n"
      "ATOM      3  C   ALA A   1      13.149   5.916  -5.179  1.00  0.00           C";  // no final line break
  write_text(folder_ / "cut.pdb", pdb);
  const auto map = run_cli("map " + (folder_ / "cut.pdb").string() + " -o " + (folder_ / "m").string() + " -q");
  EXPECT_EQ(map.exit_code, 0) << map.output;
  EXPECT_NE(map.output.find("warning: " + (folder_ / "cut.pdb").string() + ": the file does not end with a line break"),
            std::string::npos)
      << map.output;
  const auto report = nlohmann::json::parse(slurp(folder_ / "m" / "report.json"));
  ASSERT_EQ(report["structure"]["warnings"].size(), 1u);
  EXPECT_NE(report["structure"]["warnings"][0].get<std::string>().find("line break"), std::string::npos);
  const auto batch = run_cli("batch " + (folder_ / "cut.pdb").string() + " -o " + (folder_ / "b").string() + " -q");
  EXPECT_EQ(batch.exit_code, 0) << batch.output;
  EXPECT_NE(batch.output.find("warning: the file does not end with a line break"), std::string::npos) << batch.output;
  EXPECT_NE(slurp(folder_ / "b" / "summary.csv").find("warning: the file does not end with a line break"),
            std::string::npos);
  const auto strict =
      run_cli("batch " + (folder_ / "cut.pdb").string() + " -o " + (folder_ / "s").string() + " -q --strict");
  EXPECT_EQ(strict.exit_code, 1) << strict.output;
  EXPECT_NE(slurp(folder_ / "s" / "summary.csv").find("--strict"), std::string::npos);
}

}  // namespace
}  // namespace spheremap
