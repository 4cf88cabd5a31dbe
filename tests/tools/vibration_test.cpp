// The transfer's numerical damping: free vibration of a simply supported plate against
// Kirchhoff plate theory, a swinging sheet against the pin reaction and its own amplitude, a
// free-floating bent sheet against energy conservation, and breakable shells against intact ones.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scene/build.hpp"
#include "scene/scene_error.hpp"
#include "sim/simulation.hpp"
#include "tools/vibration.hpp"

namespace shellfrac::tools {
namespace {

TEST(Vibration, DecayOfASampledDampedCosineIsMeasured) {
  // w = exp(-zeta omega t) cos(omega_d t): the log decrement gives zeta back, the extrema omega_d.
  VibrationResult r;
  const double omega = 2 * 3.14159265358979323846, zeta = 0.05, omega_d = omega * std::sqrt(1 - zeta * zeta);
  for (int k = 0; k <= 6000; ++k) {
    const double t = k * 1e-3;
    r.time.push_back(t);
    r.deflection.push_back(std::exp(-zeta * omega * t) * std::sin(omega_d * t));
  }
  measure_decay(r, 5);
  EXPECT_EQ(r.extrema, 11);
  EXPECT_NEAR(r.damping_ratio, zeta, 1e-4);  // parabolic extremum fit at 1000 samples per period
  EXPECT_NEAR(r.period, 2 * 3.14159265358979323846 / omega_d, 1e-5);
}

TEST(Vibration, AffineFlipConservesLinearMomentumInFreeFlight) {
  // The FLIP part of g2p sums to zero over all particles (tools/vibration.hpp, docs/shell-model.md):
  // a stretched, bent, spinning sheet keeps its momentum to round-off, as under PIC.
  sim::Simulation sim(scene::build_model(R"({"name": "t", "gravity": [0, 0, 0], "grid": {"transfer": "aflip"},
    "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [0.5, 0.4], "cells": [10, 8]},
                "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}}]})", "t.json"));
  const auto x = sim.positions(0), v = sim.velocities(0);
  for (size_t k = 0; k < x.size(); ++k) {
    x[k] = Eigen::Vector3d(1.1 * x[k].x(), 0.95 * x[k].y(), 0.05 * std::sin(6 * x[k].x()));
    v[k] = Eigen::Vector3d(0.3, -0.2, 0.1) + Eigen::Vector3d(0, 0, 2.0).cross(x[k]);
  }
  const Eigen::Vector3d before = sim.linear_momentum();
  for (int s = 0; s < 60; ++s) sim.step(0.5 * sim.stable_dt());
  const double mass = 200 * 0.001 * 0.5 * 0.4;
  EXPECT_GT(before.norm(), 1e-3);
  EXPECT_LE((sim.linear_momentum() - before).norm(), 1e-12 * mass);
}

TEST(Vibration, FlipRatioWithoutAFlipTransferIsRefused) {
  // PIC itself: a FLIP share means nothing to it, so the key is refused there.
  try {
    scene::build_model(R"({"grid": {"transfer": "pic", "flip_ratio": 0.5},
      "shells": [{"patch": {"type": "flat", "size": [1, 1], "cells": [2, 2]}, "thickness": 0.01,
                  "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})", "bad.json");
    FAIL() << "accepted";
  } catch (const scene::SceneError& e) {
    EXPECT_EQ(e.json_path(), "/grid/flip_ratio");
  }
}

// The simply supported plate at a/t = 100, 16 x 16 cells, under the default transfer (no grid.transfer key).
PlateVibrationCase thin_plate_under_the_default() {
  PlateVibrationCase c;
  c.thickness = c.side / 100;
  c.cells = 16;
  c.transfer.transfer = "default";
  return c;
}

TEST(Vibration, SimplySupportedPlateKeepsItsFirstMode) {
  // a/t = 100, 16 x 16 cells, cfl 1, the default transfer (no grid.transfer key: the adaptive transfer,
  // under which the intact elastic plate runs affine-FLIP with share 1): it must keep zeta <= 0.02 over
  // 5 periods and the period within 2% of 2 pi / omega_11. The period error left is the spatial
  // discretisation's (docs/shell-model.md).
  PlateVibrationCase c = thin_plate_under_the_default();
  const VibrationResult v = simply_supported_plate(c);
  std::printf("default (adaptive): zeta = %.5f, period / reference = %.5f, %d extrema, %ld steps\n", v.damping_ratio,
              v.period / v.reference_period, v.extrema, v.steps);
  EXPECT_EQ(v.extrema, 11);  // 5 whole periods measured
  EXPECT_LE(v.damping_ratio, 0.02);
  // Within 2%. Measured +1.60% with the adaptive transfer's shear mass share of 0.2
  // (scene::model::kAdaptiveShearMassShare); with the default share of 0.5 it was +3.15%.
  EXPECT_NEAR(v.period, v.reference_period, 0.02 * v.reference_period);
  // PIC (the thesis's transfer) beside it, over one reference period: the thin plate does not swing back.
  c.transfer.transfer = "pic";
  c.periods = 1;
  const VibrationResult pic = simply_supported_plate(c);
  std::printf("pic: zeta = %.5f (1 = over-damped, no oscillation), %d extrema\n", pic.damping_ratio, pic.extrema);
  EXPECT_GT(pic.damping_ratio, 0.5);  // far from the new transfer's: the reason for it
}

TEST(Vibration, BreakablePlateVibratesLikeTheIntactOne) {
  // The a/t = 100 plate of SimplySupportedPlateKeepsItsFirstMode with a fracture material it never
  // reaches (failure stress 0.1 E): it can crack, and under the default it runs the adaptive transfer
  // like the intact plate until damage appears, which it never does. It must keep zeta <= 0.02 and
  // the period within 2% of the intact plate's. The thesis's PIC (cracking_shells "pic", the
  // default until this change) over-damps it: no oscillation.
  PlateVibrationCase c = thin_plate_under_the_default();
  const VibrationResult intact = simply_supported_plate(c);
  c.breakable = true;
  const VibrationResult breakable = simply_supported_plate(c);
  std::printf("breakable plate: zeta = %.5f, period / intact period = %.5f; intact zeta = %.5f\n",
              breakable.damping_ratio, breakable.period / intact.period, intact.damping_ratio);
  EXPECT_EQ(breakable.extrema, 11);
  EXPECT_LE(breakable.damping_ratio, 0.02);
  EXPECT_NEAR(breakable.period, intact.period, 0.02 * intact.period);
  c.transfer.cracking_shells = "pic";
  c.periods = 1;
  const VibrationResult pic = simply_supported_plate(c);
  std::printf("breakable plate, cracking_shells pic: zeta = %.5f (1 = over-damped)\n", pic.damping_ratio);
  EXPECT_GT(pic.damping_ratio, 0.5);
}

TEST(Vibration, SimplySupportedPlatePeriodConvergesAt32Cells) {
  // The same plate at 32 x 32 cells over 2 periods: the period within 2% of 2 pi / omega_11
  // (measured +0.07%, zeta 5e-5).
  PlateVibrationCase c;
  c.thickness = c.side / 100;
  c.cells = 32;
  c.periods = 2;
  c.transfer.transfer = "adaptive";
  const VibrationResult v = simply_supported_plate(c);
  std::printf("adaptive, 32 cells: zeta = %.5f, period / reference = %.5f, %d extrema\n", v.damping_ratio,
              v.period / v.reference_period, v.extrema);
  EXPECT_GE(v.extrema, 4);
  EXPECT_LE(v.damping_ratio, 0.02);
  EXPECT_NEAR(v.period, v.reference_period, 0.02 * v.reference_period);
}

TEST(Vibration, FreeFloatingBentSheetKeepsItsEnergy) {
  // No gravity, no pins: kinetic + elastic energy must stay constant, to 2% over 2 s. The
  // adaptive transfer runs the intact sheet as pure affine-FLIP (share 1); at 32 x 8 cells the
  // drift was 0.75% with "aflip" share 1. The drift is the lumped kinetic energy's discretisation error,
  // not a loss (16 x 4 cells: 2.9%, oscillating, back to +2.4% after 2 s); any PIC share loses energy
  // steadily (flip_ratio 0.99 at 16 x 4: half of it in 2 s).
  FreeSheetCase c;
  c.cells_u = 32;
  c.cells_v = 8;
  c.transfer.transfer = "adaptive";
  const EnergyHistory h = free_bent_sheet(c);
  // The energy did move between kinetic and elastic (the sheet bent).
  double min_kinetic = h.kinetic[0];
  for (double k : h.kinetic) min_kinetic = std::min(min_kinetic, k);
  EXPECT_LT(min_kinetic, 0.2 * h.kinetic[0]);
  std::printf("adaptive: energy drift %.5f over %.1f s (%ld steps)\n", h.max_relative_drift(), c.end, h.steps);
  EXPECT_LE(h.max_relative_drift(), 0.02);
  // PIC over the first second: most of the energy is gone.
  c.transfer = {"pic", -1, ""};
  c.end = 1.0;
  const EnergyHistory pic = free_bent_sheet(c, 50);
  const double left = pic.total(pic.time.size() - 1) / pic.total(0);
  std::printf("pic: energy left after %.1f s: %.4f of the start\n", c.end, left);
  EXPECT_LT(left, 0.5);
}

TEST(Vibration, PendulumSheetKeepsSwingingAndObeysThePinReaction) {
  // A 0.1 m x 0.2 m plate (L/t = 10, bending stiffness D / L about 3x its weight moment) hinged at its top
  // edge (first control-point row pinned, slopes free) and let go at rest 30 degrees from the vertical
  // under gravity -z; the patch is built in that position, so it starts unstrained. Linear momentum
  // changes only by the pin reaction and the weight of the free particles: dp = dt (R + M_free g) in
  // every step (a discrete identity of the transfers, to round-off). After 3 swings (periods) the
  // amplitude is at least 90% of the start, with the adaptive transfer.
  const double L = 0.2, g = 9.81;
  sim::Simulation sim(scene::build_model(R"({"name": "pendulum", "gravity": [0, 0, -9.81], "time": {"cfl": 1.0},
    "grid": {"transfer": "adaptive"},
    "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [0.1, 0.2], "cells": [4, 8],
                "origin": [0, 0, 0], "axis_u": [1, 0, 0], "axis_v": [0, 0.5, -0.8660254037844386]},
                "thickness": 0.02, "material": {"E": 4e6, "nu": 0.3, "density": 500}}],
    "pins": [{"shell": "sheet", "control_points": [[0,0],[1,0],[2,0],[3,0],[4,0],[5,0]]}]})",
                                         "pendulum.json"));
  const auto& world = sim.world();
  double free_mass = 0;
  for (double m : world.transfer_mass(0)) free_mass += m;
  for (double m : world.shell(0).shear.mass) free_mass += m;
  Eigen::Vector3d p = sim.linear_momentum();
  double worst = 0, scale = 0;
  std::vector<double> tip;
  const double start = world.shell(0).current_surface().point(0.5, 1.0).y();
  const double dt = sim.stable_dt();
  const double end = 3.4 * 2 * 3.14159265358979323846 * std::sqrt(2 * L / (3 * g));  // rigid-plate periods
  while (sim.time() < end) {
    sim.step(dt);
    const Eigen::Vector3d p_new = sim.linear_momentum();
    const Eigen::Vector3d expected = dt * (sim.pin_reaction(0) + free_mass * Eigen::Vector3d(0, 0, -g));
    worst = std::max(worst, (p_new - p - expected).norm());
    scale = std::max(scale, expected.norm());
    p = p_new;
    tip.push_back(world.shell(0).current_surface().point(0.5, 1.0).y());
  }
  std::printf("momentum residual %.3e of the largest step change %.3e\n", worst, scale);
  EXPECT_LE(worst, 1e-10 * scale);
  // Swing amplitudes: extrema of the free edge's horizontal position; the 6th is the end of swing 3.
  std::vector<double> amplitude;
  for (size_t k = 1; k + 1 < tip.size(); ++k)
    if ((tip[k] > tip[k - 1] && tip[k] >= tip[k + 1]) || (tip[k] < tip[k - 1] && tip[k] <= tip[k + 1]))
      amplitude.push_back(std::abs(tip[k]));
  ASSERT_GE(amplitude.size(), 6u);
  std::printf("tip amplitude: start %.5f, after 3 swings %.5f (ratio %.4f)\n", start, amplitude[5], amplitude[5] / start);
  EXPECT_GE(amplitude[5], 0.9 * start);
}

