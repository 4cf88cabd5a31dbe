#include "crack2d/sample_clearance.hpp"

namespace shellfrac::crack2d {

bool segment_hits_sample(const Point& a, const Point& b, const std::vector<Point>& samples, const SampleGrid& grid) {
  bool hit = false;
  const Point lo = a.cwiseMin(b), hi = a.cwiseMax(b);
  grid.for_each_within(0.5 * (a + b), 0.5 * (b - a).norm() + 1e-12, [&](int i) {
    const Point& s = samples[i];
    if (hit || s.x() < lo.x() || s.x() > hi.x() || s.y() < lo.y() || s.y() > hi.y()) return;
    hit = orientation(a, b, s) == 0;
  });
  return hit;
}

void clear_samples_off_edges(std::vector<Point>& nodes, const std::vector<std::array<int, 2>>& edges,
                             const std::vector<char>& movable, const std::vector<Point>& samples,
                             const SampleGrid& grid, double shift) {
  // A few rounds: moving a node can (rarely) put another of its edges onto a sample.
  for (int round = 0; round < 4; ++round) {
    bool moved = false;
    for (const auto& e : edges) {
      const Point &a = nodes[e[0]], &b = nodes[e[1]];
      if (a == b || !segment_hits_sample(a, b, samples, grid)) continue;
      const Point d = (b - a).normalized();
      // Across the segment, always towards the same side of a fixed direction, so that collinear
      // neighbours sharing the moved node push it the same way instead of cancelling.
      Point across(-d.y(), d.x());
      if (across.dot(Point(0.6, 0.8)) < 0.0) across = -across;
      // Move the later end when both may move; never an existing crack vertex.
      const int k = movable[e[1]] ? e[1] : movable[e[0]] ? e[0] : -1;
      if (k < 0) continue;
      nodes[k] += shift * across;
      moved = true;
    }
    if (!moved) break;
  }
}

}  // namespace shellfrac::crack2d
