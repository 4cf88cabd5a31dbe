// Boundary conditions, loads, initial velocity fields and probes: load totals against their
// closed forms, momentum balance with the pins' reactions, and plate statics against Kirchhoff theory.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <array>
#include <cstdio>
#include <filesystem>
#include <sstream>

#include "core/constants.hpp"
#include "output/run.hpp"
#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "sim/probes.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::sim {
namespace {

constexpr double kRho = 200, kTau = 0.001, kLx = 0.5, kLy = 0.4;

// A 0.5 m x 0.4 m sheet without gravity; `extra` is spliced into the top level.
std::string sheet(const std::string& extra, const std::string& shell_extra = "") {
  return R"({"name": "t", "gravity": [0, 0, 0],
    "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [0.5, 0.4], "cells": [10, 8]}, )" +
         shell_extra + R"("thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}}])" + extra + "}";
}

double particle_mass(const Simulation& sim) {
  double m = 0;
  for (double x : sim.world().shell(0).mass) m += x;
  for (double x : sim.world().shell(0).shear.mass) m += x;
  return m;
}

TEST(Ramp, IsPiecewiseLinearThroughItsKeyframes) {
  scene::model::Ramp r;
  r.keys = {{0.0, 0.0}, {0.1, 1.0}, {0.3, 0.5}};
  EXPECT_EQ(r.at(-1.0), 0.0);  // constant before the first keyframe
  EXPECT_EQ(r.at(0.0), 0.0);
  EXPECT_NEAR(r.at(0.05), 0.5, 1e-15);
  EXPECT_EQ(r.at(0.1), 1.0);
  EXPECT_NEAR(r.at(0.2), 0.75, 1e-15);
  EXPECT_EQ(r.at(0.3), 0.5);
  EXPECT_EQ(r.at(5.0), 0.5);  // and after the last
  EXPECT_EQ(scene::model::Ramp{}.at(3.0), 1.0);
}

TEST(Loads, TotalsMatchTheirClosedForms) {
  // On the flat sheet at rest each load's total is known exactly: pressure q A along the normal, an
  // edge load q L, a point load F (partition of unity), a body load M a with M the particles' mass.
  Simulation sim(scene::build_model(sheet(R"(, "loads": [
      {"type": "pressure", "shell": "sheet", "pressure": 3.0},
      {"type": "edge", "shell": "sheet", "edge": "u0", "force_per_length": [0, 2.0, -1.0]},
      {"type": "edge", "shell": "sheet", "edge": "v1", "force_per_length": [0.5, 0, 0]},
      {"type": "point", "shell": "sheet", "at": [0.3, 0.7], "force": [1.0, -2.0, 4.0]},
      {"type": "body", "shell": "sheet", "acceleration": [0, 0, -3.0],
       "ramp": [[0, 2.0], [1.0, 0.0]]}])"),
                                    "t.json"));
  sim.step(0.5 * sim.stable_dt());
  const double mass = particle_mass(sim);
  EXPECT_NEAR(mass, kRho * kTau * kLx * kLy, 1e-12);
  const double tol = 1e-12;
  EXPECT_LE((sim.applied_load(0) - Eigen::Vector3d(0, 0, 3.0 * kLx * kLy)).norm(), tol);
  EXPECT_LE((sim.applied_load(1) - kLy * Eigen::Vector3d(0, 2.0, -1.0)).norm(), tol);
  EXPECT_LE((sim.applied_load(2) - kLx * Eigen::Vector3d(0.5, 0, 0)).norm(), tol);
  EXPECT_LE((sim.applied_load(3) - Eigen::Vector3d(1.0, -2.0, 4.0)).norm(), tol);
  // The ramp is read at the start of the step (t = 0): factor 2.
  EXPECT_LE((sim.applied_load(4) - 2.0 * mass * Eigen::Vector3d(0, 0, -3.0)).norm(), tol);
}

