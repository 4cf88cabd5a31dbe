#include "shell/crack_bases.hpp"

#include <algorithm>

namespace shellfrac::shell {

CrackBases uncut_bases(size_t num_control_points, size_t num_points, size_t num_cells) {
  CrackBases cut;
  cut.point_slot.assign(num_points, -1);
  cut.shear_slot.assign(num_cells, -1);
  cut.control_near_crack.assign(num_control_points, 0);
  cut.shear_near_crack.assign(num_cells, 0);
  cut.cut_cells.assign(num_cells, 0);
  cut.gather_offsets.assign(num_control_points + 1, 0);
  return cut;
}

void rebuild_gather(CrackBases& cut, size_t points_per_cell) {
  size_t entries = 0;
  for (MlsSupport& m : cut.slots) {
    m.force_offset = entries;
    entries += m.index.size();
  }
  cut.slot_force.assign(entries, Vec3::Zero());
  // Control point -> its entries of slot_force, in slot order.
  std::fill(cut.gather_offsets.begin(), cut.gather_offsets.end(), 0);
  std::fill(cut.control_near_crack.begin(), cut.control_near_crack.end(), 0);
  for (const MlsSupport& m : cut.slots)
    for (int k : m.index) ++cut.gather_offsets[static_cast<size_t>(k) + 1];
  for (size_t i = 0; i + 1 < cut.gather_offsets.size(); ++i) cut.gather_offsets[i + 1] += cut.gather_offsets[i];
  cut.gather.resize(static_cast<size_t>(cut.gather_offsets.back()));
  std::vector<int> cursor(cut.gather_offsets.begin(), cut.gather_offsets.end() - 1);
  for (const MlsSupport& m : cut.slots)
    for (size_t e = 0; e < m.index.size(); ++e) {
      const auto k = static_cast<size_t>(m.index[e]);
      cut.gather[static_cast<size_t>(cursor[k]++)] = static_cast<int>(m.force_offset + e);
      cut.control_near_crack[k] = 1;
    }
  for (size_t c = 0; c < cut.shear_slot.size(); ++c) cut.shear_near_crack[c] = cut.shear_slot[c] != -1;
  std::fill(cut.cut_cells.begin(), cut.cut_cells.end(), 0);
  for (size_t q = 0; q < cut.point_slot.size(); ++q)
    if (cut.point_slot[q] >= 0) cut.cut_cells[q / points_per_cell] = 1;
}

}  // namespace shellfrac::shell
