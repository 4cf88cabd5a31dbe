#pragma once
// The deterministic gather of the force pass: each NURBS point adds its forces into its cell's slots (one
// per support control point), each point with a fallback basis writes its own support's slots, and
// control point i then sums cell_force[entries[k]] for k in offsets[i] .. offsets[i + 1], then
// slot_force[slot_entries[k]] for k in slot_offsets[i] .. slot_offsets[i + 1], in a fixed order whatever
// the threads did.
#include <cstddef>
#include <vector>

#include "shell/crack_bases.hpp"
#include "shell/kinematics.hpp"

namespace shellfrac::shell {

struct ForceGather {
  std::vector<Vec3> cell_force;   // cells x support_size
  std::vector<int> offsets;       // control point -> its range of entries
  std::vector<int> entries;       // slots of cell_force, grouped by control point
  std::vector<Vec3> slot_force;   // the fallback bases' forces, slot after slot (MlsSupport::force_offset)
  std::vector<int> slot_offsets;  // control point -> its range of slot_entries
  std::vector<int> slot_entries;  // entries of slot_force, grouped by control point, in slot order

  Vec3* forces_of(const MlsSupport& m) { return slot_force.data() + m.force_offset; }
};

// From the cells' supports (cells x support_size control point indices), with no fallback bases yet.
ForceGather make_force_gather(const std::vector<int>& support, size_t num_control_points);

// After the fallback bases changed: places every slot's forces in slot_force (setting its force_offset)
// and rebuilds the control points' slot gather.
void lay_out_slot_forces(std::vector<MlsSupport>& slots, ForceGather& gather);

}  // namespace shellfrac::shell
