#include "crack2d/crack_graph.hpp"
#include "crack2d/geometry.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace shellfrac::crack2d {
namespace {

// Independent reference: points on the lattice m * 2^-40 (|m| < 2^41), orientation in 128-bit integers.
constexpr double kLattice = 1.0 / 1099511627776.0;  // 2^-40
__extension__ typedef __int128 int128;
int exact_lattice_orientation(const Point& a, const Point& b, const Point& c) {
  auto q = [](double x) { return static_cast<int128>(std::llround(x / kLattice)); };
  const int128 det = (q(b.x()) - q(a.x())) * (q(c.y()) - q(a.y())) - (q(b.y()) - q(a.y())) * (q(c.x()) - q(a.x()));
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

TEST(Orientation, ExactOnNearlyCollinearLatticePoints) {
  std::mt19937_64 rng(7);
  std::uniform_int_distribution<long long> coord(0, (1LL << 40) - 1);
  std::uniform_int_distribution<int> jitter(-2, 2);
  int zero = 0, mismatches = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const Point a(coord(rng) * kLattice, coord(rng) * kLattice);
    const Point b(coord(rng) * kLattice, coord(rng) * kLattice);
    // c near the line ab: midpoint rounded to the lattice, then nudged by a few lattice steps.
    const Point mid = 0.5 * (a + b);
    const Point c(std::round(mid.x() / kLattice + jitter(rng)) * kLattice, std::round(mid.y() / kLattice + jitter(rng)) * kLattice);
    const int expected = exact_lattice_orientation(a, b, c);
    zero += expected == 0;
    mismatches += orientation(a, b, c) != expected;
  }
  EXPECT_EQ(mismatches, 0);
  EXPECT_GT(zero, 100);  // the sample really exercises exact collinearity
}

TEST(Orientation, ClassicFailureOfNaiveEvaluation) {
  // Points (0.5 + i ulp, 0.5 + j ulp) against the line through (12,12)-(24,24): the true sign is sign(j - i).
  const double ulp = std::ldexp(1.0, -53);
  int mismatches = 0;
  for (int i = 0; i < 64; ++i)
    for (int j = 0; j < 64; ++j) {
      const Point p(0.5 + i * ulp, 0.5 + j * ulp);
      const int expected = (j > i) - (j < i);
      mismatches += orientation(Point(12, 12), Point(24, 24), p) != expected;
    }
  EXPECT_EQ(mismatches, 0);
}

TEST(SegmentsIntersect, ElementaryCases) {
  const Point o(0, 0), x(1, 0), y(0, 1), xy(1, 1);
  EXPECT_TRUE(segments_intersect(o, xy, x, y));                            // proper crossing
  EXPECT_TRUE(segments_intersect(o, x, x, xy));                            // shared endpoint
  EXPECT_TRUE(segments_intersect(o, x, Point(0.5, 0), Point(0.5, 1)));     // T: endpoint on interior
  EXPECT_TRUE(segments_intersect(o, x, Point(0.25, 0), Point(2, 0)));      // collinear overlap
  EXPECT_TRUE(segments_intersect(o, x, Point(1, 0), Point(2, 0)));         // collinear, touching ends
  EXPECT_FALSE(segments_intersect(o, x, Point(1.0000001, 0), Point(2, 0)));  // collinear, disjoint
  EXPECT_FALSE(segments_intersect(o, x, Point(0, 1e-300), Point(1, 1e-300)));  // parallel, tiny gap
  EXPECT_FALSE(segments_intersect(o, x, Point(0.5, std::nextafter(0.0, 1.0)), Point(0.5, 1)));  // near miss
  EXPECT_TRUE(segments_intersect(Point(0.5, 0.5), Point(0.5, 0.5), Point(0, 0), Point(1, 1)));  // point on segment
  EXPECT_FALSE(segments_intersect(Point(0.5, 0.5 + 1e-17 * 64), Point(0.5, 0.5 + 1e-17 * 64), Point(0, 0), Point(1, 1)));
}

TEST(SegmentBox, TouchingCornerAndEdge) {
  const Box box{Point(0, 0), Point(1, 1)};
  EXPECT_TRUE(segment_intersects_box({Point(-1, 1), Point(1, -1)}, box));    // through the corner (0,0)
  EXPECT_TRUE(segment_intersects_box({Point(-1, 2), Point(1, 0)}, box));     // touches corner (0,1)... and (1,0)
  EXPECT_TRUE(segment_intersects_box({Point(2, 1), Point(3, 1)}, {Point(0, 0), Point(2, 1)}));  // touches corner
  EXPECT_FALSE(segment_intersects_box({Point(-1, 2.0000001), Point(1, 0.0000001 + 1)}, box));
  EXPECT_TRUE(segment_intersects_box({Point(0.2, 0.2), Point(0.3, 0.3)}, box));  // inside
}

TEST(CrackGraph, IgnoresSelfLoopsAndDuplicatesAndChecksSubset) {
  CrackGraph g;
  const int a = g.add_vertex(Point(0, 0)), b = g.add_vertex(Point(1, 0)), c = g.add_vertex(Point(1, 1));
  g.add_edge(a, b);
  g.add_edge(b, a);
  g.add_edge(a, a);
  EXPECT_EQ(g.num_edges(), 1u);
  const CrackGraph before = g;
  g.add_edge(b, c);
  EXPECT_TRUE(g.contains(before));
  EXPECT_FALSE(before.contains(g));
  CrackGraph moved;
  moved.add_vertex(Point(0, 0));
  moved.add_vertex(Point(std::nextafter(1.0, 2.0), 0));  // one ulp off: not the same vertex
  moved.add_vertex(Point(1, 1));
  moved.add_edge(0, 1);
  EXPECT_FALSE(moved.contains(before));
  EXPECT_THROW(g.add_edge(0, 7), std::out_of_range);
}

}  // namespace
}  // namespace shellfrac::crack2d
