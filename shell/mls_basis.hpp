#pragma once
// Moving-least-squares (MLS) shape functions in a patch's parameter plane, used for quadrature points
// whose NURBS support is cut by a crack (thesis sec. 4.6, Eq. 4.15-4.21). Equations: docs/mls.md.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

namespace shellfrac::nurbs {
class NurbsSurface;
}

namespace shellfrac::shell {

// How a control point hidden behind a crack near one of its free tips is weighted (docs/mls.md, "Tip
// weights"). visibility: not at all (thesis sec. 4.6). diffraction: the diffraction method of Organ,
// Fleming, Terry and Belytschko (1996): the distance to it is lengthened by how much the way around the tip
// is longer than the straight line, so its weight fades from the full weight (the line of sight grazes the
// tip) to zero (far along the crack).
struct TipWeights {
  enum class Mode : unsigned char { visibility, diffraction };
  Mode mode = Mode::visibility;
  double lambda = 2.0;  // exponent of the lengthening ratio (Organ et al. use 1 or 2)
  // Within about this many cells of the tip the lengthening is faded out smoothly (factor
  // s2^2 / (s2^2 + radius^2)), which bounds the second derivatives there; 0 gives the plain method.
  double radius = 0.1;
  // Also around the reflex corners of bent cracks (the open side of a bend or junction), not only free
  // tips: a point on the outer side of a bend then reaches its own side's control points behind the bend.
  bool corners = true;
};

// How the first support factor of an evaluation point is chosen (docs/mls.md, "Support size").
//  - stepped: initial_factor, then growth steps. Two points a quarter cell apart along a crack face can land
//    one step apart (2.37 against 2.88 cells), and the basis jumps between them; opened crack faces then
//    show a sawtooth of over-stretched render edges.
//  - continuous: support_margin times the distance, in cells, of the min_neighbours-th nearest visible
//    control point (max-norm, lengthened around crack tips as the diffraction weight lengthens it), and
//    never below initial_factor. It moves continuously with the evaluation point while the visible set stays.
//  Either way the factor then grows by growth steps while the basis is rejected; the continuous rule then
//  bisects back to the smallest accepted factor, which also moves continuously with the point.
enum class SupportRule : unsigned char { stepped, continuous };

// How the support of one evaluation point is chosen (thesis sec. 4.6, "we determine d_X").
struct MlsSettings {
  double initial_factor = 1.5;  // d_alpha = factor * l_alpha; 1.5 l is the NURBS-equivalent support
  SupportRule rule = SupportRule::stepped;
  double support_margin = 1.5;  // continuous rule only; > 1 so that min_neighbours points have weight > 0
  double max_factor = 4.5;      // the thesis never needed more than ~4.5 l
  double growth = 1.25;         // factor multiplier per enlargement step (> 1); the last step lands on max_factor
  int min_neighbours = 9;       // visible control points with weight > 0 (9 for a quadratic basis)
  // Lower bound on the reciprocal 1-norm condition estimate of the local, Jacobi-equilibrated moment
  // matrix. Near-degenerate supports (a row of control points with weight -> 0) give shape-function
  // derivatives with large cancelling terms; 1e-3 keeps quadratic reproduction errors below ~3e-10 in
  // cell-scaled units (l^2 d2R) and leaves interior 4x4 Gauss points at 1.5 l (docs/mls.md).
  double min_rcond = 1e-3;
  // Polynomial order of the basis: 2 is the complete quadratic of thesis Eq. 4.16 (6 terms), 1 the linear
  // basis [1, x1, x2] (3 terms) of the shell's fallback for points that see too few control points. A
  // linear basis reproduces first derivatives only; its second derivatives carry no curvature (docs/mls.md).
  int order = 2;
  // Used by the fallback chain (shell/basis_chain.hpp); mls_basis itself takes what its sight callback says.
  TipWeights tip;
};

enum class MlsStatus {
  ok,
  invalid_input,       // non-finite point, bad settings or cell sizes
  too_few_neighbours,  // fewer than min_neighbours visible control points even at max_factor
  ill_conditioned,     // moment matrix singular or rcond < min_rcond even at max_factor
};

// The compact MLS basis of one evaluation point: support point k has control point index[k] and shape
// function value R[k] with parametric derivatives R1 = dR/dxi1, R2, R11 = d2R/dxi1^2, R12, R22.
// Reuse one object per thread: all buffers keep their capacity between calls.
struct MlsBasis {
  std::vector<int> index;
  std::vector<double> R, R1, R2, R11, R12, R22;
  double factor = 0.0;  // final support factor (d_alpha = factor * l_alpha); last tried one on failure
  double rcond = 0.0;   // reciprocal condition estimate of the scaled moment matrix at `factor`
  bool ok = false;
  MlsStatus status = MlsStatus::invalid_input;
  std::string reason;  // empty when ok

