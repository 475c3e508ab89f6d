// The Coulomb potential of point charges at points (the built-in electrostatics of the surface).
#pragma once

#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Point charges: positions in Å, charges in e (same length).
struct PointCharges {
  std::vector<Vec3> positions;
  std::vector<double> charges;
};

/// e²/(4πε₀ k_B) in Å·K, from CODATA 2018 (e and k_B exact, ε₀ = 8.8541878128e-12 F/m, relative
/// uncertainty 1.5e-10): divided by a temperature it is the Bjerrum length in vacuum, 560.459 Å at 298.15 K.
inline constexpr double kCoulombAngstromKelvin = 167100.94689828737;

inline constexpr double kDefaultTemperature = 298.15;  // K

/// e²/(4πε₀ k T) in Å: the potential of a unit charge at 1 Å in vacuum, in kT/e.
/// Precondition: temperature > 0 (K); throws std::invalid_argument otherwise.
double bjerrum_length(double temperature);

enum class Dielectric {
  kDistanceDependent,  // ε(r) = value · r, r in Å (ChimeraX `coulombic`'s default, value 4)
  kConstant,           // ε = value
};

enum class CoulombSummation {
  kAuto,      // exact when points × charges <= kExactCoulombPairs, else the treecode
  kExact,     // every pair
  kTreecode,  // multipole treecode (see TreecodeOptions)
};

inline constexpr double kExactCoulombPairs = 2e7;

/// The treecode's accuracy knobs (a dual-tree walk with Cartesian Taylor expansions fitted to the kernel,
/// 1/r or 1/r²). The defaults keep the relative RMS error against the exact sum near 1e-4 on proteins.
struct TreecodeOptions {
  /// A cell of charges and a cell of points interact through expansions when r_charges + r_points < theta
  /// times the distance of their centres (r: a cell's radius); smaller is more accurate and slower. In (0, 1).
  double theta = 0.4;
  /// Highest order of the expansions (0 charge, 1 dipole, 2 quadrupole, 3 octupole, ... 6); the error falls
  /// about as theta^(order + 1).
  int order = 3;
  int charges_per_leaf = 32;  // charges of a leaf of the charge tree (summed exactly with the near points)
  int points_per_leaf = 128;  // points of a leaf of the point tree
};

struct CoulombOptions {
  Dielectric dielectric = Dielectric::kDistanceDependent;
  double dielectric_value = 4;               // κ of ε(r) = κr, or the constant ε
  double temperature = kDefaultTemperature;  // K
  CoulombSummation summation = CoulombSummation::kAuto;
  TreecodeOptions treecode;
  int threads = 0;  // 0: one per hardware thread; the result is the same bytes for any count
};

/// φ(x) = (e²/(4πε₀ k T)) Σ_i q_i / (ε(r_i) r_i) in kT/e at every point x, r_i = |x - position_i| in Å.
/// Charges of zero are skipped. Deterministic: the same bytes whatever options.threads.
/// Preconditions: charges.positions.size() == charges.charges.size(), every charge and position finite,
/// dielectric_value > 0, temperature > 0, treecode options in range; throws std::invalid_argument otherwise.
/// A point on a charge gets an infinite value (points 1.4 Å outside a molecular surface never are).
std::vector<double> coulomb_potential(const PointCharges& charges, const std::vector<Vec3>& points,
                                      const CoulombOptions& options = {});

/// sqrt(Σ (a - b)²) / sqrt(Σ b²): the relative RMS difference of `a` from the reference `b` (0 when both are
/// zero). Throws std::invalid_argument when the sizes differ.
double relative_rms_difference(const std::vector<double>& a, const std::vector<double>& b);

}  // namespace spheremap
