#pragma once
// The rigid rotation that moves a given amount of angular momentum: used where a step keeps linear
// momentum exactly and must give back angular momentum it moved (mpm g2p, the shear particles' placement).
#include <Eigen/Dense>

namespace shellfrac::core {

// omega with I omega = change, I = tr(S) Id - S the inertia of point masses whose second moment about
// their centre is `spread` (sum m (x - c)(x - c)^T). Adding omega x (x - c) to their velocities changes
// sum x m v by `change` and adds no linear momentum. Zero when the masses lie on a line or a point (no
// inertia about it).
inline Eigen::Vector3d rotation_for(const Eigen::Matrix3d& spread, const Eigen::Vector3d& change) {
  const Eigen::Matrix3d inertia = spread.trace() * Eigen::Matrix3d::Identity() - spread;
  const double size = inertia.trace();
  if (!(size > 0) || inertia.determinant() <= 1e-12 * size * size * size) return Eigen::Vector3d::Zero();
  return inertia.ldlt().solve(change);
}

}  // namespace shellfrac::core
