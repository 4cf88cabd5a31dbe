// Seam metrics of patch interfaces and the coupling verification scenes (thesis Fig. 4.24):
// the metrics against states with a known gap, kink and stress, and scaled-down drapes of a cloth in
// two non-conforming patches (20 vs 25 cells along the seam) over a sphere.
#include <gtest/gtest.h>

#include <cmath>
#include <algorithm>
#include <cstdio>
#include <string>
#include <tuple>
#include <vector>

#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"
#include "output/seam_metrics.hpp"
#include "output/verification.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::output {
using sim::Simulation;
namespace {

constexpr double kPi = 3.14159265358979323846;

// Two flat patches meeting along x = 0 (the line y = 0.3 running along z). `right_axis_v` [0, 0, 1]
// runs the right patch's seam against the left's (reversed) and flips its normal.
std::string seam_scene(const std::string& interface_fields, const std::string& right_axis_v = "[0, 0, -1]",
                       const std::string& extra = "") {
  const std::string right_origin = right_axis_v == "[0, 0, 1]" ? "[0.0, 0.3, -0.5]" : "[0.0, 0.3, 0.5]";
  return R"({"name": "seam",
    "shells": [
      {"name": "left", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [4, 8],
        "origin": [-0.5, 0.3, 0.5], "axis_u": [1, 0, 0], "axis_v": [0, 0, -1]},
       "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}},
      {"name": "right", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [5, 10],
        "origin": )" + right_origin + R"(, "axis_u": [1, 0, 0], "axis_v": )" + right_axis_v + R"(},
       "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}}],
    "interfaces": [{"a": {"shell": "left", "side": "u1"}, "b": {"shell": "right", "side": "u0"}, )" +
         interface_fields + "}]" + extra + "}";
}

// Rotates every control point of patch i by `degrees` about the seam line (x = 0, y = 0.3, along z).
void fold_about_seam(Simulation& sim, size_t i, double degrees) {
  const double a = degrees * kPi / 180.0;
  for (auto& x : sim.positions(i)) {
    const double dx = x.x(), dy = x.y() - 0.3;
    x = {std::cos(a) * dx - std::sin(a) * dy, 0.3 + std::sin(a) * dx + std::cos(a) * dy, x.z()};
  }
}

TEST(SeamMetrics, KnownKinkAngleAndShift) {
  for (const char* axis : {"[0, 0, -1]", "[0, 0, 1]"}) {  // same and reversed seam direction
    const bool reversed = std::string(axis) == "[0, 0, 1]";
    const scene::Model scene = scene::build_model(
        seam_scene(std::string(R"("continuity": "none", "reversed": )") + (reversed ? "true" : "false"), axis),
        "seam.json");
    ASSERT_EQ(scene.interfaces.size(), 0u);  // "none" is measured, never coupled
    ASSERT_EQ(scene.uncoupled_seams.size(), 1u);
    Simulation sim(scene);
    SeamMeasurement rest = output::measure_seams(scene, sim.world()).at(0);
    EXPECT_LE(rest.gap, 1e-15) << axis;
    EXPECT_LE(rest.angle_degrees, 1e-9) << axis;  // the reversed patch's opposite normal is flipped
    EXPECT_FALSE(rest.stress_ratio.has_value());   // no stress at rest
    // The right patch folded by 30 degrees about the seam: the edges still meet, the normals differ by 30.
    fold_about_seam(sim, 1, 30.0);
    const SeamMeasurement kinked = output::measure_seams(scene, sim.world()).at(0);
    EXPECT_LE(kinked.gap, 1e-15) << axis;
    EXPECT_NEAR(kinked.angle_degrees, 30.0, 1e-6) << axis;
    // Folded back and shifted by t = (0, 1, 2) mm: the gap is |t| everywhere, the normals agree.
    fold_about_seam(sim, 1, -30.0);
    for (auto& x : sim.positions(1)) x += Eigen::Vector3d(0, 0.001, 0.002);
    const SeamMeasurement shifted = output::measure_seams(scene, sim.world()).at(0);
    EXPECT_NEAR(shifted.gap, std::sqrt(5.0) * 1e-3, 1e-12) << axis;
    EXPECT_LE(shifted.angle_degrees, 1e-9) << axis;
  }
}

// Stretches patch i by the factor s along x, affinely about x = 0: a uniform in-plane stress.
void stretch_x(Simulation& sim, size_t i, double s) {
  for (auto& x : sim.positions(i)) x.x() *= s;
}

TEST(SeamMetrics, StressRatioOfUniformStressIsOneAndPinsAreExcluded) {
  // The right patch pinned along its far edge (u = 1); the left stays at rest (no stress: skipped).
  const std::string pins = R"(, "pins": [{"shell": "right", "region": {"u": [0.95, 1.0]}}])";
  const scene::Model scene = scene::build_model(seam_scene(R"("continuity": "none")", "[0, 0, -1]", pins), "seam.json");
  Simulation sim(scene);
  stretch_x(sim, 1, 1.01);
  const SeamMeasurement uniform = output::measure_seams(scene, sim.world()).at(0);
  ASSERT_TRUE(uniform.stress_ratio.has_value());
  EXPECT_NEAR(*uniform.stress_ratio, 1.0, 1e-9);
  // A pinned control point (u = 1) dragged 1 cm along the seam spikes the stress of the last cell. With
  // 5 cells across, the seam band (cells 0-1, u <= 0.4) and the pin's exclusion (cells within two cells
  // of u = 1: cells 3-4, u >= 0.6) do not overlap, and the excluded cells leave the median too: ratio 1.
  const auto& ref = sim.world().shell(1).reference();
  const auto pinned_point = static_cast<size_t>(ref.flat_index(ref.num_u() - 1, 5));
  const auto seam_neighbour = static_cast<size_t>(ref.flat_index(1, 5));
  sim.positions(1)[pinned_point].z() += 0.01;
  const SeamMeasurement pinned = output::measure_seams(scene, sim.world()).at(0);
  ASSERT_TRUE(pinned.stress_ratio.has_value());
  EXPECT_NEAR(*pinned.stress_ratio, 1.0, 1e-9);
  // The same displacement one row from the seam, where no pin excuses it, raises the ratio.
  sim.positions(1)[pinned_point].z() -= 0.01;
  sim.positions(1)[seam_neighbour].z() += 0.01;
  const SeamMeasurement spiked = output::measure_seams(scene, sim.world()).at(0);
  ASSERT_TRUE(spiked.stress_ratio.has_value());
  EXPECT_GT(*spiked.stress_ratio, 2.0);
  // Independent check of that ratio from the points' parameters: the largest stress at u <= 0.4 over
  // the median at u < 0.6.
  const std::vector<double> s = sim.world().shell(1).mid_surface_stress();
  std::vector<double> kept;
  double band = 0;
  for (size_t q = 0; q < s.size(); ++q) {
    const double u = sim.world().shell(1).parameter(q).x();
    if (u <= 0.4) band = std::max(band, s[q]);
    if (u < 0.6) kept.push_back(s[q]);
  }
  std::nth_element(kept.begin(), kept.begin() + static_cast<long>(kept.size() / 2), kept.end());
  const double expected = band / kept[kept.size() / 2];
  EXPECT_NEAR(*spiked.stress_ratio, expected, 1e-12 * expected);
  std::printf("stress ratio with a displaced control point next to the seam: %.4g\n", expected);
}

TEST(SeamMetrics, DefaultThresholdsAndVerifyParsing) {
  const scene::Model c1 = scene::build_model(seam_scene(R"("continuity": "C1", "tolerance": 1e-6)"), "seam.json");
  // Reference control nets span 1 m x 1 m at y = 0.3: model size sqrt(2).
  EXPECT_NEAR(model_size(c1), std::sqrt(2.0), 1e-15);
  SeamThresholds t = seam_thresholds(c1, c1.interfaces.at(0));
  EXPECT_NEAR(*t.max_gap, 1e-9 * std::sqrt(2.0), 1e-24);
  EXPECT_EQ(*t.max_angle_degrees, 0.5);
  // Checked by default, with a limit above every shipped coupled scene (docs/coupling.md).
  EXPECT_EQ(*t.max_stress_ratio, kDefaultMaxStressRatio);
  const scene::Model c0 = scene::build_model(
      seam_scene(R"("continuity": "C0", "verify": {"max_gap": 0.001, "max_angle_degrees": 5, "max_stress_ratio": 2})"),
      "seam.json");
  t = seam_thresholds(c0, c0.interfaces.at(0));
  EXPECT_EQ(*t.max_gap, 0.001);
  EXPECT_EQ(*t.max_angle_degrees, 5.0);
  EXPECT_EQ(*t.max_stress_ratio, 2.0);
  const scene::Model off = scene::build_model(seam_scene(R"("continuity": "C1", "verify": {"max_angle_degrees": null})"), "seam.json");
  t = seam_thresholds(off, off.interfaces.at(0));
  EXPECT_FALSE(t.max_angle_degrees.has_value());
  EXPECT_TRUE(t.max_gap.has_value());
  const scene::Model none = scene::build_model(seam_scene(R"("continuity": "none")"), "seam.json");
  t = seam_thresholds(none, none.uncoupled_seams.at(0));
  EXPECT_FALSE(t.max_gap || t.max_angle_degrees || t.max_stress_ratio);

  for (const auto& [fields, path, words] :
       {std::tuple{R"("verify": {"max_gap": -1})", "/interfaces/0/verify/max_gap", "out of range"},
        std::tuple{R"("verify": {"max_angle_degrees": 200})", "/interfaces/0/verify/max_angle_degrees", "[0, 180]"},
        std::tuple{R"("verify": {"max_stress_ratio": "2"})", "/interfaces/0/verify/max_stress_ratio", "expected a number"},
        std::tuple{R"("verify": {"max_gaps": 1})", "/interfaces/0/verify/max_gaps", "allowed here are"},
        std::tuple{R"("continuity": "C2")", "/interfaces/0/continuity", "none"},
        std::tuple{R"("closure": "tight")", "/interfaces/0/closure", "least_squares"},
        std::tuple{R"("continuity": "none", "closure": "exact")", "/interfaces/0/closure", "never closed"},
        std::tuple{R"("seam_velocity": "average")", "/interfaces/0/seam_velocity", "projected"}}) {
    try {
      scene::build_model(seam_scene(fields), "seam.json");
      ADD_FAILURE() << "accepted " << fields;
    } catch (const scene::SceneError& e) {
      EXPECT_EQ(e.json_path(), path) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  }
}

TEST(SeamVerify, ExactClosureRefusesPinnedLeaderRows) {
  // 8 vs 10 cells along the seam (left leads) share one interior knot; the flat rest state lies in that
  // space, so the seam is accepted, unless a pin holds the leader rows the closure must move.
  const scene::Model ok = scene::build_model(seam_scene(R"("closure": "exact")"), "seam.json");
  EXPECT_TRUE(ok.interfaces.at(0).coupling.exact);
  EXPECT_EQ(ok.interfaces.at(0).coupling.shared.E1.cols(), 4);
  EXPECT_EQ(ok.interfaces.at(0).leader_neighbours.size(), 6u * 10u);  // 6 rows of the 6 x 10 leader net
  const std::string follower_pin = R"(, "pins": [{"shell": "right", "region": {"u": [0.0, 0.1]}}])";
  EXPECT_NO_THROW(scene::build_model(seam_scene(R"("closure": "exact")", "[0, 0, -1]", follower_pin), "seam.json"));
  const std::string leader_pin = R"(, "pins": [{"shell": "left", "region": {"u": [0.9, 1.0]}}])";
  try {
    scene::build_model(seam_scene(R"("closure": "exact")", "[0, 0, -1]", leader_pin), "seam.json");
    ADD_FAILURE() << "accepted a pinned leader row";
  } catch (const scene::SceneError& e) {
    EXPECT_EQ(e.json_path(), "/interfaces/0/closure");
    EXPECT_NE(std::string(e.what()).find("the pin at /pins/0 holds one of them"), std::string::npos) << e.what();
  }
}

// ---- Scaled-down drapes (Fig. 4.24): a 1 m cloth dropped onto a ball of radius 0.3 m -----------------

// The drapes run the default grid transfer (no grid.transfer key: "adaptive"), as users do. That
// transfer keeps the swing PIC damped away, so the scene carries grid damping and time.until_rest, and
// the comparisons below are made at rest, not at a fixed moment of a motion.
constexpr double kDrapeDamping = 2.0;  // [1/s]
// At rest (time.until_rest, measured by AdvectedRest below): kinetic energy below 5e-6 J (the 0.12 kg
// the control points carry, at an rms speed of about 9 mm/s) and no control point faster than 3 cm/s,
// both for 0.1 s. The speed allows for a jitter of about 2 cm/s that some control points on the ball
// keep in a settled one-patch drape, whose corners then move by about 1 mm per 0.5 s.
constexpr const char* kDrapeRest = R"({"kinetic_energy": 5e-6, "speed": 0.03, "duration": 0.1})";
// The latest end of a drape that should come to rest.
constexpr double kDrapeEnd = 5.0;

// The cloth as one patch (11 x 20 cells), or as a left half with 20 cells along the seam and a right
// half with `right_cells` (25: non-nested, the two share only every 5th / 4th knot; 40: nested) coupled
// by `interface_fields`.
std::string drape_scene(bool one_patch, const std::string& interface_fields, int right_cells, double end,
                        int right_across, int one_across) {
  const std::string material = R"("thickness": 0.0005, "quadrature": {"points": 3, "layers": 3},
       "material": {"E": 1e5, "nu": 0.3, "density": 300}})";
  std::string shells =
      one_patch ? R"({"name": "cloth", "patch": {"type": "flat", "size": [1.0, 1.0], "cells": [)" + std::to_string(one_across) + R"(, 20],
        "origin": [-0.5, 0.32, 0.5], "axis_u": [1, 0, 0], "axis_v": [0, 0, -1]}, )" + material
                : R"({"name": "left", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [5, 20],
        "origin": [-0.5, 0.32, 0.5], "axis_u": [1, 0, 0], "axis_v": [0, 0, -1]}, )" + material + R"(,
      {"name": "right", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [)" + std::to_string(right_across) + ", " +
                      std::to_string(right_cells) + R"(],
        "origin": [0.0, 0.32, 0.5], "axis_u": [1, 0, 0], "axis_v": [0, 0, -1]}, )" + material;
  std::string s = R"({"name": "drape", "time": {"end": )" + std::to_string(end) + R"(, "cfl": 0.4, "until_rest": )" +
                  kDrapeRest + R"(}, "damping": )" + std::to_string(kDrapeDamping) + R"(,
    "shells": [)" + shells + R"(],
    "colliders": [{"shape": "sphere", "center": [0, 0, 0], "radius": 0.3, "friction": 0.4},
                  {"shape": "half_space", "point": [0, -0.35, 0], "normal": [0, 1, 0], "friction": 0.5}])";
  if (!one_patch)
    s += R"(, "interfaces": [{"a": {"shell": "left", "side": "u1"}, "b": {"shell": "right", "side": "u0"}, )" +
         interface_fields + "}]";
  return s + "}";
}

