#include "coupling/seam_release.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/QR>

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

// Zeroes the entries of `row` flagged in `drop` and corrects the two kept entries nearest to `at`
// (seam coordinate) so that the row keeps its sum and its first moment along the seam: the corrected
// row maps any field affine along the seam to the same value. Returns false (row unchanged) when
// fewer than two entries may be kept.
bool drop_entries(Eigen::Ref<Eigen::RowVectorXd, 0, Eigen::InnerStride<>> row, const std::vector<bool>& drop,
                  const std::vector<double>& along, double at) {
  double sum = 0, moment = 0, kept_sum = 0, kept_moment = 0;
  int near1 = -1, near2 = -1;
  auto distance = [&](int j) { return std::abs(along[static_cast<size_t>(j)] - at); };
  bool any = false;
  for (Eigen::Index j = 0; j < row.size(); ++j) {
    const double s = along[static_cast<size_t>(j)], m = row[j];
    sum += m;
    moment += m * s;
    if (drop[static_cast<size_t>(j)]) {
      any = any || m != 0.0;
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
  if (!any) return true;
  if (near2 < 0) return false;
  for (Eigen::Index j = 0; j < row.size(); ++j)
    if (drop[static_cast<size_t>(j)]) row[j] = 0;
  const double s1 = along[static_cast<size_t>(near1)], s2 = along[static_cast<size_t>(near2)];
  // d1 + d2 = sum - kept_sum and d1 s1 + d2 s2 = moment - kept_moment
  const double r0 = sum - kept_sum, r1 = moment - kept_moment;
  const double d2 = (r1 - s1 * r0) / (s2 - s1);
  row[near1] += r0 - d2;
  row[near2] += d2;
  return true;
}

}  // namespace

bool TornTangents::any() const {
  return std::find(leader.begin(), leader.end(), 1) != leader.end() ||
         std::find(follower.begin(), follower.end(), 1) != follower.end();
}

SeamCut cut_interface(const Interface& itf, const std::vector<double>& follower_along,
                      const std::vector<double>& leader_along, const std::vector<double>& seam_cracks,
                      const TornTangents& torn) {
  SeamCut out{itf, {}};
  const auto n = static_cast<Eigen::Index>(itf.follower_row1.size());
  const bool c1 = itf.continuity == Continuity::C1;
  out.released.assign(static_cast<size_t>(c1 ? 2 * n : n), 0);
  Eigen::MatrixXd& M0 = out.coupling.M0;
  Eigen::MatrixXd& M1 = out.coupling.M1;
  std::vector<bool> across(leader_along.size()), unusable(leader_along.size());
  for (Eigen::Index k = 0; k < n; ++k) {
    const double sk = follower_along[static_cast<size_t>(k)];
    for (size_t j = 0; j < leader_along.size(); ++j) {
      const double lo = std::min(sk, leader_along[j]), hi = std::max(sk, leader_along[j]);
      across[j] = false;
      for (double c : seam_cracks) across[j] = across[j] || (c > lo && c < hi);
    }
    // Row 1 (and the M0 part of row 2): the crack's connections dropped.
    const double sum0 = M0.row(k).sum();
    const double ratio = c1 && sum0 != 0 ? M1.row(k).sum() / sum0 : 0.0;
    const Eigen::RowVectorXd before = M0.row(k);
    if (!drop_entries(M0.row(k), across, leader_along, sk)) {
      M0.row(k).setZero();
      if (c1) M1.row(k).setZero();
      out.released[static_cast<size_t>(k)] = 1;
      if (c1) out.released[static_cast<size_t>(n + k)] = 1;
      continue;
    }
    if (!c1) continue;
    // The tangent part follows the cut M0 row times its old row-sum ratio (a uniform cross-seam tangent
    // is carried unchanged), then lets go of the leader tangents a crack tore.
    if (M0.row(k) != before) M1.row(k) = ratio * M0.row(k);
    for (size_t j = 0; j < leader_along.size(); ++j)
      unusable[j] = across[j] || (j < torn.leader.size() && torn.leader[j]);
    const bool own_torn = static_cast<size_t>(k) < torn.follower.size() && torn.follower[static_cast<size_t>(k)];
    if (own_torn || !drop_entries(M1.row(k), unusable, leader_along, sk)) {
      M1.row(k).setZero();
      out.released[static_cast<size_t>(n + k)] = 1;
    }
  }
  return out;
}

namespace {

// Segment of a seam coordinate: how many cracks lie before it.
int segment_of(double along, const std::vector<double>& cracks) {
  int n = 0;
  for (double c : cracks) n += c < along;
  return n;
}

// One shared space per segment: E restricted to the rows `in` marks for that segment, with its left
// inverse (pseudo-inverse: rows of other segments and undetermined coefficients give zero).
struct SegmentSpace {
  Eigen::MatrixXd E;     // n_lambda x n_shared, rows outside the segment zero
  Eigen::MatrixXd left;  // n_shared x n_lambda, E left = identity on the segment's rows in the space
};

SegmentSpace segment_space(const Eigen::MatrixXd& E, const std::vector<int>& segment, int s) {
  SegmentSpace out{E, {}};
  for (Eigen::Index j = 0; j < E.rows(); ++j)
    if (segment[static_cast<size_t>(j)] != s) out.E.row(j).setZero();
  out.left = out.E.completeOrthogonalDecomposition().pseudoInverse();
  return out;
}

// Row r (over shared coefficients) written on the leader points of a segment, if the segment determines
// every coefficient r needs (r in the row space of the segment's E).
bool on_segment(const Eigen::RowVectorXd& r, const SegmentSpace& sp, Eigen::RowVectorXd& out) {
  out = r * sp.left;
  const double scale = r.cwiseAbs().maxCoeff();
  return scale == 0 || (out * sp.E - r).cwiseAbs().maxCoeff() <= 1e-9 * scale;
}

// Block matrix of the segments' spaces (all-zero columns dropped): the leader rows' constraint.
Eigen::MatrixXd blocks(const std::vector<SegmentSpace>& spaces) {
  std::vector<Eigen::VectorXd> cols;
  for (const SegmentSpace& sp : spaces)
    for (Eigen::Index i = 0; i < sp.E.cols(); ++i)
      if (sp.E.col(i).cwiseAbs().maxCoeff() > 0) cols.push_back(sp.E.col(i));
  const Eigen::Index rows = spaces.empty() ? 0 : spaces.front().E.rows();
  Eigen::MatrixXd out(rows, static_cast<Eigen::Index>(cols.size()));
  for (size_t i = 0; i < cols.size(); ++i) out.col(static_cast<Eigen::Index>(i)) = cols[i];
  return out;
}

}  // namespace

SeamCut cut_exact_interface(const Interface& itf, const std::vector<double>& follower_along,
                            const std::vector<double>& leader_along, const std::vector<double>& seam_cracks,
                            const TornTangents& torn) {
  // Least-squares cut rows first: the fallback next to the crack.
  SeamCut out = cut_interface(itf, follower_along, leader_along, seam_cracks, torn);
  const bool c1 = itf.continuity == Continuity::C1;
  const auto n = static_cast<Eigen::Index>(itf.follower_row1.size());
  const int segments = static_cast<int>(seam_cracks.size()) + 1;
  std::vector<int> seg1(leader_along.size()), seg2(leader_along.size());
  for (size_t j = 0; j < leader_along.size(); ++j) {
    seg1[j] = segment_of(leader_along[j], seam_cracks);
    seg2[j] = j < torn.leader.size() && torn.leader[j] ? -1 : seg1[j];  // a torn tangent: no segment
  }
  std::vector<SegmentSpace> space1, space2;
  for (int s = 0; s < segments; ++s) {
    space1.push_back(segment_space(itf.shared.E1, seg1, s));
    if (c1) space2.push_back(segment_space(itf.shared.E2, seg2, s));
  }
  // Exact rows over the shared coefficients (intact operators): c_eta1 = R1 s1 and
  // c_eta2 = (R1 + M1 E1) s1 - M1 E2 s2 (Eq. 4.29, 4.34 on the shared space).
  const Eigen::MatrixXd R1 = itf.M0 * itf.shared.E1;
  Eigen::MatrixXd T1, T2;
  if (c1) {
    T1 = itf.M1 * itf.shared.E1;
    T2 = itf.M1 * itf.shared.E2;
    if (out.coupling.M1_row2.size() == 0) out.coupling.M1_row2 = out.coupling.M1;
  }
  Eigen::RowVectorXd a, b, t;
  for (Eigen::Index k = 0; k < n; ++k) {
    const auto s = static_cast<size_t>(segment_of(follower_along[static_cast<size_t>(k)], seam_cracks));
    if (!on_segment(R1.row(k), space1[s], a)) continue;  // next to the crack: the least-squares cut row
    out.coupling.M0.row(k) = a;
    out.released[static_cast<size_t>(k)] = 0;
    if (!c1) continue;
    const bool own_torn = static_cast<size_t>(k) < torn.follower.size() && torn.follower[static_cast<size_t>(k)];
    if (own_torn || !on_segment(T1.row(k), space1[s], t) || !on_segment(T2.row(k), space2[s], b)) {
      // Row 2 next to the crack: the least-squares cut operators, on both leader rows alike.
      out.coupling.M1_row2.row(k) = out.coupling.M1.row(k);
      continue;
    }
    out.coupling.M1.row(k) = t;
    out.coupling.M1_row2.row(k) = b;
    out.released[static_cast<size_t>(n + k)] = 0;
  }
  out.coupling.shared.E1 = blocks(space1);
  if (c1) out.coupling.shared.E2 = blocks(space2);
  return out;
}

}  // namespace shellfrac::coupling
