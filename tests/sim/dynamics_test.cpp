// Shell dynamics on the MPM grid: conservation, determinism, statics against beam theory, and failure
// reporting.
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::sim {
namespace {

using ::testing::HasSubstr;

std::string sheet_scene(const std::string& extra) {
  return R"({"name": "t", "gravity": [0, 0, 0],
    "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [0.5, 0.4], "cells": [10, 8]},
                "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}}])" +
         extra + "}";
}

TEST(Dynamics, FreeFlightConservesLinearMomentum) {
  Simulation sim(scene::build_model(sheet_scene(""), "t.json"));
  const auto x = sim.positions(0), v = sim.velocities(0);
  // Stretched and bent, moving and spinning: internal forces are large, total momentum must not change.
  for (size_t k = 0; k < x.size(); ++k) {
    x[k] = Eigen::Vector3d(1.1 * x[k].x(), 0.95 * x[k].y(), 0.05 * std::sin(6 * x[k].x()));
    v[k] = Eigen::Vector3d(0.3, -0.2, 0.1) + Eigen::Vector3d(0, 0, 2.0).cross(x[k]);
  }
  const Eigen::Vector3d before = sim.linear_momentum();
  for (int s = 0; s < 60; ++s) sim.step(0.5 * sim.stable_dt());
  const Eigen::Vector3d after = sim.linear_momentum();
  const auto& p = sim.world().shell(0);
  double mass = 0;
  for (double m : p.mass) mass += m;
  for (double m : p.shear.mass) mass += m;
  EXPECT_NEAR(mass, 200 * 0.001 * 0.5 * 0.4, 1e-12);  // rho tau A, split over Types II and III
  EXPECT_GT(before.norm(), 1e-3);
  EXPECT_LE((after - before).norm(), 1e-12 * mass);
}

TEST(Dynamics, LaunchedShellStartsWithItsWholeMomentum) {
  // "initial_velocity" reaches every particle that carries mass (control points and Type III), so the
  // momentum is M v0 from the start and stays so in free flight. Before, the Type III particles started
  // at rest and the sheet lost their share (about a fifth) in its first step.
  const Eigen::Vector3d v0(0.4, -0.3, 1.2);
  Simulation sim(scene::build_model(R"({"name": "t", "gravity": [0, 0, 0],
    "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [0.5, 0.4], "cells": [10, 8]},
                "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200},
                "initial_velocity": [0.4, -0.3, 1.2]}]})",
                             "t.json"));
  const double mass = 200 * 0.001 * 0.5 * 0.4;  // rho tau A
  EXPECT_LE((sim.linear_momentum() - mass * v0).norm(), 1e-12 * mass);
  for (int s = 0; s < 20; ++s) sim.step(0.5 * sim.stable_dt());
  EXPECT_LE((sim.linear_momentum() - mass * v0).norm(), 1e-12 * mass);
  for (const Eigen::Vector3d& v : sim.world().shell(0).v) EXPECT_LE((v - v0).norm(), 1e-12);
}

TEST(Dynamics, FramesAreBitIdenticalForAnyThreadCount) {
  const scene::Model scene = scene::build_model(R"({"name": "t",
    "shells": [{"name": "cloth", "patch": {"type": "flat", "size": [0.6, 0.6], "cells": [12, 12],
                "origin": [-0.3, 0.3, 0.3], "axis_u": [1, 0, 0], "axis_v": [0, 0, -1]},
                "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}}],
    "colliders": [{"shape": "sphere", "center": [0, 0, 0], "radius": 0.2}]})", "t.json");
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    Simulation sim(scene);
    sim.advance_to(0.15);
    return sim.world().shell(0).x;
  };
  const auto one = run(1), two = run(2), again = run(2);
  ASSERT_EQ(one.size(), two.size());
  bool identical = true;
  for (size_t k = 0; k < one.size(); ++k) identical = identical && one[k] == two[k] && two[k] == again[k];
  EXPECT_TRUE(identical);
  EXPECT_LT(one[0].y(), 0.3 - 0.05);  // and it did move
}

