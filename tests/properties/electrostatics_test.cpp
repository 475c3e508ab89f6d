#include "spheremap/properties/electrostatics.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>

#include <fmt/format.h>

#include "spheremap/error.hpp"
#include "spheremap/geometry/normals.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/surface/ses.hpp"

namespace spheremap {
namespace {

const std::filesystem::path kData = SPHEREMAP_SHARED_DATA_DIR;

// PATH without the folders of pdb2pqr30 and apbs, for the length of a test.
class NoToolsOnPath {
 public:
  NoToolsOnPath() : saved_(std::getenv("PATH") ? std::getenv("PATH") : "") {
    setenv("PATH", (std::filesystem::temp_directory_path() / "spheremap-no-such-folder").c_str(), 1);
  }
  ~NoToolsOnPath() { setenv("PATH", saved_.c_str(), 1); }

 private:
  std::string saved_;
};

std::vector<Atom> two_atoms() {
  std::vector<Atom> atoms(2);
  atoms[0].name = "NZ", atoms[0].residue_name = "LYS", atoms[0].element = "N", atoms[0].chain = "A";
  atoms[1].name = "OD1", atoms[1].residue_name = "ASP", atoms[1].element = "O", atoms[1].chain = "A";
  atoms[1].residue_number = 2;
  atoms[1].position = {6, 0, 0};
  return atoms;
}

TEST(Electrostatics, MissingProgramsNameTheirDebianPackages) {
  const NoToolsOnPath no_tools;
  EXPECT_FALSE(pdb2pqr_available());
  EXPECT_FALSE(apbs_available());
  try {
    pdb2pqr_charges(two_atoms(), ForceField::kAmber, "x.pdb");
    ADD_FAILURE() << "no error without pdb2pqr30";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("apt-get install pdb2pqr"), std::string::npos) << e.what();
  }
  try {
    run_apbs(two_atoms(), {{0, 0, 5}}, {}, "x.pdb");
    ADD_FAILURE() << "no error without apbs";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("apt-get install apbs pdb2pqr"), std::string::npos) << e.what();
    EXPECT_EQ(e.code(), ExitCode::kUsage);
  }
  // --charges unset: formal charges, with a warning that says why.
  const ChargeAssignment charges = assign_charges(two_atoms(), "x.pdb", {});
  EXPECT_EQ(charges.source, "formal");
  EXPECT_EQ(charges.atom_charges, (std::vector<double>{1, -0.5}));
  ASSERT_FALSE(charges.warnings.empty());
  EXPECT_NE(charges.warnings.back().find("pdb2pqr30 is not installed"), std::string::npos);
}

TEST(Electrostatics, APotentialMapIsReadAtTheOffsetPoints) {
  // A map of the linear field f = 2x - y + 0.5z + 1 over [-20, 20]^3, and a sphere of radius 10 Å in it.
  const auto path = std::filesystem::temp_directory_path() / fmt::format("spheremap-map-{}.dx", ::getpid());
  {
    std::ofstream out(path);
    out << "object 1 class gridpositions counts 9 9 9\norigin -20 -20 -20\n"
           "delta 5 0 0\ndelta 0 5 0\ndelta 0 0 5\nobject 2 class gridconnections counts 9 9 9\n"
           "object 3 class array type double rank 0 items 729 data follows\n";
    for (int i = 0; i < 9; ++i)
      for (int j = 0; j < 9; ++j)
        for (int k = 0; k < 9; ++k) out << 2 * (-20 + 5 * i) - (-20 + 5 * j) + 0.5 * (-20 + 5 * k) + 1 << "\n";
  }
  Mesh sphere = make_icosphere(2);
  for (auto& p : sphere.positions) p = 10.0 * p;
  ElectrostaticsOptions options;
  options.method = ElectrostaticsMethod::kPotentialMap;
  options.potential_map = path;
  const ElectrostaticsResult result = surface_electrostatics(sphere, two_atoms(), "x.pdb", options);
  const auto points = offset_along_normals(sphere.positions, vertex_normals(sphere.positions, sphere.triangles), 1.4);
  ASSERT_EQ(result.potential.size(), sphere.vertex_count());
  for (std::size_t v = 0; v < points.size(); ++v)
    EXPECT_NEAR(result.potential[v], 2 * points[v][0] - points[v][1] + 0.5 * points[v][2] + 1, 1e-12);
  EXPECT_EQ(result.source, fmt::format("APBS map {}", path.filename().string()));
  for (auto& p : sphere.positions) p = 2.0 * p;  // radius 20 Å + 1.4: outside the map
  EXPECT_THROW(surface_electrostatics(sphere, two_atoms(), "x.pdb", options), InputError);
  std::filesystem::remove(path);
}