// Worst seam metrics over the frames (24 per second) of a drape, the seam stress ratio and the cloth's
// four corners at the end (at rest when rest_time >= 0).
struct DrapeRun {
  double gap = 0, angle = 0, ratio = 0;  // maxima over the frames (ratio: frames where it is defined)
  double final_ratio = 0;                // at the last frame
  double model_size = 0;
  double rest_time = -1;                 // when time.until_rest was met; negative: not before the end
  std::vector<Eigen::Vector3d> corners;  // (x-, z+), (x+, z+), (x-, z-), (x+, z-) in the rest layout
};

// The one-patch cloth's stress ratio measured as output::measure_seams measures the two-patch seam, at
// the same line (x = 0 at rest): on each side the largest stress within two cells of the two-patch
// halves (left cells 0.1 m, right cells 0.5 / right_across m) over the median of that half, the larger
// side. What the ball alone does to the cloth there, without any seam.
double one_patch_seam_ratio(const shell::ShellPatch& p, int right_across) {
  const std::vector<double> s = p.mid_surface_stress();
  std::vector<double> half[2];
  double band[2] = {0, 0};
  const double reach[2] = {2 * 0.5 / 5, 2 * 0.5 / right_across};
  for (size_t q = 0; q < s.size(); ++q) {
    const double x = p.reference().point(p.parameter(q).x(), p.parameter(q).y()).x();
    const int side = x < 0 ? 0 : 1;
    half[side].push_back(s[q]);
    if (std::abs(x) <= reach[side]) band[side] = std::max(band[side], s[q]);
  }
  double ratio = 0;
  for (int side = 0; side < 2; ++side) {
    std::vector<double>& h = half[side];
    std::nth_element(h.begin(), h.begin() + static_cast<long>(h.size() / 2), h.end());
    const double median = h[h.size() / 2];
    if (median > 1e-4) ratio = std::max(ratio, band[side] / median);  // 1e-4 Pa = 1e-9 E, as measure_seams
  }
  return ratio;
}