TEST(Dynamics, CantileverPlateMatchesBeamTheory) {
  // A 0.5 m x 0.1 m plate, 5 cm thick (nu = 0, so plate and beam theory agree), clamped at x = 0 by its
  // first two control point columns, under its own weight along -z; grid damping brings it to rest.
  // Euler-Bernoulli tip deflection: w = q L^4 / (8 E I) = 1.5 rho g L^4 / (E tau^2).
  const double E = 2e8, rho = 1000, g = 9.81, L = 0.5, tau = 0.05;
  const scene::Model scene = scene::build_model(R"({"name": "cantilever", "gravity": [0, 0, -9.81], "damping": 180,
    "shells": [{"name": "plate", "patch": {"type": "flat", "size": [0.5, 0.1], "cells": [20, 4]},
                "thickness": 0.05, "material": {"E": 2e8, "nu": 0.0, "density": 1000}}],
    "pins": [{"shell": "plate", "control_points": [[0,0],[0,1],[0,2],[0,3],[0,4],[0,5],
                                                   [1,0],[1,1],[1,2],[1,3],[1,4],[1,5]]}]})", "c.json");
  Simulation sim(scene);
  auto tip_deflection = [&] {
    const auto surf = sim.world().shell(0).current_surface();
    double tip = 0;
    for (int k = 0; k <= 4; ++k) tip += surf.point(1.0, k / 4.0).z() / 5.0;
    return tip;
  };
  sim.advance_to(0.3);
  const double tip = tip_deflection();
  const double expected = -1.5 * rho * g * L * L * L * L / (E * tau * tau);
  // Measured at 20 x 4 cells: 0.9983 of beam theory.
  EXPECT_NEAR(tip, expected, 0.03 * std::abs(expected));
  // At rest: the deflection no longer changes.
  sim.advance_to(0.35);
  EXPECT_NEAR(tip_deflection(), tip, 5e-4 * std::abs(expected));
  // Statics: at rest, and the clamp carries the weight of everything that is not pinned.
  const auto& p = sim.world().shell(0);
  double free_mass = 0;
  for (size_t k = 0; k < p.mass.size(); ++k)
    if (k % 22 > 1) free_mass += p.mass[k];
  for (double m : p.shear.mass) free_mass += m;
  EXPECT_NEAR(sim.pin_reaction(0).z(), free_mass * g, 0.01 * free_mass * g);
}

TEST(Dynamics, TimeStepAboveTheBoundIsRefused) {
  try {
    Simulation sim(scene::build_model(sheet_scene(R"(, "time": {"dt": 0.01})"), "t.json"));
    FAIL();
  } catch (const scene::SceneError& e) {
    EXPECT_EQ(e.json_path(), "/time/dt");
    EXPECT_THAT(e.message(), HasSubstr("exceeds the stability bound"));
  }
  // With substepping allowed the step is split instead.
  Simulation sim(scene::build_model(sheet_scene(R"(, "time": {"dt": 0.01, "allow_substepping": true})"), "t.json"));
  EXPECT_LT(sim.stable_dt(), 0.01);
  EXPECT_EQ(sim.advance_to(0.01), static_cast<long>(std::ceil(0.01 / sim.stable_dt() - 1e-9)));
}

TEST(Dynamics, BlowUpIsReportedWithShellAndStep) {
  Simulation sim(scene::build_model(sheet_scene(R"(, "time": {"dt": 0.05, "enforce_stability_bound": false})"), "t.json"));
  for (auto& x : sim.positions(0)) x.x() *= 1.2;  // stretched: the oversized step cannot hold it
  try {
    for (int s = 0; s < 200; ++s) sim.step(0.05);
    FAIL() << "no failure detected";
  } catch (const NumericalError& e) {
    EXPECT_THAT(e.what(), HasSubstr("shell \"sheet\""));
    EXPECT_THAT(e.what(), HasSubstr("at step"));
  }
}

