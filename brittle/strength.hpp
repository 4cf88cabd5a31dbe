#pragma once
#include <Eigen/Core>
#include <vector>

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

// Heterogeneous strength: sigma_f per particle drawn from a Weibull distribution,
// P(sigma_f <= s) = 1 - exp(-(s / s0)^m), with the local sigma_f (material or region) as s0, or as the
// mean when scale_is_mean. Each particle's draw depends only on (seed, particle index): the same for any
// thread count and any order of evaluation.
struct WeibullStrength {
  bool enabled = false;
  double modulus = 0;  // m (Weibull modulus; glass ~ 5-15, ceramics ~ 10-20)
  bool scale_is_mean = false;
  unsigned long long seed = 1;
};

// Failure stress of every particle: `base` everywhere, the regions' values inside them, then the Weibull
// factor. Throws InputError for non-positive stresses or a Weibull modulus <= 0.
std::vector<double> assign_failure_stress(const std::vector<Eigen::Vector3d>& rest_positions, double base,
                                          const std::vector<StrengthRegion>& regions, const WeibullStrength& weibull);

// Uniform number in (0, 1) from (seed, index) by a SplitMix64 hash (counter-based, order-independent).
double hashed_uniform(unsigned long long seed, unsigned long long index);

}  // namespace shellfrac::brittle
