#pragma once
// The fallback chain that gives every point near a crack a basis (docs/mls.md, "Fallback chain"): a
// quadrature point, shear particle or render vertex whose NURBS support the crack cuts tries, in order,
//   quadratic MLS (thesis sec. 4.6) -> relaxed quadratic -> linear MLS (membrane only) over the control
//   points it sees in straight lines (with diffraction tip weights, MlsSettings::tip, also around one crack
//   tip or bend corner) -> MLS over its own fragment's control points along paths around
//   crack tips and corners -> a rigid sliver (follows its fragment's control points, no force) -> removed
//   (its fragment holds no control point at all).
// A point lying exactly on a crack line is first moved 1e-9 cells to the side that sees the most.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"
#include "shell/fragment_basis.hpp"
#include "shell/mls_basis.hpp"

namespace shellfrac::shell {

enum class BasisLevel : unsigned char {
  Nurbs,             // the NURBS support is not cut (ShellPatch's default; never returned by the chain)
  Quadratic,         // thesis sec. 4.6: >= min_neighbours visible control points, rcond >= min_rcond
  RelaxedQuadratic,  // >= 6 visible control points, rcond >= 1e-9
  Linear,            // linear basis over >= 3 visible control points: membrane only (no curvature)
  Fragment,          // own fragment's control points along crack-free paths (quadratic or linear)
  Rigid,             // fragment too small for a basis: moves with its control points, carries no stress
  Removed,           // fragment without a control point: no force, no position
};
inline constexpr int kNumBasisLevels = 7;
const char* basis_level_name(BasisLevel level);

struct BasisChainSettings {
  MlsSettings mls;  // level Quadratic (the thesis's fit); its factors bound the straight-line levels
  // Relaxed and linear levels: the rcond bounds keep the reproduction of 1 and xi (values and first
  // derivatives) within 1e-10 (measured, docs/mls.md); a worse-conditioned quadratic fit is left to the
  // linear level, and a nearly collinear linear one to the fragment level.
  int relaxed_min_neighbours = 6;
  double relaxed_min_rcond = 1e-4;
  double linear_min_rcond = 1e-3;
  // Fragment level: first forward paths up to mls.max_factor cells (bending at crack corners only into
  // the half-plane ahead of the corner, and by at most 90 degrees in all: past a tip, never back behind
  // the crack), then paths up to fragment_reach * mls.max_factor cells bending any way.
  double fragment_reach = 2.0;
  // Portals and the on-crack nudge, in cells.
  double nudge = 1e-9;
};

struct PointFit {
  BasisLevel level = BasisLevel::Removed;
  int order = 0;             // polynomial order of the basis: 2, 1, or 0 (Rigid, Removed)
  bool nudged = false;       // the point lay on a crack line and was evaluated at `at` instead
  bool chain_failed = false; // Rigid although the fragment spans a plane: no fit succeeded (a defect)
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  // where the basis was evaluated
  double reach = 0.0;        // half-width in cells of the box holding everything the result depends on
  std::string reason;        // why the quadratic fit failed; empty at level Quadratic
};

struct BasisChainWork {
  MlsBasis basis;
  FragmentWork fragment;
  std::vector<size_t> tips;  // portals (free tips, or all corners) in sight of the point (diffraction weights)
};

// Runs the chain at xi. On return work.basis holds the result: R and its derivatives for levels
// Quadratic .. Fragment (second derivatives are those of the basis order: a linear basis reproduces no
// curvature); for Rigid, index = the fragment's control points with R = 1 / n and zero derivatives;
// for Removed, nothing. Thread-safe for distinct work objects.
PointFit fit_point_basis(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                         const crack2d::CrackPortals& portals, const BasisChainSettings& settings,
                         BasisChainWork& work);

}  // namespace shellfrac::shell
