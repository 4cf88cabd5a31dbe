#include "brittle/strength.hpp"

#include <cmath>
#include <string>

#include "brittle/errors.hpp"

namespace shellfrac::brittle {

bool StrengthRegion::contains(const Eigen::Vector3d& x) const {
  if (shape == Shape::Sphere) return (x - centre).squaredNorm() <= radius * radius;
  return ((x - centre).cwiseAbs() - half_extents).maxCoeff() <= 0.0;
}

std::vector<double> assign_failure_stress(const std::vector<Eigen::Vector3d>& x, double base,
                                          const std::vector<StrengthRegion>& regions, const WeibullStrength& weibull) {
  if (!(base > 0)) throw InputError("failure_stress must be > 0 (got " + std::to_string(base) + ")");
  for (size_t r = 0; r < regions.size(); ++r)
    if (!(regions[r].failure_stress > 0))
      throw InputError("strength region " + std::to_string(r) + ": failure_stress must be > 0");
  if (weibull.enabled && !(weibull.modulus > 0))
    throw InputError("weibull modulus must be > 0 (got " + std::to_string(weibull.modulus) + ")");
  std::vector<double> s(x.size(), base);
  for (size_t p = 0; p < x.size(); ++p) {
    for (const StrengthRegion& r : regions)
      if (r.contains(x[p])) s[p] = r.failure_stress;
    s[p] *= core::weibull_factor(weibull, p);
  }
  return s;
}

}  // namespace shellfrac::brittle
