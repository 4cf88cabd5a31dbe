#include "shell/basis_chain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellfrac::shell {

const char* basis_level_name(BasisLevel level) {
  switch (level) {
    case BasisLevel::Nurbs: return "nurbs";
    case BasisLevel::Quadratic: return "quadratic";
    case BasisLevel::RelaxedQuadratic: return "relaxed_quadratic";
    case BasisLevel::Linear: return "linear";
    case BasisLevel::Fragment: return "fragment";
    case BasisLevel::Rigid: return "rigid";
    case BasisLevel::Removed: return "removed";
  }
  return "?";
}

namespace {

constexpr double kPi = 3.14159265358979323846;

// A point exactly on a crack line sees nothing (touching counts as crossing). It stands for material on
// both sides; it is given to the side from which it sees the most control points within the initial
// support, moved `nudge` cells in one of eight directions (none along a grid axis or diagonal, where
// extracted crack lines run). Ties keep the first direction: deterministic.
Eigen::Vector2d nudge_off_crack(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                                const BasisChainSettings& s) {
  const double lu = grid.cell_u, lv = grid.cell_v;
  const double hu = s.mls.initial_factor * lu, hv = s.mls.initial_factor * lv;
  const crack2d::Box& domain = index.domain();
  for (double eps = s.nudge; eps < 1e-2; eps *= 1e3) {
    Eigen::Vector2d best = xi;
    int best_score = -1;
    for (int k = 0; k < 8; ++k) {
      const double a = (k + 0.5) * kPi / 4.0;
      const Eigen::Vector2d p = xi + eps * Eigen::Vector2d(lu * std::cos(a), lv * std::sin(a));
      if (!crack2d::box_contains(domain, p) || index.crosses(p, p)) continue;
      int score = 0;
      grid.for_each_in_box(p, hu, hv, [&](int, const Eigen::Vector2d& xk) { score += !index.crosses(p, xk); });
      if (score > best_score) {
        best_score = score;
        best = p;
      }
    }
    if (best_score >= 0) return best;
  }
  return xi;
}

double box_reach(const Eigen::Vector2d& xi, const Eigen::Vector2d& p, const ControlGrid& grid) {
  return std::max(std::abs(p.x() - xi.x()) / grid.cell_u, std::abs(p.y() - xi.y()) / grid.cell_v);
}

// Tips that can matter: a control point seen around a tip farther than kTipBox supports (infinity norm,
// cells / factor) gets weight 0 (docs/mls.md), so the basis depends on cracks within kTipBox * factor.
constexpr double kTipBox = 1.5;

// The portals of the corners in sight of xi within kTipBox supports: free tips, or with tip.corners
// every reflex corner of a bend or junction.
void tips_in_sight(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                   const crack2d::CrackPortals& portals, const BasisChainSettings& s, std::vector<size_t>& tips) {
  tips.clear();
  const double hu = kTipBox * s.mls.max_factor * grid.cell_u, hv = kTipBox * s.mls.max_factor * grid.cell_v;
  const bool corners = s.mls.tip.corners;
  const size_t n = corners ? portals.size() : portals.tips().size();
  for (size_t t = 0; t < n; ++t) {
    const size_t portal = corners ? t : portals.tip_portals()[t];
    const Eigen::Vector2d& c = portals.corners()[portal];
    if (std::abs(c.x() - xi.x()) > hu || std::abs(c.y() - xi.y()) > hv) continue;
    if (index.crosses(xi, portals.points()[portal])) continue;  // the corner is not in sight
    tips.push_back(portal);
  }
}

// How a control point at c is seen from a: directly, or around one of `tips` by the shortest way (cell
// units, measured through the crack vertex; the hops themselves are checked to the corner's portal, 1e-7
// cells beyond it), or not at all.
struct SightAroundTips {
  const crack2d::CrackIndex& index;
  const crack2d::CrackPortals& portals;
  const std::vector<size_t>& tips;
  double lu, lv;

