#include "core/weibull.hpp"

#include <cmath>

namespace shellfrac::core {

double hashed_uniform(unsigned long long seed, unsigned long long index) {
  unsigned long long z = seed * 0x9E3779B97F4A7C15ULL + index + 0x632BE59BD9B4E019ULL;
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  z ^= z >> 31;
  return (static_cast<double>(z >> 11) + 0.5) * (1.0 / 9007199254740992.0);  // 53 bits
}

double weibull_factor(const WeibullStrength& w, unsigned long long index) {
  if (!w.enabled) return 1.0;
  const double factor = std::pow(-std::log1p(-hashed_uniform(w.seed, index)), 1.0 / w.modulus);
  // The mean of a unit-scale Weibull variate is Gamma(1 + 1/m).
  return w.scale_is_mean ? factor / std::tgamma(1.0 + 1.0 / w.modulus) : factor;
}

}  // namespace shellfrac::core