// A stiff board, 0.5 x 0.25 m, 10 mm thick (E = 2 GPa, rho = 1000, 10 x 5 cells), hinged along its edge u0
// (one control-point row pinned, slope free) and let go horizontally under gravity: it swings down through
// the vertical and up the other side. Samples the free edge's midpoint every `sample` seconds up to `end`.
struct BoardSwing {
  std::vector<Eigen::Vector3d> tip;
  bool turned = false;
};

BoardSwing hinged_board(const std::string& material_extra, const std::string& grid, double end, double sample,
                        const std::string& shell_extra = "", double probe_u = 1.0) {
  sim::Simulation sim(scene::build_model(R"({"name": "board", "gravity": [0, -9.81, 0], "time": {"cfl": 1.0},
    "grid": {)" + grid + R"(},
    "shells": [{"name": "board", "patch": {"type": "flat", "size": [0.5, 0.25], "cells": [10, 5],
                "origin": [0, 0, 0], "axis_u": [1, 0, 0], "axis_v": [0, 0, 1]},
                "thickness": 0.01, "material": {"E": 2e9, "nu": 0.3, "density": 1000)" + material_extra + R"(})" +
                                         shell_extra + R"(}],
    "pins": [{"shell": "board", "edges": ["u0"]}]})",
                                         "board.json"));
  BoardSwing r;
  for (double t = sample; t <= end + 1e-12; t += sample) {
    sim.advance_to(t);
    r.tip.push_back(sim.world().shell(0).current_surface().point(probe_u, 0.5));
  }
  r.turned = sim.transfer_turned(0);
  return r;
}

