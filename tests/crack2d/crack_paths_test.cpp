// Shortest crack-free paths around crack corners (crack2d/crack_paths.hpp), checked against path
// lengths worked out by hand.
#include <gtest/gtest.h>

#include <cmath>

#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"

namespace shellfrac::crack2d {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr double kOffset = 1e-9;  // portal offset: path lengths are exact up to a few times this

struct Scene {
  CrackGraph graph;
  CrackIndex index;
  CrackPortals portals;
  void polyline(std::initializer_list<Point> pts, bool closed = false) {
    int first = -1, prev = -1;
    for (const Point& p : pts) {
      const int v = graph.add_vertex(p);
      if (prev >= 0) graph.add_edge(prev, v);
      if (first < 0) first = v;
      prev = v;
    }
    if (closed) graph.add_edge(prev, first);
  }
  void commit() {
    index.rebuild(graph);
    portals.build(index, kOffset);
  }
};

TEST(CrackPaths, PortalsSitAtTipsAndReflexCornersOnly) {
  Scene s;
  s.polyline({Point(0.1, 0.5), Point(0.3, 0.5), Point(0.5, 0.5)});  // straight: 2 tips, no bend
  s.polyline({Point(0.2, 0.8), Point(0.4, 0.8), Point(0.4, 0.6)});  // L: 2 tips + the reflex side of the bend
  // A junction of three branches 120 degrees apart: no sector is wider than pi, 3 tips.
  const Point j(0.7, 0.3);
  s.polyline({j, j + 0.1 * Point(1, 0)});
  s.polyline({j, j + 0.1 * Point(std::cos(2 * kPi / 3), std::sin(2 * kPi / 3))});
  s.polyline({j, j + 0.1 * Point(std::cos(4 * kPi / 3), std::sin(4 * kPi / 3))});
  s.commit();
  EXPECT_EQ(s.portals.size(), 2u + 3u + 3u);
  // The L's reflex portal lies outside the corner, on the bisector (1, -1)/sqrt 2 rotated to the open side.
  bool found = false;
  for (const Point& p : s.portals.points())
    if ((p - Point(0.4, 0.8)).norm() < 2 * kOffset) {
      found = true;
      EXPECT_GT(p.x(), 0.4);
      EXPECT_GT(p.y(), 0.8);
    }
  EXPECT_TRUE(found);
}

TEST(CrackPaths, PathAroundASlitTipHasTheUnfoldedLength) {
  // A slit from the left border to the tip (0.5, 0.5): from just below to just above it, the only way
  // round is past the tip, length |s - tip| + |tip - t|.
  Scene s;
  s.polyline({Point(0.0, 0.5), Point(0.5, 0.5)});
  s.commit();
  const Point src(0.3, 0.45), dst(0.2, 0.6), tip(0.5, 0.5);
  CrackPaths paths;
  paths.start(s.index, s.portals, src, PathSettings{});
  paths.settle_all();
  EXPECT_TRUE(paths.exhausted());
  double length = 0;
  Point hop;
  ASSERT_TRUE(paths.path_to(dst, length, hop));
  EXPECT_NEAR(length, (tip - src).norm() + (dst - tip).norm(), 1e-8);
  EXPECT_LE((hop - tip).norm(), 2 * kOffset);  // the first hop is the tip's portal
  EXPECT_EQ(paths.last_bends(), 1);
  // A point seen directly has the straight distance and itself as first hop.
  ASSERT_TRUE(paths.path_to(Point(0.6, 0.3), length, hop));
  EXPECT_NEAR(length, (Point(0.6, 0.3) - src).norm(), 1e-15);
  EXPECT_EQ(hop, Point(0.6, 0.3));
  // Scaled lengths: cells of 0.1 x 0.05 make the same path 10 and 20 times longer per axis.
  PathSettings scaled;
  scaled.scale_u = 0.1;
  scaled.scale_v = 0.05;
  paths.start(s.index, s.portals, src, scaled);
  paths.settle_all();
  ASSERT_TRUE(paths.path_to(dst, length, hop));
  const auto cells = [](const Point& d) { return std::hypot(d.x() / 0.1, d.y() / 0.05); };
  EXPECT_NEAR(length, cells(tip - src) + cells(dst - tip), 1e-6);
}

TEST(CrackPaths, TurningAndLengthLimitsExcludePathsBehindATip) {
  Scene s;
  s.polyline({Point(0.0, 0.5), Point(0.5, 0.5)});
  s.commit();
  const Point src(0.3, 0.45);
  // Ahead of the tip (turn about 30 degrees) and behind it (turn about 150 degrees).
  const Point ahead(0.7, 0.6), behind(0.3, 0.55);
  const Point tip(0.5, 0.5);
  const auto turn = [&](const Point& t) {
    const Point a = (tip - src).normalized(), b = (t - tip).normalized();
    return std::acos(a.dot(b));
  };
  ASSERT_LT(turn(ahead), kPi / 2);
  ASSERT_GT(turn(behind), kPi / 2);
  PathSettings limited;
  limited.max_turn = kPi / 2;
  CrackPaths paths;
  paths.start(s.index, s.portals, src, limited);
  paths.settle_all();
  double length = 0;
  Point hop;
  EXPECT_TRUE(paths.path_to(ahead, length, hop));
  EXPECT_FALSE(paths.path_to(behind, length, hop));
  // A length limit just below the unfolded length of `behind` excludes it too, even with any turning.
  PathSettings short_paths;
  short_paths.limit = (tip - src).norm() + (behind - tip).norm() - 1e-6;
  paths.start(s.index, s.portals, src, short_paths);
  paths.settle_all();
  EXPECT_FALSE(paths.path_to(behind, length, hop));
  short_paths.limit += 2e-6;
  paths.start(s.index, s.portals, src, short_paths);
  paths.settle_all();
  EXPECT_TRUE(paths.path_to(behind, length, hop));
}

TEST(CrackPaths, AheadOnlyPathsStayInTheHalfPlaneBeyondTheTip) {
  // Slit (0, 0.5) - (0.5, 0.5): ahead of its tip is u >= 0.5. From below, (0.55, 0.9) is reached around
  // the tip going ahead; (0.45, 0.9) only by bending back behind the slit, which ahead_only forbids
  // although that path turns less than 90 degrees.
  Scene s;
  s.polyline({Point(0.0, 0.5), Point(0.5, 0.5)});
  s.commit();
  ASSERT_EQ(s.portals.size(), 1u);
  EXPECT_LE((s.portals.ahead()[0] - Point(1, 0)).norm(), 1e-15);
  const Point src(0.45, 0.3), tip(0.5, 0.5);
  const Point behind(0.45, 0.9);
  ASSERT_LT(std::acos((tip - src).normalized().dot((behind - tip).normalized())), kPi / 2);
  PathSettings ahead;
  ahead.ahead_only = true;
  CrackPaths paths;
  paths.start(s.index, s.portals, src, ahead);
  paths.settle_all();
  double length = 0;
  Point hop;
  EXPECT_TRUE(paths.path_to(Point(0.55, 0.9), length, hop));
  EXPECT_FALSE(paths.path_to(behind, length, hop));
  EXPECT_TRUE(paths.path_to(Point(0.3, 0.2), length, hop));  // seen directly: no bend, no restriction
  paths.start(s.index, s.portals, src, PathSettings{});
  paths.settle_all();
  EXPECT_TRUE(paths.path_to(behind, length, hop));
}

TEST(CrackPaths, NoPathLeavesAClosedLoop) {
  // A closed square: inside and outside are different fragments; an L-shaped cut inside leaves one
  // fragment with a bend to go around.
  Scene s;
  s.polyline({Point(0.3, 0.3), Point(0.7, 0.3), Point(0.7, 0.7), Point(0.3, 0.7)}, true);
  s.polyline({Point(0.4, 0.6), Point(0.6, 0.6), Point(0.6, 0.4)});
  s.commit();
  CrackPaths paths;
  paths.start(s.index, s.portals, Point(0.65, 0.65), PathSettings{});
  paths.settle_all();
  EXPECT_TRUE(paths.exhausted());
  double length = 0;
  Point hop;
  EXPECT_FALSE(paths.path_to(Point(0.1, 0.1), length, hop));
  EXPECT_FALSE(paths.path_to(Point(0.8, 0.5), length, hop));
  // Around the L's tip (0.6, 0.4) to a point under its arm: (0.65,0.65) -> (0.6,0.4) -> (0.5,0.5)... the
  // straight line from the source to the tip runs inside the loop beside the arm.
  const Point dst(0.5, 0.5), tip(0.6, 0.4), src(0.65, 0.65);
  ASSERT_TRUE(paths.path_to(dst, length, hop));
  EXPECT_NEAR(length, (tip - src).norm() + (dst - tip).norm(), 1e-8);
}

}  // namespace
}  // namespace shellfrac::crack2d