  Sight operator()(const Eigen::Vector2d& a, const Eigen::Vector2d& c) const {
    Sight out;
    if (!index.crosses(a, c)) {
      out.kind = Sight::Kind::direct;
      return out;
    }
    double best = std::numeric_limits<double>::infinity();
    for (size_t t : tips) {
      const Eigen::Vector2d& tip = portals.corners()[t];
      const double way = std::hypot((tip.x() - a.x()) / lu, (tip.y() - a.y()) / lv) +
                         std::hypot((c.x() - tip.x()) / lu, (c.y() - tip.y()) / lv);
      if (!(way < best)) continue;
      if (index.crosses(portals.points()[t], c)) continue;
      best = way;
      out.kind = Sight::Kind::around_tip;
      out.tip = tip;
    }
    return out;
  }
};

// The linear fit's settings over supports of the chain's sizes: three points not in a line.
MlsSettings linear_settings(const BasisChainSettings& s) {
  MlsSettings linear = s.mls;
  linear.order = 1;
  linear.min_neighbours = 3;
  linear.min_rcond = s.linear_min_rcond;
  return linear;
}

// Levels 1-3: the control points seen in straight lines, and with diffraction tip weights also those two
// straight hops around one corner in sight reach (docs/mls.md, "Tip weights"). False if none fits.
bool fit_in_sight(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                  const crack2d::CrackPortals& portals, const BasisChainSettings& s, BasisChainWork& work,
                  PointFit& fit) {
  MlsBasis& b = work.basis;
  const bool diffraction = s.mls.tip.mode == TipWeights::Mode::diffraction;
  if (diffraction) tips_in_sight(xi, grid, index, portals, s, work.tips);
  else work.tips.clear();
  const SightAroundTips sight{index, portals, work.tips, grid.cell_u, grid.cell_v};
  auto visible = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& c) { return !index.crosses(a, c); };
  auto fit_mls = [&](const MlsSettings& settings) {
    return diffraction ? mls_basis_with_sight(xi, grid, sight, settings, b) : mls_basis(xi, grid, visible, settings, b);
  };
  const double reach_scale = diffraction ? kTipBox : 1.0;
  auto done = [&](BasisLevel level, int order) {
    fit.level = level;
    fit.order = order;
    fit.reach = b.factor * reach_scale;
    return true;
  };
  // 1. The thesis's quadratic fit over the control points seen in straight lines (sec. 4.6).
  if (fit_mls(s.mls)) return done(BasisLevel::Quadratic, 2);
  fit.reason = b.reason;
  // 2. Relaxed: the quadratic basis size and a moment matrix merely far from singular.
  MlsSettings relaxed = s.mls;
  relaxed.min_neighbours = s.relaxed_min_neighbours;
  relaxed.min_rcond = std::min(s.mls.min_rcond, s.relaxed_min_rcond);
  if (fit_mls(relaxed)) return done(BasisLevel::RelaxedQuadratic, 2);
  // 3. Linear over the same straight-line supports.
  if (fit_mls(linear_settings(s))) return done(BasisLevel::Linear, 1);
  return false;
}

// Level 4: the own fragment along crack-free paths: first forward ones (bending only ahead of a crack
// corner and by at most 90 degrees in all: never reaching behind a crack), then any path over a longer
// reach. False if none fits.
bool fit_along_fragment_paths(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                              const crack2d::CrackPortals& portals, const BasisChainSettings& s, BasisChainWork& work,
                              PointFit& fit) {
  FragmentWork& fw = work.fragment;
  const double reaches[2] = {s.mls.max_factor, s.fragment_reach * s.mls.max_factor};
  for (int pass = 0; pass < 2; ++pass) {
    gather_along_paths(xi, grid, index, portals, reaches[pass], pass == 0, fw);
    MlsSettings quad = s.mls;
    quad.max_factor = reaches[pass];
    MlsSettings lin = linear_settings(s);
    lin.max_factor = reaches[pass];
    for (int order : {2, 1})
      if (fit_along_paths(xi, grid, fw.reached, order == 2 ? quad : lin, work.basis)) {
        fit.level = BasisLevel::Fragment;
        fit.order = order;
        fit.reach = reaches[pass];
        return true;
      }
  }
  return false;
}

