// Tests for flat_patch and cone_segment / cylinder_segment: layout, exact geometry, normals, validation.
#include "nurbs/patch_builders.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "nurbs/nurbs_error.hpp"
#include "tests/nurbs/nurbs_test_helpers.hpp"

namespace shellfrac::nurbs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

constexpr double kPi = 3.14159265358979323846;

// A tilted orthonormal frame away from the origin.
Frame tilted_frame() {
  const Eigen::Matrix3d R =
      (Eigen::AngleAxisd(0.4, Vec3(1, 2, 3).normalized()) * Eigen::AngleAxisd(-1.1, Vec3::UnitX())).toRotationMatrix();
  Frame f;
  f.origin = Vec3(10.0, -3.0, 2.5);
  f.axis_u = R.col(0);
  f.axis_v = R.col(1);
  return f;
}

TEST(FlatPatch, ControlPointSpacingIsCellSizeInsideAndHalfAtBorders) {
  // Dyadic sizes: every coordinate is exact, so compare exactly.
  const NurbsSurface s = flat_patch(2.0, 1.0, 8, 4);
  ASSERT_EQ(s.num_u(), 10);
  ASSERT_EQ(s.num_v(), 6);
  EXPECT_FALSE(s.is_rational());
  const double lu = 2.0 / 8, lv = 1.0 / 4;
  for (int j = 0; j < s.num_v(); ++j) {
    for (int i = 0; i + 1 < s.num_u(); ++i) {
      const double dx = s.control_points()[static_cast<size_t>(s.flat_index(i + 1, j))].x() -
                        s.control_points()[static_cast<size_t>(s.flat_index(i, j))].x();
      const bool border = i == 0 || i + 2 == s.num_u();
      EXPECT_EQ(dx, border ? lu / 2 : lu) << "i=" << i;
    }
  }
  for (int i = 0; i < s.num_u(); ++i) {
    for (int j = 0; j + 1 < s.num_v(); ++j) {
      const double dy = s.control_points()[static_cast<size_t>(s.flat_index(i, j + 1))].y() -
                        s.control_points()[static_cast<size_t>(s.flat_index(i, j))].y();
      const bool border = j == 0 || j + 2 == s.num_v();
      EXPECT_EQ(dy, border ? lv / 2 : lv) << "j=" << j;
    }
  }
  EXPECT_EQ(s.control_points().front(), Vec3(0, 0, 0));
  EXPECT_EQ(s.control_points().back(), Vec3(2, 1, 0));
}

TEST(FlatPatch, NonDyadicSpacingToRoundOff) {
  const double size = 0.7;
  const int cells = 7;
  const NurbsSurface s = flat_patch(size, size, cells, 3);
  const double l = size / cells;
  for (int i = 0; i + 1 < s.num_u(); ++i) {
    const double dx = s.control_points()[static_cast<size_t>(i + 1)].x() - s.control_points()[static_cast<size_t>(i)].x();
    const bool border = i == 0 || i + 2 == s.num_u();
    EXPECT_NEAR(dx, border ? l / 2 : l, 1e-15);
  }
}

TEST(FlatPatch, LinearPrecisionAndNormalInTiltedFrame) {
  const Frame f = tilted_frame();
  const double su = 3.0, sv = 1.7;
  const NurbsSurface s = flat_patch(su, sv, 5, 9, f);
  const Vec3 expected_normal = f.axis_u.cross(f.axis_v);
  for (int a = 0; a <= 40; ++a) {
    for (int b = 0; b <= 40; ++b) {
      const double u = a / 40.0, v = b / 40.0;
      const SurfacePoint sp = s.evaluate(u, v);
      const Vec3 bilinear = f.origin + (u * su) * f.axis_u + (v * sv) * f.axis_v;
      EXPECT_LE((sp.x - bilinear).norm(), 1e-14 * (1 + f.origin.norm()));
      EXPECT_LE((sp.du - su * f.axis_u).norm(), 1e-13 * su);
      EXPECT_LE((sp.dv - sv * f.axis_v).norm(), 1e-13 * sv);
      EXPECT_LE(sp.duu.norm() + sp.duv.norm() + sp.dvv.norm(), 1e-11 * (su + sv));
      // Tangents come from differences of control points of size |origin|, so their round-off scales
      // with |origin| / size.
      EXPECT_LE((sp.normal - expected_normal).norm(), 1e-14 * (1 + f.origin.norm() / std::min(su, sv)));
    }
  }
}

