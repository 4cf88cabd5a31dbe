#include "shell/force_gather.hpp"

namespace shellfrac::shell {

ForceGather make_force_gather(const std::vector<int>& support, size_t num_control_points) {
  ForceGather out;
  out.cell_force.assign(support.size(), Vec3::Zero());
  out.offsets.assign(num_control_points + 1, 0);
  for (int c : support) ++out.offsets[static_cast<size_t>(c) + 1];
  for (size_t i = 0; i < num_control_points; ++i) out.offsets[i + 1] += out.offsets[i];
  out.entries.resize(support.size());
  std::vector<int> cursor(out.offsets.begin(), out.offsets.end() - 1);
  for (size_t k = 0; k < support.size(); ++k)
    out.entries[static_cast<size_t>(cursor[static_cast<size_t>(support[k])]++)] = static_cast<int>(k);
  out.slot_offsets.assign(num_control_points + 1, 0);
  return out;
}

void lay_out_slot_forces(std::vector<MlsSupport>& slots, ForceGather& gather) {
  size_t entries = 0;
  for (MlsSupport& m : slots) {
    m.force_offset = entries;
    entries += m.index.size();
  }
  gather.slot_force.assign(entries, Vec3::Zero());
  std::vector<int>& offsets = gather.slot_offsets;
  std::fill(offsets.begin(), offsets.end(), 0);
  for (const MlsSupport& m : slots)
    for (int k : m.index) ++offsets[static_cast<size_t>(k) + 1];
  for (size_t i = 0; i + 1 < offsets.size(); ++i) offsets[i + 1] += offsets[i];
  gather.slot_entries.resize(static_cast<size_t>(offsets.back()));
  std::vector<int> cursor(offsets.begin(), offsets.end() - 1);
  for (const MlsSupport& m : slots)
    for (size_t e = 0; e < m.index.size(); ++e)
      gather.slot_entries[static_cast<size_t>(cursor[static_cast<size_t>(m.index[e])]++)] =
          static_cast<int>(m.force_offset + e);
}

}  // namespace shellfrac::shell
