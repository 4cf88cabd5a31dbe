#include "shell/basis_stiffness.hpp"

#include <algorithm>
#include <cmath>

namespace shellfrac::shell {

BasisStiffness stiffness_of(const BasisRows& rows, const std::vector<double>& mass,
                            const std::vector<double>& added_mass) {
  BasisStiffness out;
  for (size_t i = 0; i < mass.size(); ++i) {
    if (!(mass[i] > 0)) continue;
    const double m = mass[i] + added_mass[i];
    out.membrane = std::max(out.membrane, rows.membrane[i] / m);
    out.bending = std::max(out.bending, rows.bending[i] / m);
  }
  return out;
}

void choose_added_mass(const BasisRows& rows, const std::vector<double>& mass, const BasisStiffness& reference,
                       double budget, std::vector<double>& added_mass) {
  added_mass.assign(mass.size(), 0.0);
  if (!(budget > 0)) return;
  // Added mass for a ratio kappa above the uncut sheet's: m_i' = max(m_i, k_i / (kappa k_ref)) per term.
  auto need = [&](double kappa, size_t i) {
    double m = mass[i];
    auto raise = [&](double row, double ref) {
      const double target = kappa * ref * (1 + 1e-9);
      if (ref > 0 && row > target * m) m = row / target;
    };
    raise(rows.membrane[i], reference.membrane);
    raise(rows.bending[i], reference.bending);
    return m - mass[i];
  };
  auto total = [&](double kappa) {
    double sum = 0;
    for (size_t i = 0; i < mass.size(); ++i)
      if (mass[i] > 0) sum += need(kappa, i);
    return sum;
  };
  double control_mass = 0;
  for (double m : mass) control_mass += m;
  const double allowed = budget * control_mass;
  // The smallest kappa >= 1 whose added mass fits (the total falls as kappa grows).
  double lo = 1.0, hi = 1.0;
  if (total(1.0) > allowed) {
    while (total(hi) > allowed && hi < 1e12) hi *= 2;
    for (int it = 0; it < 60; ++it) {
      const double mid = std::sqrt(lo * hi);
      (total(mid) > allowed ? lo : hi) = mid;
    }
    lo = hi;
  }
  for (size_t i = 0; i < mass.size(); ++i)
    if (mass[i] > 0) added_mass[i] = need(lo, i);
}

}  // namespace shellfrac::shell