TEST(Electrostatics, CoulombWithFormalChargesOnASphere) {
  Mesh sphere = make_icosphere(2);
  for (auto& p : sphere.positions) p = 20.0 * p;
  ElectrostaticsOptions options;
  options.charges = ChargeChoice::kFormal;
  const ElectrostaticsResult result = surface_electrostatics(sphere, two_atoms(), "x.pdb", options);
  EXPECT_EQ(result.source, "Coulomb, epsilon = 4r, charges: formal");
  const auto points = offset_along_normals(sphere.positions, vertex_normals(sphere.positions, sphere.triangles), 1.4);
  const double lb = bjerrum_length(298.15);
  for (std::size_t v = 0; v < points.size(); ++v) {
    const double r1 = norm(points[v]), r2 = norm(points[v] - Vec3{6, 0, 0});
    EXPECT_NEAR(result.potential[v], lb / 4 * (1 / (r1 * r1) - 0.5 / (r2 * r2)), 1e-12);
  }
}

TEST(Electrostatics, APqrLineWithoutItsChargeIsAnError) {
  const auto path = std::filesystem::temp_directory_path() / fmt::format("spheremap-nocharge-{}.pqr", ::getpid());
  std::ofstream(path) << "ATOM      1  N   ALA A   1       1.000   2.000   3.000 -0.3000 1.8240\n"
                         "ATOM      2  CA  ALA A   1       1.500   2.000   3.000  1.9080\n";
  ElectrostaticsOptions options;
  options.charges = ChargeChoice::kFile;
  options.charges_file = path;
  try {
    assign_charges(two_atoms(), "x.pdb", options);
    ADD_FAILURE() << "no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path.string() + ":2:"), std::string::npos) << e.what();
  }
  std::filesystem::remove(path);
}

// ---------------------------------------------------------------------------------------------------------------
// With the programs and the shared structures: barnase (1brs chain A, net charge +2, pI about 9).

struct Barnase {
  std::vector<Atom> atoms;
  Mesh surface;
};

const Barnase& barnase() {
  static const Barnase b = [] {
    Barnase result;
    StructureOptions options;
    options.chains = {"A"};
    result.atoms = read_structure(kData / "pdb/misc/1brs.pdb", options).atoms;
    SurfaceOptions surface;
    surface.grid = 1.0;
    result.surface = solvent_excluded_surface(result.atoms, surface);
    return result;
  }();
  return b;
}

// Mean potential on the vertices whose nearest atom is one of `names` of `residue`.
double mean_near(const std::vector<double>& potential, const std::string& residue,
                 const std::vector<std::string>& names) {
  const auto& b = barnase();
  const auto& atom_of = b.surface.integer_attributes.at("atomid");
  double sum = 0;
  int count = 0;
  for (std::size_t v = 0; v < potential.size(); ++v) {
    const Atom& a = b.atoms[atom_of[v]];
    if (a.residue_name == residue && std::find(names.begin(), names.end(), a.name) != names.end())
      sum += potential[v], ++count;
  }
  EXPECT_GT(count, 20) << residue;
  return sum / count;
}

#define SKIP_WITHOUT(condition, what) \
  if (!(condition)) GTEST_SKIP() << what << " is not installed or not found: test skipped"

