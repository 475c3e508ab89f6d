#include "spheremap/properties/coulomb.hpp"

#include <cmath>
#include <stdexcept>

#include "treecode.hpp"

namespace spheremap {

double bjerrum_length(double temperature) {
  if (!(temperature > 0) || !std::isfinite(temperature))
    throw std::invalid_argument("bjerrum_length: the temperature must be positive (K)");
  return kCoulombAngstromKelvin / temperature;
}

namespace {

void check(const PointCharges& charges, const CoulombOptions& options) {
  if (charges.positions.size() != charges.charges.size())
    throw std::invalid_argument("coulomb_potential: as many charges as positions are needed");
  for (std::size_t i = 0; i < charges.charges.size(); ++i) {
    const Vec3& p = charges.positions[i];
    if (!std::isfinite(charges.charges[i]) || !std::isfinite(p[0]) || !std::isfinite(p[1]) || !std::isfinite(p[2]))
      throw std::invalid_argument("coulomb_potential: a charge or its position is not finite");
  }
  if (!(options.dielectric_value > 0) || !std::isfinite(options.dielectric_value))
    throw std::invalid_argument("coulomb_potential: the dielectric value must be positive");
}

}  // namespace

std::vector<double> coulomb_potential(const PointCharges& charges, const std::vector<Vec3>& points,
                                      const CoulombOptions& options) {
  check(charges, options);
  const double factor = bjerrum_length(options.temperature) / options.dielectric_value;
  // Zero charges (most atoms under formal charges) cost time and add nothing.
  std::vector<Vec3> positions;
  std::vector<double> values;
  for (std::size_t i = 0; i < charges.charges.size(); ++i)
    if (charges.charges[i] != 0) {
      positions.push_back(charges.positions[i]);
      values.push_back(charges.charges[i]);
    }
  // ε = κr makes each term q / (κ r²): the kernel is 1/r², with its own expansion.
  const auto kernel = options.dielectric == Dielectric::kDistanceDependent ? detail::PowerKernel::kInverseSquare
                                                                           : detail::PowerKernel::kInverseDistance;
  const bool exact = options.summation == CoulombSummation::kExact ||
                     (options.summation == CoulombSummation::kAuto &&
                      static_cast<double>(points.size()) * static_cast<double>(values.size()) <= kExactCoulombPairs);
  std::vector<double> phi;
  if (exact) {
    phi = detail::direct_power_sum(positions, values, points, kernel, options.threads);
  } else {
    detail::TreecodeParameters parameters;
    parameters.theta = options.treecode.theta;
    parameters.order = options.treecode.order;
    parameters.source_leaf_size = options.treecode.charges_per_leaf;
    parameters.target_leaf_size = options.treecode.points_per_leaf;
    parameters.threads = options.threads;
    phi = detail::treecode_power_sum(positions, values, points, kernel, parameters);
  }
  for (double& value : phi) value *= factor;
  return phi;
}

double relative_rms_difference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) throw std::invalid_argument("relative_rms_difference: the sizes differ");
  double difference = 0, reference = 0;
  for (std::size_t i = 0; i < a.size(); ++i) {
    difference += (a[i] - b[i]) * (a[i] - b[i]);
    reference += b[i] * b[i];
  }
  if (reference == 0) return difference == 0 ? 0 : INFINITY;
  return std::sqrt(difference / reference);
}

}  // namespace spheremap
