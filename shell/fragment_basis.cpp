#include "shell/fragment_basis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "crack2d/geometry.hpp"

namespace shellfrac::shell {


void gather_along_paths(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                        const crack2d::CrackPortals& portals, double limit, bool forward_only, FragmentWork& work) {
  const double lu = grid.cell_u, lv = grid.cell_v;
  crack2d::PathSettings ps;
  ps.scale_u = lu;
  ps.scale_v = lv;
  ps.limit = limit;
  // Forward: every bend goes on ahead of its corner and the path turns by at most 90 degrees in all, so
  // it never wraps around one crack's tip (nor, bend by bend, around several) to that crack's far side.
  ps.ahead_only = forward_only;
  ps.max_turn = forward_only ? 1.5707963267948966 : std::numeric_limits<double>::infinity();
  work.paths.start(index, portals, xi, ps);
  work.paths.settle_all();
  work.reached.clear();
  // A path no longer than `limit` ends within `limit` cells in a straight line.
  grid.for_each_in_box(xi, limit * lu, limit * lv, [&](int k, const Eigen::Vector2d& xk) {
    ReachedPoint r;
    r.index = k;
    if (work.paths.path_to(xk, r.length, r.first_hop) && r.length < limit) work.reached.push_back(r);
  });
}

bool fit_along_paths(const Eigen::Vector2d& xi, const ControlGrid& grid, const std::vector<ReachedPoint>& reached,
                     const MlsSettings& settings, MlsBasis& out) {
  if (!detail::check_mls_inputs(xi, grid.cell_u, grid.cell_v, settings, out)) return false;
  const double lu = grid.cell_u, lv = grid.cell_v;
  MlsBasis::Workspace& w = out.work;
  const std::size_t n = reached.size();
  for (auto* a : {&w.W, &w.W1, &w.W2, &w.W11, &w.W12, &w.W22, &w.e1, &w.e2}) a->resize(n);
  w.support.resize(n);
  double factor = settings.initial_factor;
  detail::MlsAttempt attempt;
  for (;;) {
    const double du = factor * lu, dv = factor * lv;
    std::size_t m = 0;
    for (const ReachedPoint& r : reached) {
      const double rr = r.length / factor;  // thesis Eq. 4.18 with the path length as distance
      const CubicWeight c = cubic_weight(rr);
      if (!(c.w > 0.0)) continue;
      const Eigen::Vector2d xk = grid.point(r.index);
      // Scaled vector from the evaluation point to the first hop; the path length changes with xi only
      // through that first segment: dr/dy = -t / |t|, d2r/dy2 = (I - n n^T) / |t|.
      const Eigen::Vector2d t((r.first_hop.x() - xi.x()) / du, (r.first_hop.y() - xi.y()) / dv);
      const double tn = t.norm();
      w.W[m] = c.w;
      if (tn > 1e-12) {
        const double g1 = -t.x() / tn, g2 = -t.y() / tn;
        w.W1[m] = c.dw * g1;
        w.W2[m] = c.dw * g2;
        w.W11[m] = c.ddw * g1 * g1 + c.dw * (1.0 - g1 * g1) / tn;
        w.W12[m] = c.ddw * g1 * g2 - c.dw * g1 * g2 / tn;
        w.W22[m] = c.ddw * g2 * g2 + c.dw * (1.0 - g2 * g2) / tn;
      } else {  // the control point sits at xi: a radial function has Hessian w''(0) I there
        w.W1[m] = w.W2[m] = w.W12[m] = 0.0;
        w.W11[m] = w.W22[m] = c.ddw;
      }
      w.e1[m] = (xk.x() - xi.x()) / du;
      w.e2[m] = (xk.y() - xi.y()) / dv;
      w.support[m] = r.index;
      ++m;
    }
    out.factor = factor;
    attempt = detail::mls_solve(m, du, dv, settings, out);
    if (attempt.status == MlsStatus::ok) return true;
    if (factor >= settings.max_factor) break;
    factor = std::min(factor * settings.growth, settings.max_factor);
  }
  detail::report_mls_failure(xi, attempt, settings, out);
  return false;
}

bool mls_basis_along_paths(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                           const crack2d::CrackPortals& portals, const MlsSettings& settings, bool forward_only,
                           FragmentWork& work, MlsBasis& out) {
  gather_along_paths(xi, grid, index, portals, settings.max_factor, forward_only, work);
  if (fit_along_paths(xi, grid, work.reached, settings, out)) return true;
  out.reason += forward_only ? " (along forward crack-free paths)" : " (along crack-free paths)";
  return false;
}

bool spans_plane(const ControlGrid& grid, const std::vector<ReachedPoint>& reached) {
  if (reached.size() < 3) return false;
  const Eigen::Vector2d a = grid.point(reached[0].index);
  std::size_t j = 1;
  while (j < reached.size() && grid.point(reached[j].index) == a) ++j;
  if (j == reached.size()) return false;
  const Eigen::Vector2d b = grid.point(reached[j].index);
  for (std::size_t k = j + 1; k < reached.size(); ++k)
    if (crack2d::orientation(a, b, grid.point(reached[k].index)) != 0) return true;
  return false;
}

bool reach_fragment(const Eigen::Vector2d& xi, const ControlGrid& grid, const crack2d::CrackIndex& index,
                    const crack2d::CrackPortals& portals, bool need_spread, FragmentWork& work) {
  crack2d::PathSettings ps;
  ps.scale_u = grid.cell_u;
  ps.scale_v = grid.cell_v;  // no limit on length or turning: the whole fragment
  work.paths.start(index, portals, xi, ps);
  work.reached.clear();
  // Control points nearest first; each newly settled path node tests the ones not reached yet. The length
  // recorded is that through the first node that sees the point (an upper bound of the shortest path).
  std::vector<std::pair<double, int>> order;
  order.reserve(static_cast<std::size_t>(grid.size()));
  for (int k = 0; k < grid.size(); ++k) order.emplace_back(work.paths.scaled_length(xi, grid.point(k)), k);
  std::sort(order.begin(), order.end());
  std::vector<unsigned char> found(static_cast<std::size_t>(grid.size()), 0);
  for (std::size_t node = 0;; ++node) {
    if (node == work.paths.num_settled() && !work.paths.settle_next()) break;
    const Eigen::Vector2d p = work.paths.settled_point(node);
    const double base = work.paths.settled_length(node);
    for (const auto& entry : order) {
      const int k = entry.second;
      if (found[static_cast<std::size_t>(k)]) continue;
      const Eigen::Vector2d xk = grid.point(k);
      if (index.crosses(p, xk)) continue;
      found[static_cast<std::size_t>(k)] = 1;
      ReachedPoint r;
      r.index = k;
      r.length = base + work.paths.scaled_length(p, xk);
      r.first_hop = node == 0 ? xk : p;  // here: the path node that sees it
      work.reached.push_back(r);
      if (need_spread && spans_plane(grid, work.reached)) return true;
    }
  }
  std::sort(work.reached.begin(), work.reached.end(),
            [](const ReachedPoint& a, const ReachedPoint& b) { return a.length < b.length; });
  return false;
}

}  // namespace shellfrac::shell
