#include "crack2d/prescribed_cut.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>

namespace shellfrac::crack2d {

namespace {

std::string describe(const Point& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << p.x() << ", " << p.y() << ")";
  return s.str();
}

// Segment i runs from vertex i to vertex (i + 1) mod n.
void check_self_intersection(const std::vector<Point>& pts, bool closed) {
  const size_t n = pts.size();
  const size_t num_segments = closed ? n : n - 1;
  auto seg_a = [&](size_t i) { return pts[i]; };
  auto seg_b = [&](size_t i) { return pts[(i + 1) % n]; };
  // Sort segments by min x and sweep: pairs whose x-ranges overlap are tested exactly.
  std::vector<size_t> order(num_segments);
  std::iota(order.begin(), order.end(), size_t{0});
  auto min_x = [&](size_t i) { return std::min(seg_a(i).x(), seg_b(i).x()); };
  auto max_x = [&](size_t i) { return std::max(seg_a(i).x(), seg_b(i).x()); };
  std::sort(order.begin(), order.end(), [&](size_t l, size_t r) { return min_x(l) < min_x(r) || (min_x(l) == min_x(r) && l < r); });
  for (size_t oi = 0; oi < num_segments; ++oi) {
    const size_t i = order[oi];
    for (size_t oj = oi + 1; oj < num_segments && min_x(order[oj]) <= max_x(i); ++oj) {
      const size_t j = order[oj];
      const size_t lo = std::min(i, j), hi = std::max(i, j);
      const bool consecutive = hi == lo + 1 || (closed && lo == 0 && hi == num_segments - 1);
      if (!segments_intersect(seg_a(i), seg_b(i), seg_a(j), seg_b(j))) continue;
      if (consecutive) {
        // Neighbours share one vertex; they may only meet there, i.e. must not fold back onto each other.
        const size_t shared = (hi == lo + 1) ? hi : 0;
        const Point& s = pts[shared];
        const Point& prev = pts[(shared + n - 1) % n];
        const Point& next = pts[(shared + 1) % n];
        const bool folds = orientation(prev, s, next) == 0 && (prev - s).dot(next - s) > 0.0;
        if (!folds) continue;
      }
      throw CutError("prescribed cut: segment " + std::to_string(lo) + " intersects segment " + std::to_string(hi) +
                     " (self-intersecting polyline)");
    }
  }
}

}  // namespace

void validate_cut(const std::vector<Point>& polyline, bool closed, const Box& domain) {
  const size_t min_points = closed ? 3 : 2;
  if (polyline.size() < min_points)
    throw CutError("prescribed cut: " + std::string(closed ? "a closed curve" : "a polyline") + " needs at least " +
                   std::to_string(min_points) + " points, got " + std::to_string(polyline.size()));
  for (size_t i = 0; i < polyline.size(); ++i) {
    const Point& p = polyline[i];
    if (!std::isfinite(p.x()) || !std::isfinite(p.y()))
      throw CutError("prescribed cut: vertex " + std::to_string(i) + " is not finite");
    if (!box_contains(domain, p))
      throw CutError("prescribed cut: vertex " + std::to_string(i) + " " + describe(p) + " lies outside the domain " +
                     describe(domain.lo) + " - " + describe(domain.hi));
  }
  const size_t n = polyline.size();
  const size_t num_segments = closed ? n : n - 1;
  for (size_t i = 0; i < num_segments; ++i)
    if (polyline[i] == polyline[(i + 1) % n])
      throw CutError("prescribed cut: segment " + std::to_string(i) + " has zero length (vertex " + std::to_string(i) +
                     " repeats at " + describe(polyline[i]) + ")");
  check_self_intersection(polyline, closed);
}

int append_cut(CrackGraph& g, const std::vector<Point>& polyline, bool closed, const Box& domain) {
  validate_cut(polyline, closed, domain);
  const int first = static_cast<int>(g.num_vertices());
  for (const Point& p : polyline) g.add_vertex(p);
  const int n = static_cast<int>(polyline.size());
  for (int i = 0; i + 1 < n; ++i) g.add_edge(first + i, first + i + 1);
  if (closed) g.add_edge(first + n - 1, first);
  return first;
}

}  // namespace shellfrac::crack2d