TEST(Loads, BodyForceAcceleratesTheFreeSheetAsMTimesA) {
  // Free flight: the momentum grows by M a per second exactly, and matches the same run under gravity.
  const Eigen::Vector3d a(0.5, -1.0, 2.0);
  Simulation sim(scene::build_model(
      sheet(R"(, "loads": [{"type": "body", "shell": "sheet", "acceleration": [0.5, -1.0, 2.0]}])"), "t.json"));
  Simulation gravity(scene::build_model(R"({"name": "t", "gravity": [0.5, -1.0, 2.0],
    "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [0.5, 0.4], "cells": [10, 8]},
                "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200}}]})",
                                        "g.json"));
  const double dt = 0.5 * sim.stable_dt();
  for (int s = 0; s < 40; ++s) {
    sim.step(dt);
    gravity.step(dt);
  }
  const double M = particle_mass(sim);
  EXPECT_LE((sim.linear_momentum() - M * a * sim.time()).norm(), 1e-10 * M * a.norm() * sim.time());
  // Gravity acts on the grid nodes, the body load on the control points: the same total, and (a
  // uniform acceleration of an unstressed sheet) the same motion up to round-off.
  EXPECT_LE((gravity.linear_momentum() - sim.linear_momentum()).norm(), 1e-10 * M * a.norm() * sim.time());
}

TEST(Pins, MomentumObeysLoadsAndReactionsWithRollers) {
  // A point load on a sheet on rollers (u0 and u1 held in z only, one corner in x and y): every step the
  // momentum of the moving particles changes by dt (applied load + support reactions), to round-off.
  Simulation sim(scene::build_model(sheet(R"(,
    "pins": [{"shell": "sheet", "edges": ["u0", "u1"], "components": ["z"]},
             {"shell": "sheet", "control_points": [[0, 0]], "components": ["x", "y"]}],
    "loads": [{"type": "point", "shell": "sheet", "at": [0.4, 0.6], "force": [0.2, 0.1, -0.5],
               "ramp": [[0, 0], [0.01, 1]]}])"),
                                    "t.json"));
  const double dt = 0.5 * sim.stable_dt();
  const auto& x0 = sim.world().initial_positions(0);
  for (int s = 0; s < 80; ++s) {
    const Eigen::Vector3d before = sim.linear_momentum();
    sim.step(dt);
    const Eigen::Vector3d change = sim.linear_momentum() - before;
    const Eigen::Vector3d expected = dt * (sim.applied_load(0) + sim.pin_set_reaction(0) + sim.pin_set_reaction(1));
    ASSERT_LE((change - expected).norm(), 1e-10 * dt * 0.5) << "step " << s;
  }
  // The held components never moved; the free ones did.
  const auto& p = sim.world().shell(0);
  const int nu = p.reference().num_u(), nv = p.reference().num_v();
  double in_plane = 0;
  for (int j = 0; j < nv; ++j)
    for (int i : {0, nu - 1}) {
      const auto k = static_cast<size_t>(i + nu * j);
      EXPECT_EQ(p.x[k].z(), x0[k].z());
      in_plane = std::max(in_plane, (p.x[k] - x0[k]).head<2>().norm());
    }
  EXPECT_EQ(p.x[0].head<2>(), x0[0].head<2>());
  EXPECT_GT(in_plane, 0.0);
  // The load is transverse mostly: the rollers carry it with a downward-pointing share.
  EXPECT_GT(sim.pin_set_reaction(0).z(), 0.0);
}

TEST(Pins, EdgeFrameHoldsTheSurfaceNormalOfACylinder) {
  // A quarter cylinder (axis z) on rollers along its straight edges held in the edge frame's normal
  // direction: the held points move only within their tangent plane.
  Simulation sim(scene::build_model(R"({"name": "t", "gravity": [0, -9.81, 0],
    "shells": [{"name": "roof", "patch": {"type": "cylinder", "radius": 0.3, "height": 0.4, "sweep_degrees": 90,
                "cells": [8, 6]}, "thickness": 0.002, "material": {"E": 1e6, "nu": 0.3, "density": 500}}],
    "pins": [{"shell": "roof", "edges": ["u0", "u1"], "frame": "edge", "components": ["normal"]},
             {"shell": "roof", "edges": ["v0"], "components": ["z"]}]})",
                                    "t.json"));
  const double dt = 0.5 * sim.stable_dt();
  for (int s = 0; s < 40; ++s) sim.step(dt);
  const auto& p = sim.world().shell(0);
  const auto& x0 = sim.world().initial_positions(0);
  const int nu = p.reference().num_u(), nv = p.reference().num_v();
  double moved = 0;
  for (int j = 0; j < nv; ++j)
    for (int i : {0, nu - 1}) {
      const auto k = static_cast<size_t>(i + nu * j);
      const double u = i == 0 ? p.reference().knots_u().domain_begin() : p.reference().knots_u().domain_end();
      const Eigen::Vector3d n = p.reference().normal(u, p.reference().knots_v().greville(j));
      EXPECT_NEAR(n.dot(p.x[k] - x0[k]), 0.0, 1e-15);
      moved = std::max(moved, (p.x[k] - x0[k]).norm());
    }
  EXPECT_GT(moved, 1e-9);  // they slide along the tangent plane
}