  int size() const { return static_cast<int>(index.size()); }

  // Scratch space of mls_basis (visible candidates and per-point weights); not part of the result.
  struct Workspace {
    std::vector<int> index;
    std::vector<double> pu, pv;                  // parameter coordinates of visible candidates
    std::vector<double> tu, tv;                  // tip a candidate is seen around (NaN: seen directly)
    std::vector<double> W, W1, W2, W11, W12, W22;  // weight and its derivatives (scaled coordinates)
    std::vector<int> support;                    // control point of each support point (compacted)
    std::vector<double> e1, e2;                  // local coordinates of the support points (compacted)
    std::vector<double> q;                       // local basis values per point (6 or 3)
    std::vector<double> reach;                   // lengthened distances in cells (continuous support rule)
  } work;
};

// Control points of a NURBS patch in parameter space: the tensor grid of Greville abscissae, control
// point (i, j) at flat index i + nu * j (as nurbs::NurbsSurface). cell_u/cell_v are the cell sizes l_alpha.
// Box queries use binary search, so the cost is proportional to the number of points returned.
struct ControlGrid {
  std::vector<double> u, v;  // non-decreasing
  double cell_u = 0.0, cell_v = 0.0;

  int nu() const { return static_cast<int>(u.size()); }
  int nv() const { return static_cast<int>(v.size()); }
  int size() const { return nu() * nv(); }
  Eigen::Vector2d point(int k) const {
    return {u[static_cast<std::size_t>(k % nu())], v[static_cast<std::size_t>(k / nu())]};
  }

  // Greville abscissae of the surface's knot vectors; cell size = domain length / number of spans.
  static ControlGrid from_surface(const nurbs::NurbsSurface& surface);

  // Calls f(k, xi_k) for every point with |u - c.x| <= h_u and |v - c.y| <= h_v (possibly a few more).
  template <class F>
  void for_each_in_box(const Eigen::Vector2d& c, double h_u, double h_v, F&& f) const {
    const auto i0 = std::lower_bound(u.begin(), u.end(), c.x() - h_u) - u.begin();
    const auto i1 = std::upper_bound(u.begin(), u.end(), c.x() + h_u) - u.begin();
    const auto j0 = std::lower_bound(v.begin(), v.end(), c.y() - h_v) - v.begin();
    const auto j1 = std::upper_bound(v.begin(), v.end(), c.y() + h_v) - v.begin();
    const int n = nu();
    for (auto j = j0; j < j1; ++j) {
      for (auto i = i0; i < i1; ++i) {
        f(static_cast<int>(i + n * j), Eigen::Vector2d(u[static_cast<std::size_t>(i)], v[static_cast<std::size_t>(j)]));
      }
    }
  }
};

// An unstructured list of control points in parameter space (tests, small sets); linear-time queries.
struct ControlPointList {
  std::vector<double> u, v;  // point k is (u[k], v[k])
  double cell_u = 0.0, cell_v = 0.0;