// The half-width in cells of the box holding the path nodes and control points the fragment search
// reached: cracks are only ever added, so a fragment only loses control points, and only where a new
// segment cuts one of those straight hops.
double verdict_reach(const Eigen::Vector2d& xi, const ControlGrid& grid, const FragmentWork& fw) {
  double r = 0.0;
  for (size_t i = 0; i < fw.paths.num_settled(); ++i) r = std::max(r, box_reach(xi, fw.paths.settled_point(i), grid));
  for (const ReachedPoint& p : fw.reached) r = std::max(r, box_reach(xi, grid.point(p.index), grid));
  return r * (1.0 + 1e-9) + 1e-9;
}

// Level 5: the whole fragment, however far. If it spans a plane, a linear fit over all of it; otherwise
// (or if that fails) rigid: the fragment's control points, equally weighted (a rigid translation with
// their mean motion); removed if there are none.
void fit_whole_fragment(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                        const crack2d::CrackPortals& portals, const BasisChainSettings& s, BasisChainWork& work,
                        PointFit& fit) {
  FragmentWork& fw = work.fragment;
  MlsBasis& b = work.basis;
  const bool spans = reach_fragment(xi, grid, index, portals, true, fw);
  double reach = verdict_reach(xi, grid, fw);
  if (spans) {
    double longest = 0.0;
    for (const ReachedPoint& r : fw.reached) longest = std::max(longest, r.length);
    const double limit = 1.25 * longest + s.mls.initial_factor;
    gather_along_paths(xi, grid, index, portals, limit, false, fw);
    MlsSettings lin = linear_settings(s);
    lin.initial_factor = std::min(lin.initial_factor, limit);
    lin.max_factor = limit;
    if (fit_along_paths(xi, grid, fw.reached, lin, b)) {
      fit.level = BasisLevel::Fragment;
      fit.order = 1;
      fit.reach = std::max(reach, limit);
      return;
    }
    fit.chain_failed = true;  // the fragment could carry a basis but no fit was accepted
    fit.reason += "; no fit over its fragment either: " + b.reason;
    reach_fragment(xi, grid, index, portals, false, fw);
    reach = verdict_reach(xi, grid, fw);
  }
  b.index.clear();
  for (const ReachedPoint& r : fw.reached) b.index.push_back(r.index);
  const size_t n = b.index.size();
  b.R.assign(n, n > 0 ? 1.0 / static_cast<double>(n) : 0.0);
  for (auto* a : {&b.R1, &b.R2, &b.R11, &b.R12, &b.R22}) a->assign(n, 0.0);
  b.ok = n > 0;
  fit.level = n > 0 ? BasisLevel::Rigid : BasisLevel::Removed;
  fit.order = 0;
  fit.reach = reach;
}

}  // namespace

PointFit fit_point_basis(const Eigen::Vector2d& xi_in, const ControlGrid& grid, const crack2d::CrackIndex& index,
                         const crack2d::CrackPortals& portals, const BasisChainSettings& s, BasisChainWork& work) {
  PointFit fit;
  Eigen::Vector2d xi = xi_in;
  if (index.crosses(xi, xi)) {
    xi = nudge_off_crack(xi, grid, index, s);
    fit.nudged = true;
  }
  fit.at = xi;
  if (fit_in_sight(xi, grid, index, portals, s, work, fit)) return fit;
  if (fit_along_fragment_paths(xi, grid, index, portals, s, work, fit)) return fit;
  fit_whole_fragment(xi, grid, index, portals, s, work, fit);
  return fit;
}

}  // namespace shellfrac::shell