// time.until_rest's test, written out here as an independent check of output::VerificationRecorder: the
// kinetic energy and the largest control-point speed by the velocities the particles move with. Under
// the default transfer a control point's velocity carries a FLIP part that the grid does not see and
// the point does not move with (World::flip_part); counted in, no drape here ever rested (the settled
// one-patch drape: 7-9 cm/s and 9e-5 J with it, 2 cm/s and 2.5e-6 J without).
class AdvectedRest {
 public:
  explicit AdvectedRest(const scene::model::RestCriterion& c) : c_(c) {}
  bool after_step(const Simulation& sim) {
    double kinetic = 0, speed = 0;
    for (size_t i = 0; i < sim.world().num_shells(); ++i) {
      const shell::ShellPatch& p = sim.world().shell(i);
      const std::vector<Eigen::Vector3d>& flip = sim.world().flip_part(i);
      for (size_t k = 0; k < p.v.size(); ++k) {
        const Eigen::Vector3d v = flip.empty() ? p.v[k] : Eigen::Vector3d(p.v[k] - flip[k]);
        kinetic += 0.5 * p.mass[k] * v.squaredNorm();
        speed = std::max(speed, v.norm());
      }
    }
    if (kinetic > c_.kinetic_energy || speed > c_.speed) {
      quiet_since_ = -1;
      return false;
    }
    if (quiet_since_ < 0) quiet_since_ = sim.time();
    return sim.time() - quiet_since_ >= c_.duration;
  }