TEST(InitialVelocity, SineModeAtTheGrevillePointsAndTheSameAsAList) {
  Simulation sine(scene::build_model(
      sheet("", R"("initial_velocity_field": {"shape": "sine", "modes": [1, 2], "amplitude": 0.3, "direction": [0, 0, 2]}, )"),
      "t.json"));
  const auto& p = sine.world().shell(0);
  const auto& ku = p.reference().knots_u();
  const auto& kv = p.reference().knots_v();
  const int nu = p.reference().num_u();
  std::ostringstream list;
  for (size_t k = 0; k < p.v.size(); ++k) {
    const double s = (ku.greville(static_cast<int>(k) % nu) - ku.domain_begin()) / (ku.domain_end() - ku.domain_begin());
    const double t = (kv.greville(static_cast<int>(k) / nu) - kv.domain_begin()) / (kv.domain_end() - kv.domain_begin());
    const double w = 0.3 * std::sin(core::kPi * s) * std::sin(2 * core::kPi * t);
    EXPECT_NEAR(p.v[k].z(), w, 1e-15);
    EXPECT_EQ(p.v[k].head<2>(), Eigen::Vector2d::Zero());
    list << (k ? ", " : "") << "[0, 0, " << std::setprecision(17) << p.v[k].z() << "]";
  }
  Simulation listed(scene::build_model(
      sheet("", R"("initial_velocity_field": {"shape": "list", "values": [)" + list.str() + "]}, "), "t.json"));
  const auto& q = listed.world().shell(0);
  for (size_t k = 0; k < q.v.size(); ++k) EXPECT_NEAR((q.v[k] - p.v[k]).norm(), 0.0, 1e-17);
  for (size_t c = 0; c < q.shear.v.size(); ++c) EXPECT_NEAR((q.shear.v[c] - p.shear.v[c]).norm(), 0.0, 1e-16);
  // Shear particles carry the field's interpolation: the total momentum is the field's consistent one.
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < p.v.size(); ++k) momentum += p.mass[k] * p.v[k];
  for (size_t c = 0; c < p.shear.v.size(); ++c) momentum += p.shear.mass[c] * p.shear.v[c];
  EXPECT_LE((sine.linear_momentum() - momentum).norm(), 1e-15);
}

TEST(Probes, MatchTheBasisEvaluationAndTheCornerControlPoint) {
  Simulation sim(scene::build_model(sheet(R"(,
    "output": {"probes": [{"name": "inner", "shell": "sheet", "at": [0.3, 0.7]},
                          {"name": "corner", "shell": "sheet", "at": [1, 1]}]},
    "pins": [{"shell": "sheet", "edges": ["u0"]}],
    "loads": [{"type": "pressure", "shell": "sheet", "pressure": 0.5}])"),
                                    "t.json"));
  const ProbeSampler probes(sim.model(), sim.world());
  for (int s = 0; s < 30; ++s) sim.step(0.5 * sim.stable_dt());
  const auto& p = sim.world().shell(0);
  const ProbeSample inner = probes.sample(0, sim.world(), sim.time());
  const nurbs::NurbsSurface now = p.current_surface();
  const auto& ku = p.reference().knots_u();
  const auto& kv = p.reference().knots_v();
  const double u = ku.domain_begin() + 0.3 * (ku.domain_end() - ku.domain_begin());
  const double v = kv.domain_begin() + 0.7 * (kv.domain_end() - kv.domain_begin());
  EXPECT_LE((inner.position - now.point(u, v)).norm(), 1e-14);
  EXPECT_LE((inner.displacement - (inner.position - Eigen::Vector3d(0.3 * kLx, 0.7 * kLy, 0))).norm(), 1e-15);
  EXPECT_GT(inner.displacement.norm(), 1e-9);
  const ProbeSample corner = probes.sample(1, sim.world(), sim.time());
  EXPECT_EQ(corner.position, p.x.back());  // the interpolating corner: exactly the control point
  EXPECT_EQ(corner.velocity, p.v.back());
}

// The plate of scenes/plate-pressure-rollers.json: a = 1, t = 0.05, E = 1e7, nu = 0.3, q = 7.
struct PlateResult {
  double centre = 0;  // w at the centre
  std::vector<std::array<double, 3>> reactions;  // per pin
  double reaction_z = 0, applied_z = 0;
  bool rested = false;
};

