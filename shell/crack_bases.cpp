#include "shell/crack_bases.hpp"

#include <algorithm>

namespace shellfrac::shell {

CrackBases uncut_bases(size_t num_control_points, size_t num_points, size_t num_cells) {
  CrackBases cut;
  cut.point_slot.assign(num_points, -1);
  cut.shear_slot.assign(num_cells, -1);
  cut.control_near_crack.assign(num_control_points, 0);
  cut.shear_near_crack.assign(num_cells, 0);
  cut.gather_offsets.assign(num_control_points + 1, 0);
  return cut;
}

void rebuild_gather(CrackBases& cut) {
  // Control point -> (slot, entry) in slot order.
  std::fill(cut.gather_offsets.begin(), cut.gather_offsets.end(), 0);
  std::fill(cut.control_near_crack.begin(), cut.control_near_crack.end(), 0);
  for (const MlsSupport& m : cut.slots)
    for (int k : m.index) ++cut.gather_offsets[static_cast<size_t>(k) + 1];
  for (size_t i = 0; i + 1 < cut.gather_offsets.size(); ++i) cut.gather_offsets[i + 1] += cut.gather_offsets[i];
  cut.gather.resize(static_cast<size_t>(cut.gather_offsets.back()));
  std::vector<int> cursor(cut.gather_offsets.begin(), cut.gather_offsets.end() - 1);
  for (size_t s = 0; s < cut.slots.size(); ++s)
    for (size_t e = 0; e < cut.slots[s].index.size(); ++e) {
      const auto k = static_cast<size_t>(cut.slots[s].index[e]);
      cut.gather[static_cast<size_t>(cursor[k]++)] = {static_cast<int>(s), static_cast<int>(e)};
      cut.control_near_crack[k] = 1;
    }
  for (size_t c = 0; c < cut.shear_slot.size(); ++c) cut.shear_near_crack[c] = cut.shear_slot[c] != -1;
}

}  // namespace shellfrac::shell