 private:
  scene::model::RestCriterion c_;
  double quiet_since_ = -1;
};

DrapeRun run_drape(bool one_patch, const std::string& interface_fields = "", int right_cells = 25,
                   double end = kDrapeEnd, int right_across = 6, int one_across = 11) {
  const scene::Model scene =
      scene::build_model(drape_scene(one_patch, interface_fields, right_cells, end, right_across, one_across), "drape.json");
  Simulation sim(scene);
  AdvectedRest rest(*scene.time.until_rest);  // asked after every step
  bool resting = false;
  DrapeRun r;
  r.model_size = model_size(scene);
  const int frames = static_cast<int>(std::lround(scene.time.end * 24));
  for (int f = 1; f <= frames && !resting; ++f) {
    sim.advance_to(f / 24.0, [&] { return resting = rest.after_step(sim); });
    if (one_patch) {
      r.ratio = std::max(r.ratio, r.final_ratio = one_patch_seam_ratio(sim.world().shell(0), right_across));
      continue;
    }
    const SeamMeasurement m = output::measure_seams(scene, sim.world()).at(0);
    r.gap = std::max(r.gap, m.gap);
    r.angle = std::max(r.angle, m.angle_degrees);
    r.ratio = std::max(r.ratio, m.stress_ratio.value_or(0.0));
    r.final_ratio = m.stress_ratio.value_or(0.0);
  }
  if (resting) r.rest_time = sim.time();
  // Corners: u = 0 / 1 of the cloth (left's u = 0, right's u = 1), v = 0 (z = +0.5) and v = 1.
  const auto surface = [&](size_t i) { return sim.world().shell(i).current_surface(); };
  const size_t right = one_patch ? 0 : 1;
  for (double v : {0.0, 1.0}) {
    r.corners.push_back(surface(0).point(0.0, v));
    r.corners.push_back(surface(right).point(1.0, v));
  }
  return r;
}