PlateResult run_plate(scene::Scene s, const std::string& name) {
  const std::filesystem::path out = std::filesystem::temp_directory_path() / ("shellfrac-plate-" + name);
  std::ostringstream log;
  output::RunOptions options;
  options.out_dir = out;
  const output::Summary r = output::run_scene(scene::build(s), options, log);
  PlateResult p;
  p.centre = r.probes.at(0).samples.back().displacement[2];
  for (const output::PinReport& pin : r.pins) {
    p.reaction_z += pin.reaction[2];
    p.reactions.push_back(pin.reaction);
  }
  p.applied_z = r.loads.at(0).applied[2];
  p.rested = r.until_rest && r.until_rest->reached;
  std::printf("plate %s: w_centre = %.9g m, reactions %.9g N, load %.9g N, %ld steps, rest at %.4g s\n", name.c_str(),
              p.centre, p.reaction_z, p.applied_z, r.steps, r.simulated_seconds);
  std::filesystem::remove_all(out);
  return p;
}

double plate_rigidity() { return 1e7 * std::pow(0.05, 3) / (12 * (1 - 0.3 * 0.3)); }

scene::Scene plate_scene() { return scene::load_scene(std::string(SHELLFRAC_SOURCE_DIR) + "/scenes/plate-pressure-rollers.json"); }

TEST(PlateStatics, SimplySupportedOnRollersMatchesKirchhoff) {
  // Navier's series: w_centre = 0.00406235 q a^4 / D (Timoshenko & Woinowsky-Krieger, Table 8).
  const PlateResult r = run_plate(plate_scene(), "ss");
  const double expected = 0.00406235 * 7.0 / plate_rigidity();
  EXPECT_TRUE(r.rested);
  EXPECT_NEAR(r.centre, expected, 0.01 * expected);
  // At rest the supports carry the whole load (relative residual set by the rest thresholds).
  EXPECT_NEAR(r.reaction_z, -r.applied_z, 1e-3 * r.applied_z);
  EXPECT_NEAR(r.applied_z, 7.0, 1e-6 * 7.0);  // q a^2; the follower load tilts by the slope only
  // The corners shared by the rollers and the in-plane pins split their reactions by direction: the
  // rollers take only z, the corner pins only their in-plane components.
  ASSERT_EQ(r.reactions.size(), 3u);
  EXPECT_LE(std::hypot(r.reactions[0][0], r.reactions[0][1]), 1e-12);
  EXPECT_EQ(r.reactions[1][2], 0.0);
  EXPECT_EQ(r.reactions[2][0], 0.0);
  EXPECT_EQ(r.reactions[2][2], 0.0);
}

TEST(PlateStatics, ClampedQuarterPlateWithTwoSymmetryPlanesMatchesKirchhoff) {
  // w_centre = 0.00126532 q a^4 / D (Timoshenko & Woinowsky-Krieger, Table 35), on a quarter of the plate
  // (16 x 16 cells, the resolution of 32 x 32 on the whole): symmetry planes x = 0 and y = 0 through the
  // centre, now the quarter's corner (0, 0); the outer edges clamped by holding their first two
  // control-point rows in z (zero deflection and zero slope).
  scene::Scene s = plate_scene();
  auto& patch = *s.shells[0].patch;
  patch.size = scene::Vec2{0.5, 0.5};
  patch.cells = scene::Int2{16, 16};
  scene::Pin clamp;
  clamp.shell = std::string("plate");
  clamp.edges = std::vector<std::string>{"u1", "v1"};
  clamp.rows = 2;
  clamp.components = std::vector<std::string>{"z"};
  scene::Pin sym_x, sym_y;
  sym_x.shell = sym_y.shell = std::string("plate");
  sym_x.edges = std::vector<std::string>{"u0"};
  sym_x.symmetry_normal = scene::Vec3{1, 0, 0};
  sym_y.edges = std::vector<std::string>{"v0"};
  sym_y.symmetry_normal = scene::Vec3{0, 1, 0};
  s.pins = {clamp, sym_x, sym_y};
  s.output.probes[0].at = scene::Vec2{0, 0};
  const PlateResult r = run_plate(s, "clamped-quarter");
  const double expected = 0.00126532 * 7.0 / plate_rigidity();
  EXPECT_TRUE(r.rested);
  EXPECT_NEAR(r.centre, expected, 0.01 * expected);
  EXPECT_NEAR(r.applied_z, 7.0 / 4, 1e-6 * 7.0 / 4);
  EXPECT_NEAR(r.reaction_z, -r.applied_z, 1e-3 * r.applied_z);
}

}  // namespace
}  // namespace shellfrac::sim