TEST(DataElectrostatics, Pdb2pqrGivesBarnaseItsNetChargeOfPlusTwo) {
  SKIP_WITHOUT(std::filesystem::exists(kData / "pdb/misc/1brs.pdb"), "../shared/data/pdb/misc/1brs.pdb");
  SKIP_WITHOUT(pdb2pqr_available(), "pdb2pqr30 (Debian package pdb2pqr)");
  const auto& b = barnase();
  for (const auto force_field : {ForceField::kAmber, ForceField::kParse}) {
    const ChargeAssignment c = pdb2pqr_charges(b.atoms, force_field, "1brs.pdb");
    EXPECT_NEAR(c.net_charge, 2.0, 1e-6) << to_string(force_field);
    EXPECT_EQ(c.atoms_unmatched, 0);
    EXPECT_EQ(c.atoms_charged, static_cast<std::int64_t>(b.atoms.size()));
    EXPECT_EQ(c.added_hydrogens, c.added_atoms);
    EXPECT_GT(c.added_hydrogens, 800);  // 836 with either force field
    // Without the hydrogens' charges the heavy atoms alone sum to about -100 e: what made a PQR's per-vertex
    // charges read barnase as mostly negative.
    double heavy = 0;
    for (const double q : c.atom_charges) heavy += q;
    EXPECT_LT(heavy, -50);
  }
  EXPECT_NEAR(formal_charges(b.atoms).net_charge, 2.0, 1e-12);
}

TEST(DataElectrostatics, BarnaseSurfaceIsMostlyPositiveNearLysinesAndNegativeNearCarboxylates) {
  SKIP_WITHOUT(std::filesystem::exists(kData / "pdb/misc/1brs.pdb"), "../shared/data/pdb/misc/1brs.pdb");
  SKIP_WITHOUT(pdb2pqr_available(), "pdb2pqr30 (Debian package pdb2pqr)");
  const auto& b = barnase();
  ElectrostaticsOptions options;
  options.charges = ChargeChoice::kPdb2pqr;
  const ElectrostaticsResult r = surface_electrostatics(b.surface, b.atoms, kData / "pdb/misc/1brs.pdb", options);
  EXPECT_EQ(r.source, "Coulomb, epsilon = 4r, charges: pdb2pqr (AMBER)");
  double mean = 0, negative = 0;
  for (const double v : r.potential) mean += v, negative += v < 0;
  mean /= static_cast<double>(r.potential.size());
  negative /= static_cast<double>(r.potential.size());
  EXPECT_GT(mean, 1.0);                                   // measured +2.8 kT/e
  EXPECT_LT(negative, 0.45);                              // measured 36.5%, not "84% negative"
  EXPECT_GT(mean_near(r.potential, "LYS", {"NZ"}), 5.0);  // measured +12.7
  EXPECT_LT(mean_near(r.potential, "ASP", {"OD1", "OD2"}), -1.0);
  EXPECT_LT(mean_near(r.potential, "GLU", {"OE1", "OE2"}), -1.0);
}

TEST(DataElectrostatics, ApbsRunForTheUserAgreesWithCoulombOnBarnase) {
  SKIP_WITHOUT(std::filesystem::exists(kData / "pdb/misc/1brs.pdb"), "../shared/data/pdb/misc/1brs.pdb");
  SKIP_WITHOUT(pdb2pqr_available(), "pdb2pqr30 (Debian package pdb2pqr)");
  SKIP_WITHOUT(apbs_available(), "apbs (Debian package apbs)");
  const auto& b = barnase();
  ElectrostaticsOptions options;
  options.method = ElectrostaticsMethod::kApbs;
  options.apbs.grid_spacing = 0.7;  // a 97^3 grid: a few seconds
  std::vector<std::string> progress;
  const ElectrostaticsResult apbs = surface_electrostatics(b.surface, b.atoms, kData / "pdb/misc/1brs.pdb", options,
                                                           [&](const std::string& line) { progress.push_back(line); });
  ASSERT_GE(progress.size(), 4u);
  EXPECT_EQ(progress.front().rfind("pdb2pqr30: adding hydrogens", 0), 0u) << progress.front();
  EXPECT_EQ(std::count_if(progress.begin(), progress.end(),
                          [](const std::string& line) {
                            return line.rfind("apbs: solving the Poisson-Boltzmann equation on 97 x 97 x 97 points",
                                              0) == 0;
                          }),
            1);
  EXPECT_EQ(progress.back().rfind("apbs: done in", 0), 0u) << progress.back();
  ASSERT_TRUE(apbs.charges.has_value());
  EXPECT_NEAR(apbs.charges->net_charge, 2.0, 1e-6);
  options.method = ElectrostaticsMethod::kCoulomb;
  options.charges = ChargeChoice::kPdb2pqr;
  const ElectrostaticsResult coulomb = surface_electrostatics(b.surface, b.atoms, kData / "pdb/misc/1brs.pdb", options);
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  const auto n = static_cast<double>(apbs.potential.size());
  for (std::size_t v = 0; v < apbs.potential.size(); ++v) {
    const double x = apbs.potential[v], y = coulomb.potential[v];
    ASSERT_TRUE(std::isfinite(x));
    sx += x, sy += y, sxx += x * x, syy += y * y, sxy += x * y;
  }
  EXPECT_GT(sx / n, 0.5);  // mean: measured +1.5 kT/e
  EXPECT_GT((sxy - sx * sy / n) / std::sqrt((sxx - sx * sx / n) * (syy - sy * sy / n)), 0.5);  // measured 0.67
  EXPECT_GT(mean_near(apbs.potential, "LYS", {"NZ"}), 1.0);                                    // measured +3.4
  EXPECT_LT(mean_near(apbs.potential, "ASP", {"OD1", "OD2"}) + mean_near(apbs.potential, "GLU", {"OE1", "OE2"}), 0);
}