// The library's rest test (time.until_rest, as `shellfrac run` and `verify` stop on it) and the one
// written out above agree step for step on the settled one-patch drape under the default transfer:
// both see it come to rest, at the same step.
TEST(SeamVerify, UntilRestStopsASettledDrapeUnderTheDefaultTransfer) {
  const scene::Model scene = scene::build_model(drape_scene(true, "", 25, kDrapeEnd, 6, 11), "drape.json");
  Simulation sim(scene);
  output::VerificationRecorder library(sim, ::testing::TempDir());
  AdvectedRest independent(*scene.time.until_rest);
  double library_time = -1, independent_time = -1;
  sim.advance_to(kDrapeEnd, [&] {
    if (library_time < 0 && library.after_step(sim)) library_time = sim.time();
    if (independent_time < 0 && independent.after_step(sim)) independent_time = sim.time();
    return library_time >= 0 && independent_time >= 0;
  });
  EXPECT_GT(library_time, 0.0);
  EXPECT_EQ(library_time, independent_time);
  EXPECT_LT(library_time, kDrapeEnd);
}

// Largest distance between the corners of two drapes [m].
double corner_deviation(const DrapeRun& a, const DrapeRun& b) {
  double worst = 0;
  for (size_t k = 0; k < 4; ++k) worst = std::max(worst, (a.corners[k] - b.corners[k]).norm());
  return worst;
}

