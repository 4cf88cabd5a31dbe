// Smoothing of the damage-time crack (brittle/crack_smoothing.*): a crack planted as a tilted plane comes
// out near that plane instead of as a staircase of grid-cell faces, and the regions stay a partition.
#include "brittle/crack_smoothing.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>

#include "brittle/breakage_order.hpp"
#include "brittle/fracture_event.hpp"
#include "brittle/primitives.hpp"
#include "crack_fixtures.hpp"

namespace shellfrac::brittle {
namespace {

using testing::DamagedBox;

constexpr double kL = 0.05, kS = 0.005, kH = 0.01;
constexpr double kPi = 3.14159265358979323846;

// The plane's normal: at 74.5, 57.7 and 36.7 degrees to the grid axes, so no grid face is near it.
Vec3 plane_normal() { return Vec3(1, 2, 3).normalized(); }

// A 0.1 m block, every particle fully damaged, broken first on the plane n.x = 0 through its centre and
// later the farther it lies from it (tau = 1 ms + 10 ms/m x distance): a V-shaped valley whose bottom,
// the watershed's basin boundary, is that plane.
BrittleSolid tilted_valley() {
  const DamagedBox box(kL, kS, [](const Vec3&) { return true; });
  BrittleSolid s;
  s.rest = box.x;
  s.material.density = 2000;
  for (const Vec3& x : box.x) s.damage.push_back(ParticleDamage{1.0, 1.0, 1e-3 + 1e-2 * std::abs(plane_normal().dot(x))});
  return s;
}

CrackExtractionOptions grid_options() {
  CrackExtractionOptions o;
  o.grid.spacing = kH;
  return o;
}

// How far the crack faces inside the block lie from the plane n.x = 0 and how their normals turn from n:
// over the fan triangles whose centroids lie inside the block, the largest vertex distance and the
// area-weighted RMS distance (in cells), the area-weighted mean angle and the area share within 20 degrees.
struct PlaneFit {
  double max_distance = 0, rms_distance = 0, mean_angle_deg = 0, share_within_20 = 0, area = 0;
};
PlaneFit fit_to_plane(const CrackExtraction& ce) {
  const Vec3 n = plane_normal();
  PlaneFit fit;
  double d2 = 0;
  const TriMesh m = crack_surface_mesh(ce);
  for (const Tri& t : m.triangles) {
    const Vec3 &a = m.positions[t[0]], &b = m.positions[t[1]], &c = m.positions[t[2]];
    if ((((a + b + c) / 3.0).cwiseAbs().array() > kL).any()) continue;
    const Vec3 cross = (b - a).cross(c - a);
    const double area = 0.5 * cross.norm();
    if (!(area > 0)) continue;
    const double angle = std::acos(std::min(1.0, std::abs(cross.normalized().dot(n)))) * 180.0 / kPi;
    for (const Vec3* p : {&a, &b, &c}) fit.max_distance = std::max(fit.max_distance, std::abs(n.dot(*p)) / kH);
    // Mean square distance over the triangle (exact for a linear function): (d_a^2 + d_b^2 + d_c^2 + d_a d_b + d_b d_c + d_c d_a) / 6.
    const double da = n.dot(a) / kH, db = n.dot(b) / kH, dc = n.dot(c) / kH;
    d2 += area * (da * da + db * db + dc * dc + da * db + db * dc + dc * da) / 6.0;
    fit.mean_angle_deg += area * angle;
    if (angle <= 20.0) fit.share_within_20 += area;
    fit.area += area;
  }
  if (fit.area > 0) {
    fit.rms_distance = std::sqrt(d2 / fit.area);
    fit.mean_angle_deg /= fit.area;
    fit.share_within_20 /= fit.area;
  }
  return fit;
}

// The staircase of the unsmoothed diagram misses the plane by up to a cell, with every face on a grid
// plane (49 degrees from n on average); smoothed, the sheet lies near the plane and turns with it, and
// the cells still tile the container. The thresholds are regression checks set above the measured values
// (below); the staircase fails every one of them.
TEST(CrackSmoothing, TiltedPlaneComesOutNearThePlane) {
  const BrittleSolid s = tilted_valley();
  CrackExtraction stairs = damage_time_crack(s.rest, s.damage, grid_options(), 0.1);
  ASSERT_EQ(find_regions(stairs.diagram, stairs.crack_face).count, 2);
  CrackExtraction smooth = stairs;
  const CrackSmoothingReport rep = smooth_crack_faces(smooth.diagram, smooth.crack_face, kH);
  const PlaneFit before = fit_to_plane(stairs), after = fit_to_plane(smooth);
  for (const auto& [name, f] : {std::pair{"staircase", before}, std::pair{"smoothed", after}})
    std::printf("MEASURE tilted plane, %s: max distance %.3f h, rms %.3f h, mean normal angle %.1f deg, area within 20 deg %.3f, "
                "area %.5f m^2\n", name, f.max_distance, f.rms_distance, f.mean_angle_deg, f.share_within_20, f.area);
  std::printf("MEASURE smoothing: %zu sheet corners, %zu curve, %zu fixed, %zu moves undone, max displacement %.3f h\n",
              rep.sheet_corners, rep.curve_corners, rep.fixed_corners, rep.rejected_moves, rep.max_displacement / kH);
  // Measured: staircase 1.07 h / 0.307 h / 49.0 deg / 0.012 / area 0.01892 m^2; smoothed 0.61 h / 0.157 h /
  // 10.6 deg / 0.908 / 0.01200 m^2 (the section: 0.01247).
  EXPECT_LT(after.max_distance, 0.75);
  EXPECT_LT(after.rms_distance, 0.2);
  EXPECT_LT(after.mean_angle_deg, 20.0);
  EXPECT_GT(after.share_within_20, 0.7);
  // The section of the block by the plane: its projection along z is the whole 0.1 m square (|x + 2y| / 3
  // <= 0.05 there), so its area is 0.01 m^2 / n_z = 0.01 sqrt(14) / 3. Counting triangles by their
  // centroids clips the sheet to the block to within half a triangle: 5 %. Staircase: +52 %.
  const double section = 0.01 * std::sqrt(14.0) / 3.0;
  EXPECT_NEAR(after.area / section, 1.0, 0.05);
  EXPECT_GT(before.area / section, 1.05);
  EXPECT_FALSE(before.max_distance < 0.75 || before.rms_distance < 0.2 || before.mean_angle_deg < 20.0 || before.share_within_20 > 0.7);
  EXPECT_EQ(folded_tetrahedra(smooth.diagram, rep.reference), 0u);  // every cell star-shaped around its moved site
  // The cells still fill the container box exactly (their volumes from the moved faces).
  double cells = 0;
  for (double v : smooth.diagram.cell_volume) cells += v;
  const double box = (smooth.diagram.box_hi - smooth.diagram.box_lo).prod();
  EXPECT_NEAR(cells / box, 1.0, 1e-12);
}

// Through fracture_event (smoothing on by default with breakage_order): two closed fragments. The plane
// through the block's centre halves it (point symmetry), so each piece holds half the volume up to the
// sheet's offset: |V_piece - V/2| <= area x rms distance (Cauchy-Schwarz) <= 0.0125 m^2 x 0.2 h = 2.5 % of V.
// The exact cutter keeps the volume to round-off (1e-9); the level-set cutter within its 2 % bound.
TEST(CrackSmoothing, TiltedPlaneFragmentsKeepTheVolumeWithBothCutters) {
  const BrittleSolid s = tilted_valley();
  TriMesh block = box_mesh(Vec3::Zero(), Vec3::Constant(kL), 2);
  block.name = "block";
  for (Cutter cutter : {Cutter::Exact, Cutter::LevelSet}) {
    FractureEventOptions o;
    o.crack = grid_options();
    o.breakage.enabled = true;
    o.fragments.cutter = cutter;
    const FractureEvent ev = fracture_event(s, block, o, "block.obj");
    std::printf("MEASURE tilted plane, %s cutter: %zu fragments, shares %.4f / %.4f, volume change %.3g\n", to_string(cutter),
                ev.fragments.fragments.size(), ev.fragments.fragments.front().properties.volume / ev.fragments.input_volume,
                ev.fragments.fragments.back().properties.volume / ev.fragments.input_volume, ev.fragments.volume_change());
    ASSERT_EQ(ev.fragments.fragments.size(), 2u) << to_string(cutter);
    for (const Fragment& f : ev.fragments.fragments) {
      EXPECT_NEAR(f.properties.volume / ev.fragments.input_volume, 0.5, 0.025 + (cutter == Cutter::Exact ? 0.0 : 0.02)) << f.mesh.name;
      EXPECT_TRUE(inspect_mesh(f.mesh).closed()) << f.mesh.name;
    }
    if (cutter == Cutter::Exact) EXPECT_LT(std::abs(ev.fragments.volume_change()), 1e-9);
    else EXPECT_LT(std::abs(ev.fragments.volume_change()), 0.02);
  }
}

}  // namespace
}  // namespace shellfrac::brittle
