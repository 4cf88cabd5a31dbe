// ShellPatch::deformation_gradients (F^KL = g_i (x) Gbar^i, thesis Eq. 4.4-4.5) against maps whose F is
// known exactly.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "nurbs/patch_builders.hpp"
#include "shell_test_helpers.hpp"

namespace shellfrac::shell {
namespace {

double max_deviation(const std::vector<Mat3>& F, const Mat3& expected) {
  double worst = 0;
  for (const Mat3& f : F) worst = std::max(worst, (f - expected).cwiseAbs().maxCoeff());
  return worst;
}

TEST(DeformationGradient, IdentityAtRest) {
  ShellPatch p(nurbs::flat_patch(1.0, 0.5, 4, 2), test::material(1e5, 0.3, 0.01));
  const std::vector<Mat3> F = p.deformation_gradients();
  ASSERT_EQ(F.size(), p.num_quadrature_points());
  EXPECT_LT(max_deviation(F, Mat3::Identity()), 1e-13);
}

TEST(DeformationGradient, InPlaneAffineMapOfAFlatSheetOnEveryLayer) {
  // x = A X with A mapping the sheet's plane (z = 0) onto itself and keeping the normal: the control
  // points reproduce the linear map exactly, so F^KL = A at every point and layer (flat: a_3,alpha = 0).
  ShellPatch p(nurbs::flat_patch(1.0, 0.5, 4, 2), test::material(1e5, 0.3, 0.01));
  Mat3 A;
  A << 1.3, 0.2, 0, -0.1, 0.8, 0, 0, 0, 1;
  for (Vec3& x : p.x) x = A * x;
  EXPECT_LT(max_deviation(p.deformation_gradients(), A), 1e-12);
}

TEST(DeformationGradient, RigidRotationOfACurvedShellThroughTheThickness) {
  // A cylinder segment turned rigidly: g_i = R Gbar_i on every layer, curvature terms included, so F = R.
  ShellPatch p(nurbs::cylinder_segment(0.5, 1.0, 1.5, 6, 3), test::material(1e5, 0.3, 0.02));
  const Mat3 R = Eigen::AngleAxisd(0.7, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();
  for (Vec3& x : p.x) x = R * x + Vec3(0.3, -1, 2);
  EXPECT_LT(max_deviation(p.deformation_gradients(), R), 1e-12);
}

TEST(DeformationGradient, UniformStretchOfACylinderSegmentAlongItsAxis) {
  // Stretching along the axis (axis_v = y) by s: the axial tangent scales by s, the circumferential one
  // and the normal do not, so F = I + (s - 1) e_y e_y^T on every layer.
  ShellPatch p(nurbs::cylinder_segment(0.5, 1.0, 1.5, 6, 3), test::material(1e5, 0.3, 0.02));
  const double s = 1.25;
  for (Vec3& x : p.x) x.y() *= s;
  Mat3 expected = Mat3::Identity();
  expected(1, 1) = s;
  EXPECT_LT(max_deviation(p.deformation_gradients(), expected), 1e-12);
}

}  // namespace
}  // namespace shellfrac::shell