TEST(SeamVerify, NestedDrapeSeamClosesToRoundOff) {
  // 20 vs 40 cells: the follower's spline space contains the leader's edge, so Eq. 4.29 is exact. The
  // first 0.75 s: the impact (where the non-nested seam opens most) and the fold. Not a rest comparison:
  // the gap and angle are maxima over every frame.
  const DrapeRun c0 = run_drape(false, R"("continuity": "C0")", 40, 0.75);
  const DrapeRun c1 = run_drape(false, R"("continuity": "C1")", 40, 0.75);
  std::printf("nested drape 20/40: C0 gap %.3g m, angle %.3g deg; C1 gap %.3g m, angle %.3g deg\n", c0.gap, c0.angle,
              c1.gap, c1.angle);
  // The default limits: gap 1e-9 x model size (round-off on nested knots), angle 0.5 degrees for C1.
  EXPECT_LE(c0.gap, 1e-9 * c0.model_size);
  EXPECT_LE(c1.gap, 1e-9 * c1.model_size);
  EXPECT_LE(c1.angle, 0.5);
  EXPECT_GT(c0.angle, 10.0);  // C0 alone lets the seam fold over the ball
}

TEST(SeamVerify, NonNestedLeastSquaresDrapeSeamGapAndKinkAreBounded) {
  // The thesis's least-squares seam (exact closure is the default) on non-nested knots:
  // Eq. 4.29 and 4.34 leave a gap and a kink that the default limits (1e-9 x model size, 0.5 degrees)
  // do not allow. Maxima over every frame, bounded here so that a change of the coupling that moves them
  // is seen (measured 6.6e-4 m, 4.6e-4 x model size, and 3.18 degrees; under PIC 6.0e-4 m and 2.84).
  const DrapeRun c1 = run_drape(false, R"("continuity": "C1", "closure": "least_squares")");
  std::printf("non-nested C1 drape 20/25: max gap %.3g m (%.3g x model size), max angle %.3g deg\n", c1.gap,
              c1.gap / c1.model_size, c1.angle);
  EXPECT_GT(c1.gap, 1e-9 * c1.model_size);
  EXPECT_LE(c1.gap, 1e-3 * c1.model_size);
  EXPECT_LE(c1.angle, 4.0);
}

// Runs the two-patch drape with `interface_fields` and the one-patch drape, prints their rest times and
// the largest corner distance at the end, and checks both came to rest.
double rest_corner_deviation(const char* what, const std::string& interface_fields, int right_cells = 25,
                             int right_across = 6, int one_across = 11) {
  const DrapeRun two = run_drape(false, interface_fields, right_cells, kDrapeEnd, right_across);
  const DrapeRun one = run_drape(true, "", right_cells, kDrapeEnd, right_across, one_across);
  const double worst = corner_deviation(two, one);
  std::printf("%s: rest at %.3g s, one patch at %.3g s (negative: not by %.1f s); corners vs one patch %.3g m "
              "(%.2f%% of the 1 m cloth)\n",
              what, two.rest_time, one.rest_time, kDrapeEnd, worst, 100 * worst);
  EXPECT_GE(two.rest_time, 0.0);
  EXPECT_GE(one.rest_time, 0.0);
  return worst;
}

