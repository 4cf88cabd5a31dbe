#pragma once
#include <Eigen/Core>
#include <vector>

#include "coupling/coupling_operators.hpp"
#include "coupling/edge.hpp"
#include "coupling/shared_space.hpp"
#include "nurbs/nurbs_surface.hpp"

namespace shellfrac::coupling {

enum class Continuity { C0, C1 };

// How the C1 constants D are chosen (see docs/coupling.md).
enum class CrossScale {
  KnotSpans,          // ratio of the cross-boundary knot spans (Coox et al. 2017 style), the default
  ReferenceGeometry,  // ratio measured on the reference control net: the rest state is a fixed point
};

// How the follower closes onto the leader (see coupling/shared_space.hpp).
enum class Closure {
  LeastSquares,  // thesis Eq. 4.29 as written: exact for nested knots, a least-squares fit otherwise
  Exact,         // the leader's coupled rows are kept in the spline space both edges share
};

struct InterfaceOptions {
  Continuity continuity = Continuity::C1;
  Closure closure = Closure::LeastSquares;
  CrossScale cross_scale = CrossScale::KnotSpans;
  double tolerance = 1e-8;  // allowed edge gap, length mismatch and refined-point mismatch (length units)
  int gap_samples = 200;
};

// A coupled pair of patch edges (thesis sec. 4.8). The leader (lambda) has fewer edge control points
// and is driven by the simulation; the follower (eta) rows are overwritten from it. Row index lists are
// flat control point indices of their own patch; leader rows follow the leader's edge parameter and
// follower rows the follower's. All operators are linear (no affine part), so apply() works on
// positions and on velocities alike.
struct Interface {
  int leader_patch = -1;
  int follower_patch = -1;
  Side leader_side = Side::U0;
  Side follower_side = Side::U0;
  bool reversed = false;  // the edges run in opposite directions
  Continuity continuity = Continuity::C0;

  std::vector<int> leader_row1, leader_row2;      // c_lambda1, c_lambda2
  std::vector<int> follower_row1, follower_row2;  // c_eta1, c_eta2

  Eigen::MatrixXd M0;  // n_eta x n_lambda: c_eta1 = M0 c_lambda1                       (Eq. 4.29)
  Eigen::MatrixXd M1;  // n_eta x n_lambda: c_eta2 = M0 c_lambda1 + M1 (c_lambda1 - c_lambda2) (Eq. 4.34)
  // Only for an exactly closed seam a crack has cut (coupling/seam_release.hpp): the operator on
  // c_lambda2 when it differs from the one on c_lambda1 (rational rows: row 1 and row 2 have their own
  // shared spaces), c_eta2 = (M0 + M1) c_lambda1 - M1_row2 c_lambda2. Empty: M1 acts on both.
  Eigen::MatrixXd M1_row2;
  Eigen::VectorXd D;   // the diagonal of mesh-dependent constants, one per refined control point
  std::vector<double> common_knots;  // k' in the follower's edge parameter (for inspection)
  // Exact closure only: the leader's rows live in shared.E1 (row 1) and shared.E2 (row 2, C1).
  bool exact = false;
  SharedSpace shared;

  // New follower rows from the leader's control points (whole-patch arrays, flat indices):
  // row 1 (n_eta x 3), and for C1 row 2 below it (2 n_eta x 3).
  PointRows follower_rows(const std::vector<Vec3>& leader_x) const;
  PointRows follower_rows(const nurbs::Vec3List& leader_x) const;

  // The same as a list: follower_row1 positions, then (C1) follower_row2 positions. This is
  // (U_eta^+ U_lambda c_lambda)^{n+1} of Eq. 4.30 for the momentum correction.
  std::vector<Vec3> follower_positions(const std::vector<Vec3>& leader_x) const;

  // Overwrites the follower's coupled rows in follower_x from leader_x.
  void apply(const std::vector<Vec3>& leader_x, std::vector<Vec3>& follower_x) const;
  void apply(const nurbs::Vec3List& leader_x, nurbs::Vec3List& follower_x) const;
};

// Builds the interface between side sa of patch a (id patch_a) and side sb of patch b. `reversed` says
// the edge parameter of b runs against that of a. Checks, each with a CouplingError
// (std::invalid_argument) naming the measured value: clamped knots, equal degrees along the edge,
// equal edge lengths, edge_gap <= tolerance, and identical curves after virtual refinement (the
// parameterisations must agree up to an affine map); for exact closure also that the leader's reference
// rows lie in the shared space. The side with fewer edge control points leads;
// on a tie, a leads.
Interface make_interface(const nurbs::NurbsSurface& a, int patch_a, Side sa, const nurbs::NurbsSurface& b,
                         int patch_b, Side sb, bool reversed, const InterfaceOptions& options = {});

}  // namespace shellfrac::coupling
