#include "crack2d/crack_index.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

namespace shellfrac::crack2d {
namespace {

// Coordinates on a coarse dyadic lattice (multiples of 1/64, exactly representable) make shared
// endpoints, T-junctions and collinear overlaps common, so the exact paths are exercised.
double lattice(std::mt19937_64& rng, int lo, int hi) { return std::uniform_int_distribution<int>(lo, hi)(rng) / 64.0; }

Point lattice_point(std::mt19937_64& rng) { return Point(lattice(rng, -8, 72), lattice(rng, -8, 72)); }

// Short random segment: a lattice point plus a small lattice offset (sometimes zero length).
Segment short_lattice_segment(std::mt19937_64& rng) {
  const Point a = lattice_point(rng);
  return {a, a + Point(lattice(rng, -6, 6), lattice(rng, -6, 6))};
}

// Integer reference for lattice segments, independent of geometry.hpp.
bool reference_intersect(const Segment& s, const Segment& t) {
  auto q = [](const Point& p) { return std::array<long long, 2>{std::llround(p.x() * 64), std::llround(p.y() * 64)}; };
  const auto a = q(s.a), b = q(s.b), c = q(t.a), d = q(t.b);
  auto orient = [](const std::array<long long, 2>& p, const std::array<long long, 2>& r, const std::array<long long, 2>& u) {
    const long long v = (r[0] - p[0]) * (u[1] - p[1]) - (r[1] - p[1]) * (u[0] - p[0]);
    return (v > 0) - (v < 0);
  };
  auto on = [](const std::array<long long, 2>& p, const std::array<long long, 2>& r, const std::array<long long, 2>& u) {
    return std::min(p[0], r[0]) <= u[0] && u[0] <= std::max(p[0], r[0]) && std::min(p[1], r[1]) <= u[1] &&
           u[1] <= std::max(p[1], r[1]);
  };
  const int o1 = orient(a, b, c), o2 = orient(a, b, d), o3 = orient(c, d, a), o4 = orient(c, d, b);
  if (o1 * o2 < 0 && o3 * o4 < 0) return true;
  if (o1 == 0 && on(a, b, c)) return true;
  if (o2 == 0 && on(a, b, d)) return true;
  if (o3 == 0 && on(c, d, a)) return true;
  if (o4 == 0 && on(c, d, b)) return true;
  return false;
}

CrackGraph random_crack(std::mt19937_64& rng, int segments) {
  CrackGraph g;
  for (int i = 0; i < segments; ++i) {
    const Segment s = short_lattice_segment(rng);
    g.add_edge(g.add_vertex(s.a), g.add_vertex(s.b));  // zero-length ones are ignored as self-loops
  }
  return g;
}

TEST(CrackIndex, CrossesAgreesWithIntegerBruteForce) {
  std::mt19937_64 rng(42);
  const CrackGraph g = random_crack(rng, 600);
  CrackIndex index;
  index.rebuild(g);
  ASSERT_EQ(index.num_segments(), g.num_edges());
  int hits_index = 0, hits_reference = 0, disagreements = 0;
  for (int q = 0; q < 5000; ++q) {
    // Mix of short queries (MLS-support size) and long ones crossing many cells.
    Segment s = short_lattice_segment(rng);
    if (q % 5 == 0) s.b = lattice_point(rng);
    bool reference = false;
    for (size_t e = 0; e < g.num_edges() && !reference; ++e) reference = reference_intersect(s, g.segment(e));
    const bool indexed = index.crosses(s.a, s.b);
    hits_index += indexed;
    hits_reference += reference;
    disagreements += indexed != reference;
  }
  EXPECT_EQ(disagreements, 0);
  EXPECT_EQ(hits_index, hits_reference);
  EXPECT_GT(hits_reference, 500);   // both outcomes are well represented
  EXPECT_LT(hits_reference, 4900);
}

TEST(CrackIndex, IncrementalEqualsRebuild) {
  std::mt19937_64 rng(3);
  const CrackGraph g = random_crack(rng, 800);
  CrackIndex full, incremental;
  full.rebuild(g);
  for (size_t k = 0; k < g.num_edges(); k += 37) {
    // Feed a growing prefix graph, as the extractor does.
    CrackGraph prefix;
    for (const Point& p : g.vertices()) prefix.add_vertex(p);
    for (size_t e = 0; e < std::min(g.num_edges(), k + 37); ++e) prefix.add_edge(g.edges()[e][0], g.edges()[e][1]);
    incremental.add_edges(prefix, k);
  }
  ASSERT_EQ(incremental.num_segments(), g.num_edges());
  int disagreements = 0;
  for (int q = 0; q < 3000; ++q) {
    const Segment s = short_lattice_segment(rng);
    disagreements += full.crosses(s.a, s.b) != incremental.crosses(s.a, s.b);
  }
  EXPECT_EQ(disagreements, 0);
}

TEST(CrackIndex, TouchesAgreesWithBruteForce) {
  std::mt19937_64 rng(11);
  const CrackGraph g = random_crack(rng, 1000);
  CrackIndex index;
  index.rebuild(g);
  const size_t first_edge = g.num_edges() / 2;
  int disagreements = 0, hits = 0;
  for (int q = 0; q < 4000; ++q) {
    const Point a = lattice_point(rng);
    const Box box{a, a + Point(lattice(rng, 0, 5), lattice(rng, 0, 5))};
    const size_t first = q % 2 ? first_edge : 0;
    bool reference = false;
    for (size_t e = first; e < g.num_edges() && !reference; ++e) {
      const Segment s = g.segment(e);
      // Reference: an endpoint inside, or a crossing of one of the four sides (integer predicate).
      const Point c10(box.hi.x(), box.lo.y()), c01(box.lo.x(), box.hi.y());
      reference = box_contains(box, s.a) || box_contains(box, s.b) || reference_intersect(s, {box.lo, c10}) ||
                  reference_intersect(s, {c10, box.hi}) || reference_intersect(s, {box.hi, c01}) ||
                  reference_intersect(s, {c01, box.lo});
    }
    const bool indexed = index.touches(box, first);
    hits += indexed;
    disagreements += indexed != reference;
  }
  EXPECT_EQ(disagreements, 0);
  EXPECT_GT(hits, 300);
}

TEST(CrackIndex, DistanceAgreesWithBruteForce) {
  std::mt19937_64 rng(5);
  const CrackGraph g = random_crack(rng, 300);
  CrackIndex index;
  index.rebuild(g);
  std::uniform_real_distribution<double> u(-0.2, 1.2);
  double worst = 0.0;
  int capped = 0;
  for (int q = 0; q < 3000; ++q) {
    const Point p(u(rng), u(rng));
    const double cap = q % 3 == 0 ? 0.05 : 10.0;
    double reference = cap;
    for (size_t e = 0; e < g.num_edges(); ++e) reference = std::min(reference, point_segment_distance(p, g.segment(e)));
    const double indexed = index.distance(p, cap);
    worst = std::max(worst, std::abs(indexed - reference));
    capped += indexed == cap;
  }
  EXPECT_EQ(worst, 0.0);  // same formula on the same segments: bit-identical minimum
  EXPECT_GT(capped, 10);
}

TEST(CrackIndex, EmptyAndOutOfDomain) {
  CrackIndex index;
  EXPECT_FALSE(index.crosses(Point(0, 0), Point(1, 1)));
  EXPECT_FALSE(index.touches(Box{Point(0, 0), Point(1, 1)}));
  EXPECT_EQ(index.distance(Point(0.5, 0.5), 0.25), 0.25);
  CrackGraph g;
  g.add_edge(g.add_vertex(Point(-3, 0.5)), g.add_vertex(Point(-2, 0.5)));  // entirely outside the domain
  g.add_edge(g.add_vertex(Point(0.5, -1)), g.add_vertex(Point(0.5, 2)));   // crosses the whole domain
  index.rebuild(g);
  EXPECT_TRUE(index.crosses(Point(-2.5, 0), Point(-2.5, 1)));
  EXPECT_TRUE(index.crosses(Point(0, 0.3), Point(1, 0.3)));
  EXPECT_FALSE(index.crosses(Point(0, 0.3), Point(0.49, 0.3)));
  EXPECT_NEAR(index.distance(Point(-1, 0.5), 5.0), 1.0, 1e-15);
  EXPECT_NEAR(index.distance(Point(0.75, 0.5), 5.0), 0.25, 1e-15);
  EXPECT_TRUE(index.touches(Box{Point(0.5, 0.9), Point(0.6, 1.0)}, 1));
  EXPECT_FALSE(index.touches(Box{Point(0.5, 0.9), Point(0.6, 1.0)}, 2));
}

}  // namespace
}  // namespace shellfrac::crack2d
