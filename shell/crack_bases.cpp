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
  return cut;
}

void mark_near_crack(CrackBases& cut, size_t points_per_cell) {
  std::fill(cut.control_near_crack.begin(), cut.control_near_crack.end(), 0);
  for (const MlsSupport& m : cut.slots)
    for (int k : m.index) cut.control_near_crack[static_cast<size_t>(k)] = 1;
  for (size_t c = 0; c < cut.shear_slot.size(); ++c) cut.shear_near_crack[c] = cut.shear_slot[c] != -1;
  std::fill(cut.cut_cells.begin(), cut.cut_cells.end(), 0);
  for (size_t q = 0; q < cut.point_slot.size(); ++q)
    if (cut.point_slot[q] >= 0) cut.cut_cells[q / points_per_cell] = 1;
}

}  // namespace shellfrac::shell