TEST(FlatPatchValidation, BadSizesCellsAndFrame) {
  EXPECT_THAT(error_message([] { flat_patch(0.0, 1.0, 2, 2); }),
              AllOf(HasSubstr("flat patch"), HasSubstr("size_u = 0"), HasSubstr("finite and > 0")));
  EXPECT_THAT(error_message([] { flat_patch(1.0, -2.0, 2, 2); }), HasSubstr("size_v = -2"));
  EXPECT_THAT(error_message([] { flat_patch(1.0, std::nan(""), 2, 2); }), HasSubstr("size_v = nan"));
  EXPECT_THAT(error_message([] { flat_patch(1.0, 1.0, 0, 2); }), AllOf(HasSubstr("cells_u = 0"), HasSubstr(">= 1")));
  EXPECT_THAT(error_message([] { flat_patch(1.0, 1.0, 2, -1); }), HasSubstr("cells_v = -1"));
  Frame skew;
  skew.axis_v = Vec3(0.1, 1, 0).normalized();
  EXPECT_THAT(error_message([&] { flat_patch(1.0, 1.0, 2, 2, skew); }),
              AllOf(HasSubstr("orthonormal"), HasSubstr("axis_u . axis_v")));
  Frame longer;
  longer.axis_u = Vec3(2, 0, 0);
  EXPECT_THAT(error_message([&] { flat_patch(1.0, 1.0, 2, 2, longer); }), HasSubstr("|axis_u| = 2"));
  Frame far_away;
  far_away.origin = Vec3(0, std::nan(""), 0);
  EXPECT_THAT(error_message([&] { flat_patch(1.0, 1.0, 2, 2, far_away); }),
              HasSubstr("frame origin and axes must be finite"));
  Frame almost;
  almost.axis_u = Vec3(1 + 1e-12, 0, 0);  // within 1e-9: accepted
  EXPECT_NO_THROW(flat_patch(1.0, 1.0, 2, 2, almost));
}

void check_cone(double r0, double r1, double height, double sweep, int cells_u, int cells_v, const Frame& f,
                int degree_u = 2, int degree_v = 2) {
  const NurbsSurface s = cone_segment(r0, r1, height, sweep, cells_u, cells_v, f, degree_u, degree_v);
  EXPECT_EQ(s.knots_u().degree(), degree_u);
  EXPECT_EQ(s.knots_v().degree(), degree_v);
  EXPECT_EQ(s.knots_u().num_spans(), cells_u);
  EXPECT_EQ(s.knots_v().num_spans(), cells_v);
  const Vec3 axis = f.axis_v;
  const double scale = std::max(r0, r1);
  // Round-off in absolute coordinates: the frame origin may be far from the axis point 0.
  const double coord = std::max({scale, height, f.origin.norm()});
  const double slope = r1 - r0;
  for (int a = 0; a <= 60; ++a) {
    for (int b = 0; b <= 20; ++b) {
      const double u = a / 60.0, v = b / 20.0;
      const SurfacePoint sp = s.evaluate(u, v);
      const Vec3 rel = sp.x - f.origin;
      const double h = rel.dot(axis);
      const Vec3 radial = rel - h * axis;
      const double radius = r0 + v * slope;
      EXPECT_NEAR(h, v * height, 1e-14 * coord) << u << "," << v;
      EXPECT_NEAR(radial.norm(), radius, 1e-14 * coord) << u << "," << v;
      // The seam (u = 0) lies on axis_u.
      if (a == 0 && radius > 0) {
        EXPECT_LE((radial / radius - f.axis_u).norm(), 1e-14 * coord / radius);
      }
      if (radius > 1e-12) {
        // Outward normal of a cone: (height * radial_dir - slope * axis) / sqrt(height^2 + slope^2).
        const Vec3 expected = (height * radial / radial.norm() - slope * axis) / std::hypot(height, slope);
        EXPECT_LE((sp.normal - expected).norm(), 1e-12 * coord / scale) << u << "," << v;
        EXPECT_GT(sp.normal.dot(radial), 0.0);
      }
    }
  }
  // End of the sweep: angle `sweep` from axis_u towards axis_v x axis_u.
  const Vec3 side = f.axis_v.cross(f.axis_u);
  const Vec3 end_dir = std::cos(sweep) * f.axis_u + std::sin(sweep) * side;
  const Vec3 end = s.point(1.0, 0.0) - f.origin;
  EXPECT_LE((end - r0 * end_dir).norm(), 1e-14 * coord);
}

