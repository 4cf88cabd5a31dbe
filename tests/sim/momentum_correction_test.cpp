// The momentum correction of coupled seams (thesis sec. 4.8.1.1, Eq. 4.30-4.32) against the uncorrected
// coupling, where Eq. 4.29/4.34 place the follower's coupled rows and their velocities stay the grid's.
//
// Why the scene below: each step the coupled rows jump from where the grid moved them (xbar) to where the
// leader's edge puts them (the target). That jump is the difference between the grid velocity along the
// seam and its fit in the leader's spline space. When the leader's cells along the seam are about as
// small as the grid spacing (the drapes, the hanging sheets of coupling_test.cpp) the jump is about 0.1%
// of a grid cell per step and both variants give the same seam stress (within 3%). With a leader much
// coarser than the grid (here 2 cells along the 1 m seam, grid spacing 1/12 m) the grid carries motion the
// leader's edge cannot follow; without the correction the rows behind the coupled ones keep that motion
// while the coupled rows are pulled back every step, and the cells between them are strained.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "output/seam_metrics.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::sim {
namespace {

// A 1 m x 1 m sheet in zero gravity as two flat patches meeting along x = 0 (the seam runs along y):
// the left (leader) with 6 x `left_cells` cells, the right (follower) with 6 x `right_cells`, coupled C1.
// `pins`: the outer edges u = 0 of the left and u = 1 of the right patch move with +-5 cm/s along the
// seam (in-plane shear across the seam, grid damping 1/s); otherwise nothing is pinned or damped and the
// sheet falls freely in `gravity`.
std::string sheet_scene(int left_cells, int right_cells, bool corrected, bool pins,
                        const std::string& gravity = "[0, 0, 0]") {
  auto shell = [&](const char* name, double x0, int cells_v) {
    return std::string(R"({"name": ")") + name + R"(", "patch": {"type": "flat", "size": [0.5, 1.0], "cells": [6, )" +
           std::to_string(cells_v) + R"(], "origin": [)" + std::to_string(x0) +
           R"(, 1.0, 0], "axis_u": [1, 0, 0], "axis_v": [0, -1, 0]},
       "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}})";
  };
  std::string s = R"({"name": "sheared-seam", "gravity": )" + gravity + R"(, "damping": )" + std::string(pins ? "1.0" : "0") +
                  R"(, "shells": [)" +
                  shell("left", -0.5, left_cells) + ", " + shell("right", 0.0, right_cells) + "]";
  if (pins) {
    s += R"(, "pins": [{"shell": "left", "region": {"u": [0, 0.01]}, "motion": {"linear_velocity": [0, 0.05, 0]}},
                     {"shell": "right", "region": {"u": [0.99, 1]}, "motion": {"linear_velocity": [0, -0.05, 0]}}])";
  }
  // The thesis's least-squares seam (Eq. 4.29) is what sec. 4.8.1.1 corrects; exact closure, the
  // default, would move the leader's coarse rows as well.
  s += R"(, "interfaces": [{"a": {"shell": "left", "side": "u1"}, "b": {"shell": "right", "side": "u0"},
                            "continuity": "C1", "closure": "least_squares", "momentum_correction": )" +
       std::string(corrected ? "true" : "false") + "}]}";
  return s;
}

struct SeamRun {
  double max_ratio = 0;        // seam stress ratio (output/seam_metrics.hpp), largest over the frames
  double max_row_offset = 0;   // coupled rows vs their Eq. 4.29/4.34 targets [m], largest over the frames
  double max_row_velocity_offset = 0;  // coupled rows' velocities vs the leader's mapped by the same operators
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();  // linear momentum at the end
  double mass = 0;             // control points and shear particles of both patches
  double max_velocity_spread = 0;  // largest |v - v_first| over all control points at the end
};