// The board's angle from the downward vertical at each turning point of the swing (tip height maxima),
// hinge at the origin: pi / 2 at the start.
std::vector<double> turning_angles(const BoardSwing& b) {
  std::vector<double> angle;
  for (size_t k = 1; k + 1 < b.tip.size(); ++k)
    if (b.tip[k].y() > b.tip[k - 1].y() && b.tip[k].y() >= b.tip[k + 1].y())
      angle.push_back(std::atan2(std::hypot(b.tip[k].x(), b.tip[k].z() - 0.125), -b.tip[k].y()));
  return angle;
}

TEST(Vibration, BreakableBoardSwingsLikeTheIntactOne) {
  // With a fracture material that never triggers (sigma_f = 1 GPa; the bending stress at the
  // hinge stays near 2 MPa) the board must swing as the intact one does: after three half swings (the
  // third turning point) at least 99% of its starting angle, and its free edge within 1 mm of the intact
  // board's at every sample. Under PIC for shells that can crack (cracking_shells "pic", the default
  // before) it sank 8 cm in 2.5 s and never swung through.
  const double end = 2.5, sample = 1e-3;
  const BoardSwing intact = hinged_board("", "", end, sample);
  const BoardSwing breakable =
      hinged_board(R"(, "fracture": {"failure_stress": 1e9, "fracture_energy": 1e9})", "", end, sample);
  const std::vector<double> a_intact = turning_angles(intact), a_breakable = turning_angles(breakable);
  ASSERT_GE(a_intact.size(), 3u);
  ASSERT_GE(a_breakable.size(), 3u);
  const double start = std::acos(0.0);
  double worst = 0;
  for (size_t k = 0; k < intact.tip.size(); ++k) worst = std::max(worst, (intact.tip[k] - breakable.tip[k]).norm());
  std::printf("board: third turning point at %.5f (intact) and %.5f (breakable) of the start; free edge at most "
              "%.3g m from the intact board's\n",
              a_intact[2] / start, a_breakable[2] / start, worst);
  EXPECT_FALSE(breakable.turned);
  EXPECT_GE(a_intact[2], 0.99 * start);
  EXPECT_GE(a_breakable[2], 0.99 * start);
  EXPECT_LE(worst, 1e-3);
  // PIC for the breakable board: it does not swing up the other side (its first turning point, if any,
  // stays far below the start).
  const BoardSwing pic = hinged_board(R"(, "fracture": {"failure_stress": 1e9, "fracture_energy": 1e9})",
                                      R"("cracking_shells": "pic")", end, sample);
  const std::vector<double> a_pic = turning_angles(pic);
  std::printf("board under PIC: %zu turning points, first at %.4f of the start\n", a_pic.size(),
              a_pic.empty() ? 0.0 : a_pic[0] / start);
  EXPECT_TRUE(a_pic.empty() || a_pic[0] < 0.9 * start);
}