  int size() const { return static_cast<int>(u.size()); }
  Eigen::Vector2d point(int k) const { return {u[static_cast<std::size_t>(k)], v[static_cast<std::size_t>(k)]}; }

  template <class F>
  void for_each_in_box(const Eigen::Vector2d& c, double h_u, double h_v, F&& f) const {
    for (int k = 0; k < size(); ++k) {
      const Eigen::Vector2d p = point(k);
      if (std::abs(p.x() - c.x()) <= h_u && std::abs(p.y() - c.y()) <= h_v) f(k, p);
    }
  }
};

// What an evaluation point sees of a control point: nothing, the point itself in a straight line, or the
// point around a crack tip (diffraction weights, TipWeights).
struct Sight {
  enum class Kind : unsigned char { hidden, direct, around_tip } kind = Kind::hidden;
  Eigen::Vector2d tip = Eigen::Vector2d::Zero();  // the tip vertex when kind == around_tip
};

// Visibility callback for an uncracked patch.
struct AlwaysVisible {
  bool operator()(const Eigen::Vector2d&, const Eigen::Vector2d&) const { return true; }
};

// The C^2 cubic spline weight of thesis Eq. 4.18 (misprint fixed, see DESIGN.md) and its first and
// second derivatives with respect to r >= 0; zero for r >= 1.
struct CubicWeight {
  double w, dw, ddw;
};
CubicWeight cubic_weight(double r);

// The weight of a control point seen around a crack tip and its first and second derivatives with respect
// to the evaluation point, in the scaled coordinates y = xi / d of the support (docs/mls.md, "Tip
// weights"): e = y_k - y (offset of the control point), r = y - y_c (offset from the tip), s1 = |y_k - y_c|,
// eps = fade radius in the same units. The tensor-product weight w(|f e1|) w(|f e2|) with
// f = 1 + (((s1 + |r|) / |e|)^lambda - 1) |r|^2 / (|r|^2 + eps^2).
struct WeightDerivatives {
  double W, W1, W2, W11, W12, W22;
  double stretch;  // f (1: the full weight of a visible point at the same place)
};
WeightDerivatives diffracted_weight(const Eigen::Vector2d& e, const Eigen::Vector2d& r, double s1, double lambda,
                                    double eps);

namespace detail {

struct MlsAttempt {
  MlsStatus status = MlsStatus::ok;
  int neighbours = 0;
  double rcond = 0.0;
};

// Checks the evaluation point, cell sizes and settings; fills out's status on failure.
bool check_mls_inputs(const Eigen::Vector2d& xi, double cell_u, double cell_v, const MlsSettings& settings,
                      MlsBasis& out);

// Builds the basis from the visible candidates gathered in out.work at support sizes d_u, d_v, with the
// tensor-product weight of thesis Eq. 4.18. Fills out's result arrays only when the returned status is ok.
MlsAttempt mls_evaluate(const Eigen::Vector2d& xi, double d_u, double d_v, const MlsSettings& settings,
                        MlsBasis& out);

// The MLS solve itself (Eq. 4.16-4.21) for m support points whose weights are already in out.work:
// support[k], W, W1, W2, W11, W12, W22 (derivatives with respect to the evaluation point in the scaled
// coordinates y = xi / d) and local coordinates e1, e2 = (xi_k - xi) / d, for k < m. Any non-negative
// weight works: the basis reproduces the polynomial basis whatever the weights (used by the fragment
// fallback's path-length weights, shell/fragment_basis.hpp). Order and acceptance from settings.
MlsAttempt mls_solve(std::size_t m, double d_u, double d_v, const MlsSettings& settings, MlsBasis& out);

// Number of terms of the polynomial basis of `order` (6 for quadratic, 3 for linear).
inline int basis_terms(int order) { return order >= 2 ? 6 : 3; }

// Fills out's status and reason after the attempt at the largest factor failed.
void report_mls_failure(const Eigen::Vector2d& xi, const MlsAttempt& attempt, const MlsSettings& settings,
                        MlsBasis& out);

}  // namespace detail

namespace detail {

// The distance in cells at which a visible candidate's weight vanishes (weight > 0 iff factor exceeds it):
// the max-norm of its offset, lengthened by the diffraction stretch when it is seen around a tip at (tu, tv)
// (NaN: seen directly). The stretch does not depend on the support size (docs/mls.md, "Tip weights").
double weight_reach(const Eigen::Vector2d& xi, double pu, double pv, double tu, double tv, double cell_u,
                    double cell_v, const TipWeights& tip);

// The continuous rule's first factor: support_margin times the min_neighbours-th smallest weight_reach of
// the visible candidates, at least initial_factor, at most max_factor. gather(f) offers take() every
// candidate within factor f not offered before; candidates are gathered only as far as the answer needs
// (a candidate's reach is never below its max-norm distance).
template <class Gather>
double continuous_factor(const Eigen::Vector2d& xi, double cell_u, double cell_v, Gather&& gather,
                         const MlsSettings& settings, MlsBasis::Workspace& work) {
  const auto nth = static_cast<std::size_t>(std::max(settings.min_neighbours, 1) - 1);
  double reach = settings.initial_factor;
  for (;;) {
    gather(reach);
    double target = settings.max_factor;
    const std::size_t n = work.index.size();
    if (n > nth) {
      work.reach.resize(n);
      for (std::size_t c = 0; c < n; ++c) {
        const bool around = c < work.tu.size();
        work.reach[c] = weight_reach(xi, work.pu[c], work.pv[c], around ? work.tu[c] : std::nan(""),
                                     around ? work.tv[c] : std::nan(""), cell_u, cell_v, settings.tip);
      }
      std::nth_element(work.reach.begin(), work.reach.begin() + static_cast<std::ptrdiff_t>(nth), work.reach.end());
      target = std::clamp(settings.support_margin * work.reach[nth], settings.initial_factor, settings.max_factor);
    }
    if (target <= reach || reach >= settings.max_factor) return target;
    reach = std::min(std::max(target, reach * settings.growth), settings.max_factor);
  }
}

// The support search shared by mls_basis and mls_basis_with_sight: the factor starts at the rule's first
// factor (settings.rule) and grows until the basis at that support is accepted, or fails at max_factor.
// take(k, xi_k) is offered every candidate inside the support that an earlier attempt did not offer
// (each candidate once) and appends the ones it keeps to out.work.
template <class Candidates, class Take>
bool grow_support(const Eigen::Vector2d& xi, const Candidates& candidates, Take&& take, const MlsSettings& settings,
                  MlsBasis& out) {
  double gathered = 0.0;  // every candidate within this factor has been offered
  auto gather = [&](double factor) {
    if (factor <= gathered) return;
    const double du = factor * candidates.cell_u, dv = factor * candidates.cell_v;
    const double pu = gathered * candidates.cell_u, pv = gathered * candidates.cell_v;
    // The query box is inflated a little; the exact |offset| < d test below decides membership.
    candidates.for_each_in_box(xi, du * (1.0 + 1e-12), dv * (1.0 + 1e-12), [&](int k, const Eigen::Vector2d& xk) {
      const double au = std::abs(xk.x() - xi.x());
      const double av = std::abs(xk.y() - xi.y());
      if (!(au < du && av < dv)) return;
      if (au < pu && av < pv) return;
      take(k, xk);
    });
    gathered = factor;
  };
  double factor = settings.rule == SupportRule::continuous
                      ? continuous_factor(xi, candidates.cell_u, candidates.cell_v, gather, settings, out.work)
                      : settings.initial_factor;
  auto attempt_at = [&](double f) {
    gather(f);
    out.factor = f;
    return mls_evaluate(xi, f * candidates.cell_u, f * candidates.cell_v, settings, out);
  };
  double rejected = 0.0;  // largest factor tried and rejected
  for (;;) {
    const MlsAttempt attempt = attempt_at(factor);
    if (attempt.status == MlsStatus::ok) break;
    if (factor >= settings.max_factor) {
      report_mls_failure(xi, attempt, settings, out);
      return false;
    }
    rejected = factor;
    factor = std::min(factor * settings.growth, settings.max_factor);
  }
  if (settings.rule == SupportRule::stepped || rejected == 0.0) return true;
  // Continuous rule: the first accepted factor would jump by a whole growth step between neighbouring
  // points; the smallest accepted one (the factor where the rejection test flips) moves with the point.
  // Bisection to 1e-4 of the factor: the accepted end of the bracket is kept.
  double accepted = factor;
  while (accepted - rejected > 1e-4 * accepted) {
    const double mid = 0.5 * (rejected + accepted);
    (attempt_at(mid).status == MlsStatus::ok ? accepted : rejected) = mid;
  }
  if (out.factor != accepted) attempt_at(accepted);
  return true;
}

// Empties the candidate lists of out.work.
inline void clear_candidates(MlsBasis::Workspace& work) {
  work.index.clear();
  work.pu.clear();
  work.pv.clear();
  work.tu.clear();
  work.tv.clear();
}

}  // namespace detail

// MLS shape functions at parameter point xi (thesis Eq. 4.15-4.21). Candidates is ControlGrid,
// ControlPointList or anything with cell_u, cell_v and for_each_in_box. visible(xi, xi_k) must return
// true when the segment xi -> xi_k does not cross a crack; it is called at most once per candidate.
// The support factor starts at settings.initial_factor and grows until at least min_neighbours visible
// control points have weight > 0 and the scaled moment matrix has rcond >= min_rcond; at max_factor
// failure is reported (out.ok == false, status and reason set, result arrays empty, never NaN).
// Thread-safe for distinct `out` objects as long as `visible` is.
template <class Candidates, class Visible>
bool mls_basis(const Eigen::Vector2d& xi, const Candidates& candidates, Visible&& visible,
               const MlsSettings& settings, MlsBasis& out) {
  if (!detail::check_mls_inputs(xi, candidates.cell_u, candidates.cell_v, settings, out)) return false;
  MlsBasis::Workspace& work = out.work;
  detail::clear_candidates(work);  // tu, tv stay empty: every candidate is seen directly
  auto take = [&](int k, const Eigen::Vector2d& xk) {
    if (!visible(xi, xk)) return;
    work.index.push_back(k);
    work.pu.push_back(xk.x());
    work.pv.push_back(xk.y());
  };
  return detail::grow_support(xi, candidates, take, settings, out);
}

// As mls_basis, with sight(xi, xi_k) -> Sight: a control point seen around a crack tip gets the
// diffraction weight (diffracted_weight) with settings.tip.lambda and settings.tip.radius.
template <class Candidates, class SightFn>
bool mls_basis_with_sight(const Eigen::Vector2d& xi, const Candidates& candidates, SightFn&& sight,
                          const MlsSettings& settings, MlsBasis& out) {
  if (!detail::check_mls_inputs(xi, candidates.cell_u, candidates.cell_v, settings, out)) return false;
  MlsBasis::Workspace& work = out.work;
  detail::clear_candidates(work);
  constexpr double kDirect = std::numeric_limits<double>::quiet_NaN();
  auto take = [&](int k, const Eigen::Vector2d& xk) {
    const Sight seen = sight(xi, xk);
    if (seen.kind == Sight::Kind::hidden) return;
    work.index.push_back(k);
    work.pu.push_back(xk.x());
    work.pv.push_back(xk.y());
    const bool around = seen.kind == Sight::Kind::around_tip;
    work.tu.push_back(around ? seen.tip.x() : kDirect);
    work.tv.push_back(around ? seen.tip.y() : kDirect);
  };
  return detail::grow_support(xi, candidates, take, settings, out);
}

}  // namespace shellfrac::shell
