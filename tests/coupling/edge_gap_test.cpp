// Edge extraction and the geometric coincidence check (arc-length pairing), plus interface detection.
#include "coupling/edge_gap.hpp"

#include <gtest/gtest.h>

#include "coupling/arc_length.hpp"
#include "coupling/edge.hpp"
#include "tests/coupling/coupling_test_helpers.hpp"

namespace shellfrac::coupling {
namespace {

using test::frame_at;

TEST(Edge, RowsAndCrossSpanOfEachSide) {
  const nurbs::NurbsSurface s = nurbs::flat_patch(2.0, 1.0, 4, 3);  // 6 x 5 control points
  const Edge u0 = extract_edge(s, Side::U0), u1 = extract_edge(s, Side::U1);
  const Edge v0 = extract_edge(s, Side::V0), v1 = extract_edge(s, Side::V1);
  EXPECT_EQ(u0.row1, (std::vector<int>{0, 6, 12, 18, 24}));
  EXPECT_EQ(u0.row2, (std::vector<int>{1, 7, 13, 19, 25}));
  EXPECT_EQ(u1.row1, (std::vector<int>{5, 11, 17, 23, 29}));
  EXPECT_EQ(u1.row2, (std::vector<int>{4, 10, 16, 22, 28}));
  EXPECT_EQ(v0.row1, (std::vector<int>{0, 1, 2, 3, 4, 5}));
  EXPECT_EQ(v1.row2, (std::vector<int>{18, 19, 20, 21, 22, 23}));
  EXPECT_DOUBLE_EQ(u0.cross_first_span, 0.25);
  EXPECT_DOUBLE_EQ(v1.cross_first_span, 1.0 / 3.0);
  EXPECT_EQ(u1.cross_degree, 2);
  EXPECT_EQ(u0.knots.num_basis(), 5);
  // The boundary row is the surface boundary.
  const nurbs::NurbsCurve c = edge_curve(s, Side::U1);
  for (double t : {0.0, 0.3, 0.77, 1.0}) EXPECT_LT((c.point(t) - s.point(1.0, t)).norm(), 1e-15);
}

TEST(ArcLength, QuarterCircleLengthAndInverse) {
  const nurbs::NurbsCurve arc = nurbs::circular_arc(2.0, 0.3, 0.5 * test::kPi);
  const ArcLength len(arc);
  EXPECT_NEAR(len.total(), test::kPi, 1e-13);
  for (double t : {0.0, 0.1, 0.5, 0.77, 1.0}) {
    EXPECT_NEAR(len.parameter_at(len.length_to(t)), t, 1e-13);
    // Arc length on a circle is radius times the swept angle.
    const Vec3 p = arc.point(t);
    EXPECT_NEAR(len.length_to(t), 2.0 * (std::atan2(p.y(), p.x()) - 0.3), 1e-13);
  }
}

TEST(EdgeGap, CoincidentEdgesWithDifferentResolution) {
  const nurbs::NurbsSurface left = nurbs::flat_patch(1.0, 1.0, 4, 10, frame_at(Vec3(-1, 0, 0)));
  const nurbs::NurbsSurface right = nurbs::flat_patch(1.0, 1.0, 5, 13);
  EXPECT_LT(edge_gap(left, Side::U1, right, Side::U0, false), 1e-12);
}

TEST(EdgeGap, RigidOffsetIsReportedExactly) {
  const nurbs::NurbsSurface left = nurbs::flat_patch(1.0, 1.0, 4, 10, frame_at(Vec3(-1, 0, 0)));
  const nurbs::NurbsSurface lifted = nurbs::flat_patch(1.0, 1.0, 5, 13, frame_at(Vec3(0, 0, 1e-3)));
  const nurbs::NurbsSurface slid = nurbs::flat_patch(1.0, 1.0, 5, 13, frame_at(Vec3(0, 1e-3, 0)));
  EXPECT_NEAR(edge_gap(left, Side::U1, lifted, Side::U0, false), 1e-3, 1e-9);
  EXPECT_NEAR(edge_gap(left, Side::U1, slid, Side::U0, false), 1e-3, 1e-9);
  // Curved (rational) edge: a cylinder ring and a copy raised by 1e-3 along its axis.
  const nurbs::NurbsSurface ring = nurbs::cylinder_segment(1.0, 1.0, 0.5 * test::kPi, 4, 2);
  const nurbs::NurbsSurface ring_up = nurbs::cylinder_segment(1.0, 1.0, 0.5 * test::kPi, 7, 2, frame_at(Vec3(0, 1.001, 0)));
  EXPECT_NEAR(edge_gap(ring, Side::V1, ring_up, Side::V0, false), 1e-3, 1e-9);
}

TEST(EdgeGap, ReversedOrientation) {
  const nurbs::NurbsSurface left = nurbs::flat_patch(1.0, 1.0, 4, 10, frame_at(Vec3(-1, 0, 0)));
  // v runs from y = 1 down to y = 0 on this patch.
  const nurbs::NurbsSurface flipped = nurbs::flat_patch(1.0, 1.0, 5, 13, frame_at(Vec3(0, 1, 0), Vec3::UnitX(), -Vec3::UnitY()));
  EXPECT_LT(edge_gap(left, Side::U1, flipped, Side::U0, true), 1e-12);
  EXPECT_NEAR(edge_gap(left, Side::U1, flipped, Side::U0, false), 1.0, 1e-9);  // wrong flag: ends swapped
}

TEST(EdgeGap, IndependentOfTheEdgeParameterisation) {
  // A straight edge x = 0, y in [0, 1] with a non-linear parameterisation (middle control point off-centre).
  const nurbs::NurbsSurface left = nurbs::flat_patch(1.0, 1.0, 1, 1, frame_at(Vec3(-1, 0, 0)));
  const nurbs::KnotVector k = nurbs::KnotVector::open_uniform(2, 1);
  nurbs::Vec3List pts;
  for (double y : {0.0, 0.8, 1.0}) {
    for (double x : {0.0, 0.5, 1.0}) pts.push_back(Vec3(x, y, 0));
  }
  const nurbs::NurbsSurface skewed(k, k, std::move(pts), std::vector<double>(9, 1.0));
  EXPECT_LT(edge_gap(left, Side::U1, skewed, Side::U0, false), 1e-12);
}

TEST(DetectCoincidentEdges, FindsSharedEdgesWithOrientation) {
  std::vector<nurbs::NurbsSurface> patches;
  patches.push_back(nurbs::flat_patch(1.0, 1.0, 4, 10, frame_at(Vec3(-1, 0, 0))));
  patches.push_back(nurbs::flat_patch(1.0, 1.0, 5, 13, frame_at(Vec3(0, 1, 0), Vec3::UnitX(), -Vec3::UnitY())));
  patches.push_back(nurbs::flat_patch(1.0, 1.0, 3, 3, frame_at(Vec3(5, 5, 0))));  // far away
  const std::vector<EdgeMatch> m = detect_coincident_edges(patches, 1e-9);
  ASSERT_EQ(m.size(), 1u);
  EXPECT_EQ(m[0].patch_a, 0);
  EXPECT_EQ(m[0].side_a, Side::U1);
  EXPECT_EQ(m[0].patch_b, 1);
  EXPECT_EQ(m[0].side_b, Side::U0);
  EXPECT_TRUE(m[0].reversed);
  EXPECT_LT(m[0].gap, 1e-12);
}

}  // namespace
}  // namespace shellfrac::coupling