TEST(DataElectrostatics, Pdb2pqrReadsOldDnaResidueNames) {
  const auto file = kData / "pdb/misc/104d.pdb";  // a DNA-RNA hybrid with one-letter residue names
  SKIP_WITHOUT(std::filesystem::exists(file), "../shared/data/pdb/misc/104d.pdb");
  SKIP_WITHOUT(pdb2pqr_available(), "pdb2pqr30 (Debian package pdb2pqr)");
  const auto atoms = read_structure(file).atoms;
  const ChargeAssignment c = pdb2pqr_charges(atoms, ForceField::kAmber, "104d.pdb");
  EXPECT_EQ(c.atoms_unmatched, 0) << "pdb2pqr dropped residues";
  EXPECT_GT(c.added_hydrogens, 0);
  EXPECT_NEAR(c.net_charge, std::round(c.net_charge), 1e-3);
  EXPECT_LT(c.net_charge, -10);
  ASSERT_FALSE(c.warnings.empty());
  EXPECT_NE(c.warnings.back().find("DNA residues named A/C/G/T/U/I given to pdb2pqr as DA/DC/DG/DT/DU/DI"),
            std::string::npos);
}

// pdb2pqr 3.5's PARSE has no DNA parameters and gives up on this hybrid (a non-integral total charge).
TEST(DataElectrostatics, Pdb2pqrFailingIsAnErrorOrFormalCharges) {
  const auto file = kData / "pdb/misc/104d.pdb";
  SKIP_WITHOUT(std::filesystem::exists(file), "../shared/data/pdb/misc/104d.pdb");
  SKIP_WITHOUT(pdb2pqr_available(), "pdb2pqr30 (Debian package pdb2pqr)");
  const auto atoms = read_structure(file).atoms;
  ElectrostaticsOptions options;
  options.force_field = ForceField::kParse;
  options.charges = ChargeChoice::kPdb2pqr;
  try {
    assign_charges(atoms, file, options);
    ADD_FAILURE() << "pdb2pqr --ff=PARSE did not fail on 104d";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("pdb2pqr30 --ff=PARSE failed on this structure"), std::string::npos) << message;
    EXPECT_NE(message.find("Use --charges formal"), std::string::npos) << message;
  }
  options.charges = ChargeChoice::kAuto;
  const ChargeAssignment charges = assign_charges(atoms, file, options);
  EXPECT_EQ(charges.source, "formal");
  ASSERT_FALSE(charges.warnings.empty());
  EXPECT_EQ(charges.warnings.back().rfind("formal charges, because pdb2pqr failed", 0), 0u);
  EXPECT_EQ(charges.net_charge, -22);  // 24 nucleotides, the two 5' ends without a phosphate
}

}  // namespace
}  // namespace spheremap
