#include "coupling/seam_release.hpp"

#include <algorithm>
#include <cmath>

namespace shellfrac::coupling {

namespace {

// Parameter ranges of the patch along and across `side`, and whether "across" grows into the patch.
struct SideFrame {
  double along0, along_len, across0, across_len;
  bool across_inward_positive;
  bool along_is_u;
};

SideFrame frame(const nurbs::NurbsSurface& s, Side side) {
  const auto& ku = s.knots_u();
  const auto& kv = s.knots_v();
  const double u0 = ku.domain_begin(), u1 = ku.domain_end(), v0 = kv.domain_begin(), v1 = kv.domain_end();
  switch (side) {
    case Side::U0: return {v0, v1 - v0, u0, u1 - u0, true, false};
    case Side::U1: return {v0, v1 - v0, u1, u1 - u0, false, false};
    case Side::V0: return {u0, u1 - u0, v0, v1 - v0, true, true};
    case Side::V1: break;
  }
  return {u0, u1 - u0, v1, v1 - v0, false, true};
}

}  // namespace

SeamCoordinate seam_coordinate(const nurbs::NurbsSurface& surface, Side side, bool flip, const Eigen::Vector2d& uv) {
  const SideFrame f = frame(surface, side);
  const double a = f.along_is_u ? uv.x() : uv.y(), c = f.along_is_u ? uv.y() : uv.x();
  SeamCoordinate out;
  out.along = (a - f.along0) / f.along_len;
  if (flip) out.along = 1.0 - out.along;
  out.across = (f.across_inward_positive ? c - f.across0 : f.across0 - c) / f.across_len;
  return out;
}

Eigen::Vector2d seam_edge_parameter(const nurbs::NurbsSurface& surface, Side side, bool flip, double along) {
  const SideFrame f = frame(surface, side);
  const double a = f.along0 + (flip ? 1.0 - along : along) * f.along_len;
  return f.along_is_u ? Eigen::Vector2d(a, f.across0) : Eigen::Vector2d(f.across0, a);
}

Eigen::Vector2d seam_direction_to_parameter(const nurbs::NurbsSurface& surface, Side side, bool flip,
                                            const Eigen::Vector2d& d) {
  const SideFrame f = frame(surface, side);
  const double a = (flip ? -d.x() : d.x()) * f.along_len;
  const double c = (f.across_inward_positive ? d.y() : -d.y()) * f.across_len;
  return f.along_is_u ? Eigen::Vector2d(a, c) : Eigen::Vector2d(c, a);
}

Eigen::Vector2d parameter_direction_to_seam(const nurbs::NurbsSurface& surface, Side side, bool flip,
                                            const Eigen::Vector2d& d) {
  const SideFrame f = frame(surface, side);
  const double a = f.along_is_u ? d.x() : d.y(), c = f.along_is_u ? d.y() : d.x();
  return {(flip ? -a : a) / f.along_len, (f.across_inward_positive ? c : -c) / f.across_len};
}

namespace {

// Cuts row k of M0 (and M1 for C1) where across[j] marks the leader points the crack separates from
// follower point k. The kept entries are corrected on the two same-side leader points nearest to
// the crack so that the row keeps its sum and its first moment in the seam coordinate: the cut row then
// still reproduces any field that is affine along the seam, so the follower point keeps its rest
// position on a straight edge and follows its fragment through any rigid motion. The M1 row (the C1
// tangent part, acting on c_lambda1 - c_lambda2) becomes the cut M0 row times its old row-sum ratio.
// Returns false when fewer than two same-side leader points remain (nothing to follow).
bool cut_row(Interface& itf, Eigen::Index k, const std::vector<bool>& across, const std::vector<double>& leader_along,
             double follower_along) {
  Eigen::MatrixXd& M0 = itf.M0;
  double sum = 0, moment = 0, kept_sum = 0, kept_moment = 0;
  int near1 = -1, near2 = -1;  // same-side leader points nearest to the follower point
  auto distance = [&](int j) { return std::abs(leader_along[static_cast<size_t>(j)] - follower_along); };
  for (Eigen::Index j = 0; j < M0.cols(); ++j) {
    const double s = leader_along[static_cast<size_t>(j)], m = M0(k, j);
    sum += m;
    moment += m * s;
    if (across[static_cast<size_t>(j)]) {
      M0(k, j) = 0;
      continue;
    }
    kept_sum += m;
    kept_moment += m * s;
    const int jj = static_cast<int>(j);
    if (near1 < 0 || distance(jj) < distance(near1)) {
      near2 = near1;
      near1 = jj;
    } else if (near2 < 0 || distance(jj) < distance(near2)) {
      near2 = jj;
    }
  }
  const double ratio = itf.continuity == Continuity::C1 && sum != 0 ? itf.M1.row(k).sum() / sum : 0.0;
  if (near2 < 0) return false;
  const double s1 = leader_along[static_cast<size_t>(near1)], s2 = leader_along[static_cast<size_t>(near2)];
  // d1 + d2 = sum - kept_sum and d1 s1 + d2 s2 = moment - kept_moment
  const double r0 = sum - kept_sum, r1 = moment - kept_moment;
  const double d2 = (r1 - s1 * r0) / (s2 - s1);
  M0(k, near1) += r0 - d2;
  M0(k, near2) += d2;
  if (itf.continuity == Continuity::C1) itf.M1.row(k) = ratio * M0.row(k);
  return true;
}

}  // namespace

SeamCut cut_interface(const Interface& itf, const std::vector<double>& follower_along,
                      const std::vector<double>& leader_along, const std::vector<double>& seam_cracks) {
  SeamCut out{itf, {}};
  const auto n = static_cast<Eigen::Index>(itf.follower_row1.size());
  const bool c1 = itf.continuity == Continuity::C1;
  out.released.assign(static_cast<size_t>(c1 ? 2 * n : n), 0);
  if (seam_cracks.empty()) return out;
  std::vector<bool> across(leader_along.size());
  for (Eigen::Index k = 0; k < n; ++k) {
    const double sk = follower_along[static_cast<size_t>(k)];
    bool any = false;
    for (size_t j = 0; j < leader_along.size(); ++j) {
      const double lo = std::min(sk, leader_along[j]), hi = std::max(sk, leader_along[j]);
      across[j] = false;
      for (double c : seam_cracks) across[j] = across[j] || (c > lo && c < hi);
      any = any || (across[j] && out.coupling.M0(k, static_cast<Eigen::Index>(j)) != 0.0);
    }
    if (!any || cut_row(out.coupling, k, across, leader_along, sk)) continue;
    out.coupling.M0.row(k).setZero();
    if (c1) out.coupling.M1.row(k).setZero();
    out.released[static_cast<size_t>(k)] = 1;
    if (c1) out.released[static_cast<size_t>(n + k)] = 1;
  }
  return out;
}

}  // namespace shellfrac::coupling