TEST(ConeSegment, CylinderIsExactWithOutwardNormals) {
  check_cone(1.5, 1.5, 2.0, 2 * kPi, 4, 3, Frame{});
  check_cone(0.25, 0.25, 4.0, 2 * kPi, 16, 8, tilted_frame());
  check_cone(100.0, 100.0, 1.0, kPi / 3, 5, 2, tilted_frame());
}

TEST(ConeSegment, ConeRadiusLinearInHeight) {
  check_cone(2.0, 0.5, 3.0, 2 * kPi, 8, 4, Frame{});
  check_cone(0.3, 1.2, 0.5, 1.5 * kPi, 7, 3, tilted_frame());
  check_cone(1.0, 0.0, 1.0, kPi, 6, 5, Frame{});  // apex at the top
}

TEST(ConeSegment, RaisedDegreesKeepTheExactCone) {
  // k-refinement: the arc elevated before its cells' knots are inserted; still on the cone to round-off,
  // C^(p - 1) inside each arc piece (single knots) and with multiplicity p at the piece joints.
  check_cone(1.5, 1.5, 2.0, 2 * kPi, 8, 3, Frame{}, 3, 3);
  check_cone(2.0, 0.5, 3.0, 1.5 * kPi, 7, 4, tilted_frame(), 4, 2);
  check_cone(0.3, 1.2, 0.5, kPi / 3, 5, 2, tilted_frame(), 5, 4);
  const NurbsSurface s = cylinder_segment(1.0, 1.0, 2 * kPi, 8, 2, Frame{}, 4, 3);
  EXPECT_EQ(s.knots_u().multiplicity(0.25), 4);  // a joint of the four quarter arcs
  EXPECT_EQ(s.knots_u().multiplicity(0.125), 1);
  EXPECT_THAT(error_message([] { cone_segment(1, 1, 1, kPi, 4, 1, Frame{}, 1, 2); }), HasSubstr("degree_u = 1"));
  EXPECT_THAT(error_message([] { cone_segment(1, 1, 1, kPi, 4, 1, Frame{}, 2, 8); }), HasSubstr("degree_v = 8"));
}

TEST(FlatPatch, RaisedDegreesAreExactlyLinearWithSimpleKnots) {
  // Open uniform knots of degree p with control points at their Greville abscissae: the bilinear patch
  // k-refined, so positions stay linear in (u, v) and second derivatives vanish.
  const Frame f = tilted_frame();
  for (const auto& [p, q] : {std::pair{3, 3}, std::pair{4, 2}, std::pair{7, 5}}) {
    const NurbsSurface s = flat_patch(3.0, 1.7, 6, 5, f, p, q);
    EXPECT_EQ(s.num_u(), 6 + p);
    EXPECT_EQ(s.num_v(), 5 + q);
    EXPECT_EQ(s.knots_u().multiplicity(0.5), 1);
    for (int a = 0; a <= 30; ++a)
      for (int b = 0; b <= 30; ++b) {
        const double u = a / 30.0, v = b / 30.0;
        const SurfacePoint sp = s.evaluate(u, v);
        EXPECT_LE((sp.x - (f.origin + (3.0 * u) * f.axis_u + (1.7 * v) * f.axis_v)).norm(), 1e-13 * (1 + f.origin.norm()));
        EXPECT_LE(sp.duu.norm() + sp.duv.norm() + sp.dvv.norm(), 1e-10);
      }
  }
}

