#pragma once
#include <Eigen/Core>
#include <vector>

#include "core/weibull.hpp"

namespace shellfrac::brittle {

// A part of the object (in material space) with its own failure stress, e.g. a weak seam or a strong
// core. Later regions in a list override earlier ones where they overlap.
struct StrengthRegion {
  enum class Shape { Box, Sphere } shape = Shape::Box;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d half_extents = Eigen::Vector3d::Zero();  // Box
  double radius = 0;                                       // Sphere
  double failure_stress = 0;                               // sigma_f inside [Pa]
  bool contains(const Eigen::Vector3d& x) const;
};

// Heterogeneous strength: sigma_f per particle drawn from a Weibull distribution (core/weibull.hpp),
// with the local sigma_f (material or region) as its scale, or as its mean when scale_is_mean.
using WeibullStrength = core::WeibullStrength;

// Failure stress of every particle: `base` everywhere, the regions' values inside them, then the Weibull
// factor. Throws InputError for non-positive stresses or a Weibull modulus <= 0.
std::vector<double> assign_failure_stress(const std::vector<Eigen::Vector3d>& rest_positions, double base,
                                          const std::vector<StrengthRegion>& regions, const WeibullStrength& weibull);

using core::hashed_uniform;

}  // namespace shellfrac::brittle
