#pragma once
// MLS over the control points of a point's own fragment, reached along crack-free paths that may bend
// around crack tips and corners (crack2d::CrackPaths). The fallback for points that see too few control
// points in straight lines: thin bands between near-parallel cracks, pockets between branches
// (docs/mls.md, "Fallback chain").
#include <Eigen/Core>
#include <vector>

#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"
#include "shell/mls_basis.hpp"

namespace shellfrac::shell {

// A control point reached from the evaluation point: path length in cells and the first point after the
// evaluation point on the path (the control point itself when it is seen in a straight line).
struct ReachedPoint {
  int index = -1;
  double length = 0.0;
  Eigen::Vector2d first_hop = Eigen::Vector2d::Zero();
};

struct FragmentWork {
  crack2d::CrackPaths paths;
  std::vector<ReachedPoint> reached;
};

// MLS basis at xi (settings.order, min_neighbours, min_rcond as usual) whose weights are the radial cubic
// spline of thesis Eq. 4.18 applied to the path length: W_k = w(L_k / rho), L_k in cells (du / l_u,
// dv / l_v), rho the support factor, which grows from settings.initial_factor to settings.max_factor.
// With forward_only, paths bend at crack corners only into the half-plane ahead of the corner and turn by
// at most 90 degrees in total (they never wrap around behind a crack). The polynomial basis is the usual one in the straight
// local coordinates (xi_k - xi) / (rho l), so the basis reproduces it exactly whatever the paths; the
// weight derivatives follow the path's first hop, dL/dxi = (xi - hop) / |xi - hop| (scaled). On failure
// out.ok is false with status and reason as for mls_basis.
bool mls_basis_along_paths(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                           const crack2d::CrackPortals& portals, const MlsSettings& settings, bool forward_only,
                           FragmentWork& work, MlsBasis& out);

// The two halves of mls_basis_along_paths. gather_along_paths fills work.reached with the control points
// reached along paths shorter than `limit` cells (only forward ones with forward_only, see above);
// fit_along_paths runs the growing
// MLS fit over `reached` (settings.max_factor should not exceed the gather limit).
void gather_along_paths(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                        const crack2d::CrackPortals& portals, double limit, bool forward_only, FragmentWork& work);
bool fit_along_paths(const Eigen::Vector2d& xi, const ControlGrid& grid, const std::vector<ReachedPoint>& reached,
                     const MlsSettings& settings, MlsBasis& out);

// Every control point of the grid reachable from xi along crack-free paths of any length and turning
// (the whole fragment), nearest first by path length. `need_spread` stops the search early once the
// points found span a plane (three not collinear in parameter space): the fragment can carry a basis.
// Returns true when it stopped early for that reason. first_hop is the path node that sees the point.
bool reach_fragment(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                    const crack2d::CrackPortals& portals, bool need_spread, FragmentWork& work);

// True when the control points reached span a plane: three of them are not collinear (exact test).
bool spans_plane(const ControlGrid& grid, const std::vector<ReachedPoint>& reached);

}  // namespace shellfrac::shell
