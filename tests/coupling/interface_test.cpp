// Interface set-up: leader choice, row bookkeeping, and clear errors for edges that cannot be coupled.
#include "coupling/interface.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/coupling/coupling_test_helpers.hpp"

namespace shellfrac::coupling {
namespace {

using ::testing::HasSubstr;
using test::error_message;
using test::frame_at;

nurbs::NurbsSurface left_patch(int cells_v = 10) { return nurbs::flat_patch(1.0, 1.0, 4, cells_v, frame_at(Vec3(-1, 0, 0))); }

TEST(Interface, LowerResolutionEdgeLeads) {
  const nurbs::NurbsSurface fine = left_patch(13);
  const nurbs::NurbsSurface coarse = nurbs::flat_patch(1.0, 1.0, 3, 5);
  const Interface itf = make_interface(fine, 7, Side::U1, coarse, 9, Side::U0, false);
  EXPECT_EQ(itf.leader_patch, 9);
  EXPECT_EQ(itf.follower_patch, 7);
  EXPECT_EQ(itf.leader_side, Side::U0);
  EXPECT_EQ(itf.follower_side, Side::U1);
  EXPECT_EQ(itf.M0.rows(), 15);
  EXPECT_EQ(itf.M0.cols(), 7);
  EXPECT_EQ(itf.M1.rows(), 15);
  EXPECT_EQ(itf.follower_row1.front(), fine.flat_index(5, 0));
  EXPECT_EQ(itf.follower_row2.front(), fine.flat_index(4, 0));
  EXPECT_EQ(itf.common_knots.size(), 3 + 4 + 12 + 3);  // 4 and 12 interior knots, none shared
  // follower_positions lists row 1 then row 2.
  std::vector<Vec3> lx(coarse.control_points().begin(), coarse.control_points().end());
  EXPECT_EQ(itf.follower_positions(lx).size(), 30u);
}

TEST(Interface, RejectsDifferentDegreesAlongTheEdge) {
  const nurbs::NurbsSurface cubic = test::flat_patch_general(nurbs::KnotVector::open_uniform(2, 4),
                                                             nurbs::KnotVector::open_uniform(3, 6), 1.0, 1.0, nurbs::Frame{});
  EXPECT_THAT(error_message([&] { make_interface(left_patch(), 0, Side::U1, cubic, 1, Side::U0, false); }),
              HasSubstr("cannot couple patch 0 side U1 and patch 1 side U0: degrees along the edge differ (2 vs 3)"));
}

TEST(Interface, RejectsEdgesOfDifferentLength) {
  const nurbs::NurbsSurface taller = nurbs::flat_patch(1.0, 1.2, 4, 13);
  EXPECT_THAT(error_message([&] { make_interface(left_patch(), 0, Side::U1, taller, 1, Side::U0, false); }),
              HasSubstr("the edges have different lengths (1 vs 1.2"));
}

TEST(Interface, RejectsEdgesThatDoNotCoincideWithTheGap) {
  const nurbs::NurbsSurface lifted = nurbs::flat_patch(1.0, 1.0, 4, 13, frame_at(Vec3(0, 0, 1e-3)));
  EXPECT_THAT(error_message([&] { make_interface(left_patch(), 0, Side::U1, lifted, 1, Side::U0, false); }),
              HasSubstr("the edges do not coincide (max gap 0.001 > tolerance 1e-08, reversed = false)"));
  // Right edges, wrong orientation flag.
  const nurbs::NurbsSurface right = nurbs::flat_patch(1.0, 1.0, 4, 13);
  EXPECT_THAT(error_message([&] { make_interface(left_patch(), 0, Side::U1, right, 1, Side::U0, true); }),
              HasSubstr("the edges do not coincide (max gap 1 > tolerance"));
}

TEST(Interface, RejectsDifferentParameterisationsOfTheSameEdge) {
  // Same straight edge, but the middle control point is off-centre: a non-affine reparameterisation.
  const nurbs::KnotVector k = nurbs::KnotVector::open_uniform(2, 1);
  nurbs::Vec3List pts;
  for (double y : {0.0, 0.8, 1.0}) {
    for (double x : {0.0, 0.5, 1.0}) pts.push_back(Vec3(x, y, 0));
  }
  const nurbs::NurbsSurface skewed(k, k, std::move(pts), std::vector<double>(9, 1.0));
  EXPECT_THAT(error_message([&] { make_interface(left_patch(), 0, Side::U1, skewed, 1, Side::U0, false); }),
              HasSubstr("are parameterised differently"));
}

TEST(Interface, RejectsControlArraysTooShort) {
  const Interface itf = make_interface(left_patch(), 0, Side::U1, nurbs::flat_patch(1.0, 1.0, 4, 20), 1, Side::U0, false);
  std::vector<Vec3> small(3, Vec3::Zero()), out(3, Vec3::Zero());
  EXPECT_THAT(error_message([&] { itf.apply(small, out); }), HasSubstr("leader control point array has 3 entries"));
}

}  // namespace
}  // namespace shellfrac::coupling
