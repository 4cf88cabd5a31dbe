#include "brittle/hertz.hpp"

#include <cmath>
#include <string>

#include "brittle/errors.hpp"

namespace shellfrac::brittle {

double hertz_effective_modulus(const HertzBody& a, const HertzBody& b) {
  return 1.0 / ((1.0 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                (1.0 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
}

double hertz_effective_radius(const HertzBody& a, const HertzBody& b) { return 1.0 / (1.0 / a.radius + 1.0 / b.radius); }

double hertz_effective_mass(const HertzBody& a, const HertzBody& b) { return 1.0 / (1.0 / a.mass + 1.0 / b.mass); }

double hertz_contact_time(const HertzBody& a, const HertzBody& b, double v) {
  const HertzBody* bodies[2] = {&a, &b};
  for (int k = 0; k < 2; ++k) {
    const HertzBody& s = *bodies[k];
    const std::string who = "hertz body " + std::to_string(k + 1) + ": ";
    if (!(s.youngs_modulus > 0)) throw InputError(who + "youngs_modulus must be > 0");
    if (!(s.poisson_ratio > -1.0 && s.poisson_ratio < 0.5)) throw InputError(who + "poisson_ratio must be in (-1, 0.5)");
    if (!(s.radius > 0)) throw InputError(who + "radius must be > 0 (use infinity for a plane)");
    if (!(s.mass > 0)) throw InputError(who + "mass must be > 0 (use infinity for a fixed body)");
  }
  if (std::isinf(a.radius) && std::isinf(b.radius)) throw InputError("hertz: two planes have no contact radius");
  if (std::isinf(a.mass) && std::isinf(b.mass)) throw InputError("hertz: two fixed bodies have no contact mass");
  if (!(v > 0) || !std::isfinite(v)) throw InputError("hertz: relative_speed must be > 0 and finite");
  const double E = hertz_effective_modulus(a, b), R = hertz_effective_radius(a, b), m = hertz_effective_mass(a, b);
  return 2.87 * std::pow(m * m / (E * E * R * v), 0.2);
}

}  // namespace shellfrac::brittle
