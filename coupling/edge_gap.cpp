#include "coupling/edge_gap.hpp"

#include <algorithm>
#include <cmath>

#include "coupling/arc_length.hpp"
#include "coupling/coupling_error.hpp"

namespace shellfrac::coupling {

namespace {

constexpr Side kSides[] = {Side::U0, Side::U1, Side::V0, Side::V1};

// Largest distance from points of `from` (uniform in its parameter) to the points of `to` at the same
// arc-length fraction.
double one_way_gap(const nurbs::NurbsCurve& from, const ArcLength& from_len, const nurbs::NurbsCurve& to,
                   const ArcLength& to_len, bool reversed, int samples) {
  const double lo = from.knots().domain_begin(), hi = from.knots().domain_end();
  double worst = 0.0;
  for (int k = 0; k < samples; ++k) {
    const double t = lo + (hi - lo) * k / (samples - 1);
    double f = from_len.total() > 0.0 ? from_len.length_to(t) / from_len.total() : 0.0;
    if (reversed) f = 1.0 - f;
    const double t_other = to_len.parameter_at(f * to_len.total());
    worst = std::max(worst, (from.point(t) - to.point(t_other)).norm());
  }
  return worst;
}

}  // namespace

double edge_gap(const nurbs::NurbsSurface& a, Side sa, const nurbs::NurbsSurface& b, Side sb, bool reversed,
                int samples) {
  if (samples < 2) throw CouplingError("edge_gap needs at least 2 samples, got " + std::to_string(samples));
  const nurbs::NurbsCurve ca = edge_curve(a, sa);
  const nurbs::NurbsCurve cb = edge_curve(b, sb);
  const ArcLength la(ca), lb(cb);
  return std::max(one_way_gap(ca, la, cb, lb, reversed, samples), one_way_gap(cb, lb, ca, la, reversed, samples));
}

std::vector<EdgeMatch> detect_coincident_edges(const std::vector<nurbs::NurbsSurface>& patches, double tolerance,
                                               int samples) {
  std::vector<EdgeMatch> matches;
  for (std::size_t i = 0; i < patches.size(); ++i) {
    for (std::size_t j = i + 1; j < patches.size(); ++j) {
      for (Side sa : kSides) {
        const nurbs::NurbsCurve ca = edge_curve(patches[i], sa);
        const Vec3 a0 = ca.control_points().front(), a1 = ca.control_points().back();
        if (ArcLength(ca).total() <= tolerance) continue;
        for (Side sb : kSides) {
          const nurbs::NurbsCurve cb = edge_curve(patches[j], sb);
          const Vec3 b0 = cb.control_points().front(), b1 = cb.control_points().back();
          // Cheap corner test first; a closed edge may pass both, then keep the smaller gap.
          const bool same = (a0 - b0).norm() <= tolerance && (a1 - b1).norm() <= tolerance;
          const bool flipped = (a0 - b1).norm() <= tolerance && (a1 - b0).norm() <= tolerance;
          EdgeMatch best{static_cast<int>(i), sa, static_cast<int>(j), sb, false, HUGE_VAL};
          for (bool reversed : {false, true}) {
            if (reversed ? !flipped : !same) continue;
            const double gap = edge_gap(patches[i], sa, patches[j], sb, reversed, samples);
            if (gap < best.gap) {
              best.gap = gap;
              best.reversed = reversed;
            }
          }
          if (best.gap <= tolerance) matches.push_back(best);
        }
      }
    }
  }
  return matches;
}

}  // namespace shellfrac::coupling
