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
  return out;
}

}  // namespace shellfrac::shell