// The cut shell is never damaged, so it runs the adaptive shares: affine-FLIP on its intact support, APIC
// on the control points beside the cut (the MLS supports reach u = 0.35 on this 10-cell board, half of
// the hinged part), and RPIC on its shear particles. While the shear particles ran PIC (they carried no
// affine velocity at all) this board sank at about 0.1 m/s and never turned, as under PIC.
TEST(Vibration, TornBoardSwingsOn) {
  // Torn pieces must keep their swing. The same board, cut through across its width at u = 0.6
  // (a torn board whose outer 0.2 m has come off), swings on its hinge as a 0.3 m board. Probed at
  // u = 0.4, whose NURBS support lies on the hinged side. By default (cracking_shells
  // "pic_where_damaged") the cut shell, never damaged, runs the adaptive transfer: after three half swings
  // it should reach at least 99% of its starting angle, the criterion for the breakable board above.
  // Turned to PIC for good at its first crack ("adaptive_then_pic") it does not swing through.
  const double end = 2.5, sample = 1e-3;
  const std::string material = R"(, "fracture": {"failure_stress": 1e9, "fracture_energy": 1e9})";
  const std::string cut = R"(, "cuts": [{"points": [[0.6, 0.0], [0.6, 1.0]]}])";
  const BoardSwing torn = hinged_board(material, "", end, sample, cut, 0.4);
  const BoardSwing turned = hinged_board(material, R"("cracking_shells": "adaptive_then_pic")", end, sample, cut, 0.4);
  const std::vector<double> a = turning_angles(torn), a_turned = turning_angles(turned);
  const double start = std::acos(0.0);
  std::printf("torn board: %zu turning points, third at %.5f of the start; adaptive_then_pic: %zu, first at %.4f\n",
              a.size(), a.size() >= 3 ? a[2] / start : 0.0, a_turned.size(), a_turned.empty() ? 0.0 : a_turned[0] / start);
  EXPECT_FALSE(torn.turned);
  ASSERT_GE(a.size(), 3u);
  EXPECT_GE(a[2], 0.99 * start);
  EXPECT_TRUE(a_turned.empty() || a_turned[0] < 0.9 * start);
}

}  // namespace
}  // namespace shellfrac::tools