TEST(Dynamics, PlasticSheetKeepsADentElasticSheetDoesNot) {
  // A clamped 0.4 m square sheet is pressed 4 cm deep at its centre by a sphere that then withdraws.
  // With von Mises plasticity the dent stays; without, the sheet springs back.
  auto run = [](bool plastic) {
    const std::string plasticity = plastic ? R"(, "plasticity": {"yield_stress": 1e6})" : "";
    const scene::Model scene = scene::build_model(R"({"name": "dent", "gravity": [0, 0, 0], "damping": 25,
      "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [0.4, 0.4], "cells": [12, 12],
                  "origin": [-0.2, -0.2, 0]},
                  "thickness": 0.002, "material": {"E": 2e8, "nu": 0.3, "density": 2700)" + plasticity + R"(}}],
      "colliders": [{"shape": "sphere", "center": [0, 0, 0.051], "radius": 0.05, "boundary": "slip",
                     "motion": {"keyframes": [{"time": 0, "translation": [0, 0, 0]},
                                              {"time": 0.05, "translation": [0, 0, -0.04]},
                                              {"time": 0.08, "translation": [0, 0, 0.1]}]}}],
      "pins": [{"shell": 0, "region": {"u": [0, 0.05]}}, {"shell": 0, "region": {"u": [0.95, 1]}},
               {"shell": 0, "region": {"v": [0, 0.05]}}, {"shell": 0, "region": {"v": [0.95, 1]}}]})",
                                    "dent.json");
    Simulation sim(scene);
    sim.advance_to(0.05);
    const double pressed = sim.world().shell(0).current_surface().point(0.5, 0.5).z();
    sim.advance_to(0.2);
    const double after = sim.world().shell(0).current_surface().point(0.5, 0.5).z();
    return std::make_tuple(pressed, after, sim.world().shell(0).max_plastic_strain());
  };
  const auto [pressed_p, after_p, strain_p] = run(true);
  const auto [pressed_e, after_e, strain_e] = run(false);
  EXPECT_LT(pressed_p, -0.03);  // the sphere pushed the centre down about 4 cm
  EXPECT_LT(pressed_e, -0.03);
  EXPECT_LT(after_p, 0.5 * pressed_p);   // the plastic sheet keeps more than half of the dent
  EXPECT_GT(after_e, 0.15 * pressed_e);  // the elastic sheet springs back to within 15%, still settling
  EXPECT_LT(after_e, -0.15 * pressed_e);
  EXPECT_GT(strain_p, 0.005);
  EXPECT_EQ(strain_e, 0.0);
}

TEST(Dynamics, SoftBallFallsAndRestsOnTheGround) {
  // Type-I solid in free fall gains exactly M g t of momentum, then rests on a sticky ground without
  // sinking more than half a grid cell.
  Simulation sim(scene::build_model(R"({"name": "ball", "grid": {"dx": 0.02},
    "solids": [{"name": "ball", "shape": "sphere", "center": [0, 0.2, 0], "radius": 0.05, "spacing": 0.01,
                "material": {"E": 1e5, "nu": 0.3, "density": 500}}],
    "colliders": [{"shape": "half_space", "point": [0, 0, 0], "normal": [0, 1, 0], "boundary": "sticky"}]})",
                             "ball.json"));
  double M = 0;
  for (double m : sim.world().solid(0).mass) M += m;
  sim.advance_to(0.05);  // still falling: 0.2 - 0.05 - g t^2 / 2 > 0
  EXPECT_NEAR(sim.linear_momentum().y(), -M * 9.81 * 0.05, 1e-9 * M);
  EXPECT_NEAR(sim.linear_momentum().x(), 0.0, 1e-12 * M);
  double lowest = 1e9;  // over the whole fall, bounce included
  for (double t = 0.06; t <= 0.6; t += 0.01) {
    sim.advance_to(t);
    for (const auto& x : sim.world().solid(0).x) lowest = std::min(lowest, x.y());
  }
  EXPECT_GT(lowest, -0.5 * 0.02);
  EXPECT_LT(lowest, 0.02);  // and it did reach the ground
}

}  // namespace
}  // namespace shellfrac::sim
