#pragma once
// What the material remembers at each layer point between steps: plastic strain (thesis sec. 4.4.2) and
// Rankine damage with its history and per-point strength (thesis sec. 4.4.1). Arrays are empty when the
// material has no such behaviour.
#include <cstddef>
#include <vector>

namespace shellfrac::shell {

struct PointMaterialState {
  std::vector<double> plastic_strain;          // in-plane points x layers, plastic materials only
  std::vector<double> damage, damage_history;  // c and c_his, in-plane points x layers, fracturing only
  std::vector<double> failure_stress;          // sigma_f per in-plane point, fracturing only
  std::vector<double> brittleness;             // H per in-plane point (thesis Eq. 2.28), fracturing only

  bool fractures() const { return !damage.empty(); }
  // The damage history of some layer of in-plane point q reached 1 (fracturing materials only).
  bool fully_damaged(size_t q, size_t layers) const;
  // How many in-plane points are fully damaged (0 quickly when none is).
  size_t count_fully_damaged(size_t points, size_t layers) const;
};

}  // namespace shellfrac::shell