TEST(ConeSegment, CellsDistributedOverArcPieces) {
  // 2*pi = 4 pieces; 6 cells -> pieces get 2, 2, 1, 1 spans; piece joints stay double knots (C0 in u).
  const NurbsSurface s = cylinder_segment(1.0, 1.0, 2 * kPi, 6, 1);
  const KnotVector& ku = s.knots_u();
  EXPECT_EQ(ku.num_spans(), 6);
  EXPECT_EQ(ku.interior_breakpoints(), (std::vector<double>{0.125, 0.25, 0.375, 0.5, 0.75}));
  EXPECT_EQ(ku.multiplicity(0.125), 1);
  EXPECT_EQ(ku.multiplicity(0.25), 2);
  EXPECT_EQ(ku.multiplicity(0.5), 2);
  EXPECT_EQ(ku.multiplicity(0.75), 2);
  // v direction is the flat-patch layout: open quadratic with control rows at the Greville heights.
  EXPECT_EQ(s.knots_v().knots(), (std::vector<double>{0, 0, 0, 1, 1, 1}));

  const NurbsSurface quarter = cylinder_segment(1.0, 1.0, kPi / 2, 3, 1);
  EXPECT_EQ(quarter.knots_u().interior_breakpoints().size(), 2u);
  EXPECT_NEAR(quarter.knots_u().interior_breakpoints()[0], 1.0 / 3, 1e-16);
}

TEST(ConeSegment, ApexNormalIsDegenerate) {
  // At the apex of a cone (r1 = 0) du vanishes up to round-off; away from it the normal is fine.
  const NurbsSurface s = cone_segment(1.0, 0.0, 1.0, 2 * kPi, 4, 2);
  const SurfacePoint apex = s.evaluate(0.3, 1.0);
  EXPECT_LE(apex.du.norm(), 1e-14);
  EXPECT_NEAR(apex.x.x(), 0.0, 1e-15);  // on the axis (axis_v = y) at height 1
  EXPECT_NEAR(apex.x.y(), 1.0, 1e-15);
  EXPECT_NEAR(apex.x.z(), 0.0, 1e-15);
  const SurfacePoint below = s.evaluate(0.3, 0.9);
  EXPECT_NEAR(below.normal.norm(), 1.0, 1e-14);
}

TEST(ConeSegmentValidation, BadArguments) {
  EXPECT_THAT(error_message([] { cone_segment(-1.0, 1.0, 1.0, kPi, 2, 1); }),
              AllOf(HasSubstr("cone segment"), HasSubstr("r0 = -1"), HasSubstr(">= 0, and not both 0")));
  EXPECT_THAT(error_message([] { cone_segment(0.0, 0.0, 1.0, kPi, 2, 1); }), HasSubstr("not both 0"));
  EXPECT_THAT(error_message([] { cone_segment(1.0, 1.0, 0.0, kPi, 2, 1); }),
              AllOf(HasSubstr("height = 0"), HasSubstr("> 0")));
  EXPECT_THAT(error_message([] { cone_segment(1.0, 1.0, 1.0, 0.0, 2, 1); }),
              AllOf(HasSubstr("sweep 0"), HasSubstr("0 < sweep <= 2*pi")));
  EXPECT_THAT(error_message([] { cone_segment(1.0, 1.0, 1.0, 7.0, 8, 1); }), HasSubstr("sweep 7"));
  EXPECT_THAT(error_message([] { cone_segment(1.0, 1.0, 1.0, 1.5 * kPi, 2, 1); }),
              AllOf(HasSubstr("cells_u = 2"), HasSubstr("3 arc pieces"), HasSubstr("cells_u >= 3")));
  EXPECT_THAT(error_message([] { cylinder_segment(1.0, 1.0, kPi, 2, 0); }), HasSubstr("cells_v = 0"));
  Frame bad;
  bad.axis_v = Vec3(1, 0, 0);
  EXPECT_THAT(error_message([&] { cylinder_segment(1.0, 1.0, kPi, 2, 1, bad); }), HasSubstr("orthonormal"));
}

}  // namespace
}  // namespace shellfrac::nurbs