// Runs `end` seconds in frames of 1/40 s and measures after every frame.
SeamRun run(const std::string& json, double end) {
  const scene::Model scene = scene::build_model(json, "sheared-seam.json");
  Simulation sim(scene);
  const coupling::Interface& c = scene.interfaces.at(0).coupling;
  std::vector<int> rows = c.follower_row1;
  rows.insert(rows.end(), c.follower_row2.begin(), c.follower_row2.end());
  SeamRun r;
  const int frames = static_cast<int>(std::lround(end * 40));
  for (int f = 1; f <= frames; ++f) {
    sim.advance_to(f / 40.0);
    const auto& leader = sim.world().shell(static_cast<size_t>(c.leader_patch));
    const auto& follower = sim.world().shell(static_cast<size_t>(c.follower_patch));
    // Independent of the simulation's coupling stage: the operators applied to the leader's state now.
    const std::vector<Eigen::Vector3d> target = c.follower_positions(leader.x);
    const std::vector<Eigen::Vector3d> target_v = c.follower_positions(leader.v);
    for (size_t k = 0; k < rows.size(); ++k) {
      const auto p = static_cast<size_t>(rows[k]);
      r.max_row_offset = std::max(r.max_row_offset, (follower.x[p] - target[k]).norm());
      r.max_row_velocity_offset = std::max(r.max_row_velocity_offset, (follower.v[p] - target_v[k]).norm());
    }
    r.max_ratio = std::max(r.max_ratio, output::measure_seams(scene, sim.world()).at(0).stress_ratio.value_or(0.0));
  }
  r.momentum = sim.linear_momentum();
  for (size_t i = 0; i < sim.world().num_shells(); ++i) {
    const auto& p = sim.world().shell(i);
    for (double m : p.mass) r.mass += m;
    for (double m : p.shear.mass) r.mass += m;
    for (const Eigen::Vector3d& v : p.v)
      r.max_velocity_spread = std::max(r.max_velocity_spread, (v - sim.world().shell(0).v[0]).norm());
  }
  return r;
}

TEST(MomentumCorrection, KeepsTheShearedSeamStressRatioUnderTwo) {
  // 2 leader cells vs 11 follower cells along the seam (non-nested), 0.5 s of shear at +-5 cm/s.
  const SeamRun corrected = run(sheet_scene(2, 11, true, true), 0.5);
  const SeamRun uncorrected = run(sheet_scene(2, 11, false, true), 0.5);
  std::printf("sheared seam 2/11, C1: seam stress ratio corrected %.4g, uncorrected %.4g; coupled rows off their "
              "targets by %.3g / %.3g m; row velocities off the mapped leader's by %.3g / %.3g m/s\n",
              corrected.max_ratio, uncorrected.max_ratio, corrected.max_row_offset, uncorrected.max_row_offset,
              corrected.max_row_velocity_offset, uncorrected.max_row_velocity_offset);
  // Measured 1.647 and 2.65 (the uncorrected peak sits in the follower's second cell from the seam, just
  // behind the coupled rows, mid-seam). Asserted with about 15% margin either side of 2.
  EXPECT_LT(corrected.max_ratio, 1.85);
  EXPECT_GT(uncorrected.max_ratio, 2.3);
  // Both variants leave the coupled rows exactly on the Eq. 4.29/4.34 targets (1 m sheet: absolute 1e-12 m).
  EXPECT_LE(corrected.max_row_offset, 1e-12);
  EXPECT_LE(uncorrected.max_row_offset, 1e-12);
  // The corrected rows move with the leader (velocities mapped by the same linear operators). The
  // uncorrected rows keep the grid's velocity, and since only their positions are reset, the force that
  // holds them on the leader's edge piles up in that velocity and goes back to the grid every step:
  // measured 0.93 m/s after 0.5 s, growing about linearly, against the pins' 5 cm/s.
  EXPECT_LE(corrected.max_row_velocity_offset, 1e-12);
  EXPECT_GT(uncorrected.max_row_velocity_offset, 0.5);
}

TEST(MomentumCorrection, FreeFallNeedsNoCorrection) {
  // Free fall: every particle gets the same g dt each step, so the leader's edge moves rigidly, the
  // operators' rows sum to one (translations pass through), the targets are where the grid moved the
  // rows, and the correction is zero. Analytic: every control point has velocity g t, and the linear
  // momentum is M g t with M the mass of the control points and shear particles.
  const Eigen::Vector3d g(1.0, -9.81, 0.5);
  const double t = 0.25;
  for (bool corrected : {true, false}) {
    const SeamRun r = run(sheet_scene(2, 11, corrected, false, "[1.0, -9.81, 0.5]"), t);
    const Eigen::Vector3d expected = r.mass * t * g;
    std::printf("free fall (%s): rows off targets %.3g m, row velocities off %.3g m/s, velocity spread %.3g m/s, "
                "momentum error %.3g (relative)\n",
                corrected ? "corrected" : "uncorrected", r.max_row_offset, r.max_row_velocity_offset,
                r.max_velocity_spread, (r.momentum - expected).norm() / expected.norm());
    EXPECT_LE(r.max_row_offset, 1e-12);
    EXPECT_LE(r.max_row_velocity_offset, 1e-12);
    EXPECT_LE(r.max_velocity_spread, 1e-12);
    EXPECT_LE((r.momentum - expected).norm(), 1e-12 * expected.norm());
  }
}

}  // namespace
}  // namespace shellfrac::sim