TEST(SeamVerify, DISABLED_NonNestedLeastSquaresDrapeRestsLikeOnePatch) {
  // Known failure: measured 14.7% (corners 0.147 m from the one-patch drape's; the coupled drape never
  // rests: still creeping at 5 s), criterion 2% of the 1 m cloth at rest. (20.1% before control points
  // touching a collider took the APIC share, 2026-12-06.)
  // Under PIC at a fixed 1.5 s it was 6.8%: the thesis's leader update treats the halves differently
  // (see DISABLED_ProjectedSeamVelocityDrapesLikeOnePatch), and these halves (5 x 20, 6 x 25 cells) have
  // no one-patch equal.
  EXPECT_LE(rest_corner_deviation("non-nested least-squares C1 drape 20/25",
                                  R"("continuity": "C1", "closure": "least_squares")"),
            0.02 * 1.0);
}

TEST(SeamVerify, ExactClosureSealsTheNonNestedDrape) {
  // 20 vs 25 cells share every 5th / 4th knot: 5 spans. With the leader's rows kept in that shared
  // space, Eq. 4.29 and 4.34 reproduce them: the default limits (gap 1e-9 x model size, C1 angle 0.5
  // degrees) hold at every frame of the whole drape.
  const DrapeRun c0 = run_drape(false, R"("continuity": "C0", "closure": "exact")");
  const DrapeRun c1 = run_drape(false, R"("continuity": "C1", "closure": "exact")");
  std::printf("exact closure, drape 20/25: C0 gap %.3g m, angle %.3g deg; C1 gap %.3g m, angle %.3g deg\n", c0.gap,
              c0.angle, c1.gap, c1.angle);
  EXPECT_LE(c0.gap, 1e-9 * c0.model_size);
  EXPECT_LE(c1.gap, 1e-9 * c1.model_size);
  EXPECT_LE(c1.angle, 0.5);
  EXPECT_GT(c0.angle, 10.0);  // C0 alone still folds at the seam
}

TEST(SeamVerify, DISABLED_ExactClosureDrapeRestsLikeOnePatch) {
  // Known failure: measured 10.3% (corners 0.103 m from the one-patch drape's, which rests at 2.1 s; the
  // coupled drape has not rested by 5 s), criterion 2% of the 1 m cloth at rest. Before control points
  // touching a collider took the APIC share (2026-12-06): 18.2%, its corners sliding down the ball at
  // about 2 cm/s at 4 s.
  EXPECT_LE(rest_corner_deviation("exact-closure C1 drape 20/25", R"("continuity": "C1", "closure": "exact")"),
            0.02 * 1.0);
}

// The conforming split of the three tests below: 5 + 5 cells across, 20 along both halves, against one
// patch of 10 x 20 cells. The same knots, so the C1 coupling is exact and any difference is the coupled
// dynamics. The thesis's update (leader rows from the grid, follower rows' grid velocities dropped)
// treats the two halves differently; projecting both halves' rows onto the coupling keeps them mirror
// images.
TEST(SeamVerify, ProjectedSeamVelocityKeepsTheHalvesMirrorImages) {
  const DrapeRun projected = run_drape(false, R"("continuity": "C1", "seam_velocity": "projected")", 20, kDrapeEnd, 5);
  double mirror = 0;
  for (size_t k : {0, 2}) {  // left corner k against the right corner k + 1, mirrored through x = 0
    const Eigen::Vector3d right = projected.corners[k + 1];
    mirror = std::max(mirror, (projected.corners[k] - Eigen::Vector3d(-right.x(), right.y(), right.z())).norm());
  }
  std::printf("conforming drape 10/10 x 20, projected seam velocity: halves mirror each other to %.3g m; seam gap "
              "%.3g m\n",
              mirror, projected.gap);
  EXPECT_LE(mirror, 1e-6);  // the scene is symmetric about x = 0; 1e-6 of the 1 m cloth
  EXPECT_LE(projected.gap, 1e-9 * projected.model_size);
}

