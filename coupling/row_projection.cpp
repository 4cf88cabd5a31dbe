#include "coupling/row_projection.hpp"

#include <string>

#include "coupling/coupling_error.hpp"

namespace shellfrac::coupling {

Eigen::MatrixXd stacked_operator(const Interface& itf) {
  if (itf.continuity == Continuity::C0) return itf.M0;
  const Eigen::Index nf = itf.M0.rows(), nl = itf.M0.cols();
  Eigen::MatrixXd B = Eigen::MatrixXd::Zero(2 * nf, 2 * nl);
  B.topLeftCorner(nf, nl) = itf.M0;
  B.bottomLeftCorner(nf, nl) = itf.M0 + itf.M1;  // Eq. 4.34
  B.bottomRightCorner(nf, nl) = itf.M1_row2.size() ? Eigen::MatrixXd(-itf.M1_row2) : Eigen::MatrixXd(-itf.M1);
  return B;
}

RowProjection::RowProjection(const Interface& itf, bool exact, const Eigen::VectorXd& leader_mass,
                             const Eigen::VectorXd& follower_mass)
    : leader_mass_(leader_mass), follower_mass_(follower_mass) {
  const bool c1 = itf.continuity == Continuity::C1;
  const auto nl = static_cast<Eigen::Index>(itf.leader_row1.size());
  if (exact) {
    const Eigen::MatrixXd& E1 = itf.shared.E1;
    E_ = Eigen::MatrixXd::Zero(c1 ? 2 * nl : nl, c1 ? E1.cols() + itf.shared.E2.cols() : E1.cols());
    E_.topLeftCorner(nl, E1.cols()) = E1;
    if (c1) E_.bottomRightCorner(nl, itf.shared.E2.cols()) = itf.shared.E2;
  } else {
    E_ = Eigen::MatrixXd::Identity(c1 ? 2 * nl : nl, c1 ? 2 * nl : nl);
  }
  BE_ = stacked_operator(itf) * E_;
  if (leader_mass.size() != E_.rows() || follower_mass.size() != BE_.rows() || leader_mass.minCoeff() <= 0 ||
      follower_mass.minCoeff() < 0) {
    throw CouplingError("seam row projection needs " + std::to_string(E_.rows()) + " positive leader masses and " +
                        std::to_string(BE_.rows()) + " non-negative follower masses");
  }
  const Eigen::MatrixXd A =
      E_.transpose() * leader_mass.asDiagonal() * E_ + BE_.transpose() * follower_mass.asDiagonal() * BE_;
  normal_.compute(A);
}

PointRows RowProjection::apply(const PointRows& leader, const PointRows& follower) const {
  const PointRows rhs = E_.transpose() * (leader_mass_.asDiagonal() * leader) +
                        BE_.transpose() * (follower_mass_.asDiagonal() * follower);
  return E_ * normal_.solve(rhs);
}

}  // namespace shellfrac::coupling
