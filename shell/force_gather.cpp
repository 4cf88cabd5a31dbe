#include "shell/force_gather.hpp"

namespace shellfrac::shell {

namespace {

// Groups entries by control point: visit(emit) calls emit(control point, entry) for every entry, in the
// order the gather must sum them; afterwards control point i's entries are entries[offsets[i] ..
// offsets[i + 1]), in that order.
template <class Visit>
void group_by_control_point(size_t num_control_points, Visit visit, std::vector<int>& offsets,
                            std::vector<int>& entries) {
  offsets.assign(num_control_points + 1, 0);
  visit([&](int control_point, int) { ++offsets[static_cast<size_t>(control_point) + 1]; });
  for (size_t i = 0; i < num_control_points; ++i) offsets[i + 1] += offsets[i];
  entries.resize(static_cast<size_t>(offsets.back()));
  std::vector<int> cursor(offsets.begin(), offsets.end() - 1);
  visit([&](int control_point, int entry) {
    entries[static_cast<size_t>(cursor[static_cast<size_t>(control_point)]++)] = entry;
  });
}

}  // namespace

ForceGather make_force_gather(const std::vector<int>& support, size_t num_control_points) {
  ForceGather out;
  out.cell_force.assign(support.size(), Vec3::Zero());
  group_by_control_point(
      num_control_points,
      [&](auto emit) {
        for (size_t k = 0; k < support.size(); ++k) emit(support[k], static_cast<int>(k));
      },
      out.offsets, out.entries);
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
  group_by_control_point(
      gather.offsets.size() - 1,
      [&](auto emit) {
        for (const MlsSupport& m : slots)
          for (size_t e = 0; e < m.index.size(); ++e) emit(m.index[e], static_cast<int>(m.force_offset + e));
      },
      gather.slot_offsets, gather.slot_entries);
}

}  // namespace shellfrac::shell