TEST(SeamVerify, DISABLED_ProjectedSeamVelocityDrapesLikeOnePatch) {
  // Known failure: measured 6.08% (corners 0.061 m from the one-patch drape's, both at rest: 2.84 s and
  // 1.85 s), criterion 2% of the 1 m cloth at rest; the thesis's leader update rests at 4.15 s, 12.7% off.
  // (3.70% and 10.6% before control points touching a collider took the APIC share, 2026-12-06, when
  // the one-patch drape rested at 2.59 s.) Under PIC at a fixed 1.5 s: 0.61 cm against 6.9 cm.
  const double leader = rest_corner_deviation("conforming drape 10/10 x 20, leader update", R"("continuity": "C1")",
                                              20, 5, 10);
  const double projected = rest_corner_deviation("conforming drape 10/10 x 20, projected",
                                                 R"("continuity": "C1", "seam_velocity": "projected")", 20, 5, 10);
  EXPECT_LE(projected, 0.02 * 1.0);
  EXPECT_GT(leader, 0.04);  // the leader update does not give a one-patch drape
}

TEST(SeamVerify, ProjectedSeamStressMatchesOnePatchAtRest) {
  // The conforming split with the projected update, which comes to rest: its seam stress ratio (largest
  // stress in the two cell rows next to the seam over the patch's median) against the one-patch cloth's
  // at the same line (one_patch_seam_ratio), both at rest. The seam may add at most 20% to what the ball
  // alone does there.
  const DrapeRun projected = run_drape(false, R"("continuity": "C1", "seam_velocity": "projected")", 20, kDrapeEnd, 5);
  const DrapeRun one = run_drape(true, "", 25, kDrapeEnd, 5, 10);
  std::printf("conforming drape 10/10 x 20, projected: seam stress ratio at rest %.4g (%.3g s), one patch %.4g "
              "(%.3g s): %.4g of it\n",
              projected.final_ratio, projected.rest_time, one.final_ratio, one.rest_time,
              projected.final_ratio / one.final_ratio);
  EXPECT_GE(projected.rest_time, 0.0);
  EXPECT_GE(one.rest_time, 0.0);
  ASSERT_GT(one.final_ratio, 0.0);
  EXPECT_LE(projected.final_ratio, 1.2 * one.final_ratio);  // measured 4.08 against 4.55: 0.90
}

TEST(SeamVerify, UncoupledDrapeCreases) {
  const DrapeRun none = run_drape(false, R"("continuity": "none")");
  std::printf("uncoupled drape 20/25: max gap %.3g m, max angle %.3g deg\n", none.gap, none.angle);
  EXPECT_GT(none.angle, 10.0);
}

TEST(SeamVerify, DISABLED_MomentumCorrectionAndSeamStress) {
  // Known failure: the least-squares drapes do not come to rest (still creeping at 5 s; the one-patch
  // drape rests at 2.1 s), and the corrected seam's stress ratio over the one-patch cloth's at the same
  // line is 1.372 at 5 s (1.189 before control points touching a collider took the APIC share,
  // 2026-12-06), criterion 1.2 at rest.
  // The thesis's least-squares seam, which sec. 4.8.1.1's correction is about.
  const DrapeRun corrected = run_drape(false, R"("continuity": "C1", "closure": "least_squares")");
  const DrapeRun uncorrected =
      run_drape(false, R"("continuity": "C1", "closure": "least_squares", "momentum_correction": false)");
  const DrapeRun one = run_drape(true);
  std::printf("seam stress ratio, C1 drape 20/25: rest at %.3g / %.3g / %.3g s; max corrected %.4g, uncorrected "
              "%.4g, one patch %.4g; at the end corrected %.4g, uncorrected %.4g, one patch %.4g (corrected / one "
              "patch %.4g)\n",
              corrected.rest_time, uncorrected.rest_time, one.rest_time, corrected.ratio, uncorrected.ratio, one.ratio,
              corrected.final_ratio, uncorrected.final_ratio, one.final_ratio, corrected.final_ratio / one.final_ratio);
  EXPECT_GE(corrected.rest_time, 0.0);
  EXPECT_GE(one.rest_time, 0.0);
  // The raw ratio (largest stress next to the seam over the median) is mostly the ball under the seam
  // (about 39 at the first contact, with or without a seam); the seamless cloth measured the same way at
  // the same line (one_patch_seam_ratio) is its reference. At rest the seam may add at most 20% to it.
  ASSERT_GT(one.final_ratio, 0.0);
  EXPECT_LE(corrected.final_ratio, 1.2 * one.final_ratio);
}

}  // namespace
}  // namespace shellfrac::output
