// ShellPatch::deformation_gradients: F^KL per layer point, for inspection (the Python module, plots).
#include <limits>

#include "shell/shell_patch.hpp"

namespace shellfrac::shell {

std::vector<Mat3> ShellPatch::deformation_gradients() const {
  const size_t L = quad_.num_layers();
  const bool mid_surface =
      material_.stress_model == StressModel::MidSurface2D || material_.stress_model == StressModel::DirectorF2D;
  const auto& rest = reference_.control_points();
  std::vector<Mat3> out(quad_.param.size() * L, Mat3::Constant(std::numeric_limits<double>::quiet_NaN()));
  std::vector<const Vec3*> cur, ref;
  for (size_t q = 0; q < quad_.param.size(); ++q) {
    if (point_level(q) >= BasisLevel::Rigid) continue;  // no stress there (docs/mls.md)
    const int32_t slot = cut_.point_slot[q];
    const bool membrane = slot >= 0 && cut_.slots[static_cast<size_t>(slot)].order == 1;
    // The same basis (NURBS or the point's fallback) applied to the current and to the rest control points:
    // g_i from x (thesis Eq. 4.3), gbar_i from the reference patch.
    const BasisView b = point_basis(q);
    cur.resize(static_cast<size_t>(b.n));
    ref.resize(static_cast<size_t>(b.n));
    for (int s = 0; s < b.n; ++s) {
      cur[static_cast<size_t>(s)] = &x[static_cast<size_t>(b.index[s])];
      ref[static_cast<size_t>(s)] = &rest[static_cast<size_t>(b.index[s])];
    }
    const SurfaceJet jet = surface_jet(cur.data(), b.basis + 1, b.n, kBasisStride);
    const SurfaceJet jet_ref = surface_jet(ref.data(), b.basis + 1, b.n, kBasisStride);
    NormalJet nj, nj_ref;
    if (!normal_jet(jet, nj) || !normal_jet(jet_ref, nj_ref)) continue;
    for (size_t l = 0; l < L; ++l) {
      // As in compute_forces: the 2D models and membrane-only points see the mid-surface at every layer.
      const double xi3 = (mid_surface || membrane) ? 0.0 : quad_.layers.xi3[l];
      const Mat3 g = kl_basis(jet, nj, xi3);
      const Mat3 G = kl_basis(jet_ref, nj_ref, xi3);
      // sum_i g_i (x) Gbar^i = g Gbar^-1, since the contravariant Gbar^i are the rows of Gbar^-1.
      out[q * L + l] = g * G.inverse();
    }
  }
  return out;
}

}  // namespace shellfrac::shell
