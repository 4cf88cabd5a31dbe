#include "brittle/strength.hpp"

#include <cmath>
#include <string>

#include "brittle/errors.hpp"

namespace shellfrac::brittle {

bool StrengthRegion::contains(const Eigen::Vector3d& x) const {
  if (shape == Shape::Sphere) return (x - centre).squaredNorm() <= radius * radius;
  return ((x - centre).cwiseAbs() - half_extents).maxCoeff() <= 0.0;
}

double hashed_uniform(unsigned long long seed, unsigned long long index) {
  unsigned long long z = seed * 0x9E3779B97F4A7C15ULL + index + 0x632BE59BD9B4E019ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return (static_cast<double>(z >> 11) + 0.5) * (1.0 / 9007199254740992.0);  // 53 bits, never 0 or 1
}

std::vector<double> assign_failure_stress(const std::vector<Eigen::Vector3d>& x, double base,
                                          const std::vector<StrengthRegion>& regions, const WeibullStrength& weibull) {
  if (!(base > 0)) throw InputError("failure_stress must be > 0 (got " + std::to_string(base) + ")");
  for (size_t r = 0; r < regions.size(); ++r)
    if (!(regions[r].failure_stress > 0))
      throw InputError("strength region " + std::to_string(r) + ": failure_stress must be > 0");
  if (weibull.enabled && !(weibull.modulus > 0))
    throw InputError("weibull modulus must be > 0 (got " + std::to_string(weibull.modulus) + ")");
  // Mean of a unit-scale Weibull variate: Gamma(1 + 1/m).
  const double unit_mean = weibull.enabled ? std::tgamma(1.0 + 1.0 / weibull.modulus) : 1.0;
  std::vector<double> s(x.size(), base);
  for (size_t p = 0; p < x.size(); ++p) {
    for (const StrengthRegion& r : regions)
      if (r.contains(x[p])) s[p] = r.failure_stress;
    if (weibull.enabled) {
      // Inverse CDF: s0 (-ln(1 - U))^(1/m).
      const double u = hashed_uniform(weibull.seed, p);
      double factor = std::pow(-std::log1p(-u), 1.0 / weibull.modulus);
      if (weibull.scale_is_mean) factor /= unit_mean;
      s[p] *= factor;
    }
  }
  return s;
}

}  // namespace shellfrac::brittle
