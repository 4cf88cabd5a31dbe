#pragma once
// The deterministic gather of the force pass: each NURBS point adds its forces into its cell's slots (one
// per support control point), and control point i then sums cell_force[entries[k]] for k in
// offsets[i] .. offsets[i + 1], in a fixed order whatever the threads did.
#include <cstddef>
#include <vector>

#include "shell/kinematics.hpp"

namespace shellfrac::shell {

struct ForceGather {
  std::vector<Vec3> cell_force;  // cells x support_size
  std::vector<int> offsets;      // control point -> its range of entries
  std::vector<int> entries;      // slots of cell_force, grouped by control point
};

// From the cells' supports (cells x support_size control point indices).
ForceGather make_force_gather(const std::vector<int>& support, size_t num_control_points);

}  // namespace shellfrac::shell
