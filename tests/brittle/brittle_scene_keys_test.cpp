// The brittle keys of the scene format (scene/describe.hpp): every brittle scene reads, writes back to the
// same document, and builds into brittle bodies whose derived inputs follow from the keys; a scene built
// in C++ is refused with the same JSON path as the file would be.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>

#include "brittle/phase_field.hpp"
#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"

namespace shellfrac::scene {
namespace {

namespace fs = std::filesystem;

fs::path brittle_scene(const std::string& name) { return fs::path(SHELLFRAC_SOURCE_DIR) / "scenes" / "brittle" / (name + ".json"); }

TEST(BrittleSceneKeys, EveryBrittleSceneWritesBackToItsDocument) {
  for (const auto& e : fs::directory_iterator(fs::path(SHELLFRAC_SOURCE_DIR) / "scenes" / "brittle")) {
    if (e.path().extension() != ".json") continue;
    std::ifstream in(e.path());
    const nlohmann::json original = nlohmann::json::parse(in);
    const Scene s = load_scene(e.path().string());
    EXPECT_EQ(to_json(s), original) << e.path();
  }
}

TEST(BrittleSceneKeys, NotchedBeamBuildsItsBrittleBody) {
  const Model m = load_model(brittle_scene("notched-beam").string());
  ASSERT_EQ(m.brittle_solids.size(), 1u);
  EXPECT_TRUE(m.solids.empty());
  const model::BrittleBody& b = m.brittle_solids[0];
  EXPECT_EQ(b.name, "beam");
  EXPECT_EQ(b.json_path, "/solids/0");
  // Regular sampling at 2.5 mm of a 0.2 x 0.02 x 0.04 m box: 80 x 8 x 16 cell centres, minus the notch
  // (|x| < 3 mm, z < 12 mm: 2 x 8 x 5 cell centres, at x = +-1.25 mm and z = 1.25 ... 11.25 mm).
  EXPECT_EQ(b.solid->size(), 80u * 8u * 16u - 2u * 8u * 5u);
  // Particle volumes share the box volume (including the removed notch: the mesh is the domain).
  EXPECT_NEAR(b.solid->particles.volume[0], 0.2 * 0.02 * 0.04 / (80.0 * 8 * 16), 1e-15);
  EXPECT_DOUBLE_EQ(b.solver.dx, 0.005);
  EXPECT_DOUBLE_EQ(b.event.crack.grid.spacing, 0.005);
  EXPECT_EQ(b.crack_interval, 25);
  EXPECT_DOUBLE_EQ(b.solver.stop.max_time, 0.012);
  EXPECT_DOUBLE_EQ(b.solver.stop.damaged_fraction, 0.2);
  EXPECT_DOUBLE_EQ(b.sliver_volume, 0.005 * 0.005 * 0.005);  // default: one MPM cell
  EXPECT_EQ(m.colliders.size(), 3u);
  EXPECT_EQ(b.solid->material.residual_stiffness, 0.0);  // the thesis's Eq. 2.30 unless the scene says
  EXPECT_EQ(b.solid->material.broken_stretch_limit, 0.0);  // unbounded, as in the thesis, unless the scene says
  EXPECT_FALSE(b.solid->material.retire_rubble);
}

TEST(BrittleSceneKeys, FullyDamagedChoosesTheThesisABoundedStretchOrRetiredRubble) {
  Scene s = load_scene(brittle_scene("notched-beam").string());
  for (const std::string mode : {"tensionless", "bounded", "rubble"}) {
    s.solids[0].material->fully_damaged = mode;
    const brittle::BrittleMaterial m = build(s).brittle_solids[0].solid->material;
    EXPECT_EQ(m.broken_stretch_limit, mode == "bounded" ? 3.0 : 0.0) << mode;
    EXPECT_EQ(m.retire_rubble, mode == "rubble") << mode;
  }
  s.solids[0].material->fully_damaged = "dust";
  try {
    build(s);
    ADD_FAILURE() << "fully_damaged \"dust\" accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/material/fully_damaged");
  }
}

TEST(BrittleSceneKeys, ResidualStiffnessReachesTheMaterialWithinItsRange) {
  Scene s = load_scene(brittle_scene("notched-beam").string());
  s.solids[0].material->residual_stiffness = 0.001;
  EXPECT_EQ(build(s).brittle_solids[0].solid->material.residual_stiffness, 0.001);
  s.solids[0].material->residual_stiffness = 0.2;
  try {
    build(s);
    ADD_FAILURE() << "residual_stiffness 0.2 accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/material/residual_stiffness");
  }
}

TEST(BrittleSceneKeys, HertzImpactDurationFollowsEq311) {
  const Model m = load_model(brittle_scene("spot-impact").string());
  ASSERT_EQ(m.brittle_solids.size(), 1u);
  const model::BrittleBody& b = m.brittle_solids[0];
  ASSERT_FALSE(b.ghosts.empty());
  double impulse = 0;
  for (const auto& g : b.ghosts) impulse += g.force.norm() * (g.end - g.start);
  EXPECT_NEAR(impulse, 12.0, 12.0 * 1e-9);  // the ghosts deliver the scene's impulse (12 N s) exactly
  const double duration = b.ghosts[0].end - b.ghosts[0].start;
  EXPECT_GT(duration, 0.0);
  EXPECT_LT(duration, 1e-2);
}

// breakage_order.smoothing_steps reaches the fracture event: 10 relaxation steps by default, 0 keeps the
// staircase sheets, a negative count is refused with its path.
TEST(BrittleSceneKeys, BreakageOrderSmoothingStepsReachTheEvent) {
  Scene s = load_scene(brittle_scene("notched-beam").string());
  ASSERT_TRUE(s.solids[0].fracture.has_value());
  s.solids[0].fracture->breakage_order = BreakageOrder{};
  EXPECT_EQ(build(s).brittle_solids[0].event.breakage.smoothing.passes, 10);
  EXPECT_TRUE(build(s).brittle_solids[0].event.breakage.enabled);
  s.solids[0].fracture->breakage_order->smoothing_steps = 0;
  EXPECT_EQ(build(s).brittle_solids[0].event.breakage.smoothing.passes, 0);
  s.solids[0].fracture->breakage_order->smoothing_steps = -1;
  try {
    build(s);
    ADD_FAILURE() << "a negative smoothing_steps was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/fracture/breakage_order/smoothing_steps");
  }
}

// fracture.detail reaches the event with Table 3.2's lengths defaulting to fractions of the crack grid
// (h_v = 5 mm here); no height or a share outside [0, 1] is refused at its path.
TEST(BrittleSceneKeys, FractureDetailKeysReachTheEvent) {
  Scene s = load_scene(brittle_scene("notched-beam").string());
  EXPECT_FALSE(build(s).brittle_solids[0].event.detail.enabled());  // off unless asked for
  s.solids[0].fracture->detail = FractureDetail{};
  s.solids[0].fracture->detail->height = 0.001;
  const brittle::FractureDetailOptions d = build(s).brittle_solids[0].event.detail;
  EXPECT_TRUE(d.enabled());
  EXPECT_DOUBLE_EQ(d.height, 0.001);
  EXPECT_DOUBLE_EQ(d.edge, 0.25 * 0.005);
  EXPECT_DOUBLE_EQ(d.step, d.edge);
  EXPECT_DOUBLE_EQ(d.radius, 4 * d.edge);
  EXPECT_DOUBLE_EQ(d.grid, 0.5 * 0.005);
  EXPECT_EQ(d.max_steps, 50);
  EXPECT_DOUBLE_EQ(d.enhanced, 0.1);
  s.solids[0].fracture->detail->enhanced = 1.5;
  try {
    build(s);
    ADD_FAILURE() << "enhanced 1.5 was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/fracture/detail/enhanced");
  }
  s.solids[0].fracture->detail = FractureDetail{};
  try {
    build(s);
    ADD_FAILURE() << "a detail without a height was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/fracture/detail/height");
  }
}

// The phase-field keys reach the material and the solver options; defaults where the scene is silent
// (l0 = 0 means half the grid spacing, r = 1e-3, CG, spline gradient, every step); a phase-field solid
// given Rankine keys or no mobility, or a Rankine solid given a phase-field solve, is refused at its path.
std::string refusal_path(const Scene& s) {
  try {
    build(s);
  } catch (const SceneError& e) {
    return e.json_path();
  }
  return "(accepted)";
}

TEST(BrittleSceneKeys, PhaseFieldKeysReachTheSolver) {
  Scene s = load_scene(brittle_scene("pulled-bar-phase-field").string());
  {
    const Model m = build(s);
    ASSERT_EQ(m.brittle_solids.size(), 1u);
    const model::BrittleBody& b = m.brittle_solids[0];
    EXPECT_EQ(b.solid->material.model, brittle::DamageModel::PhaseField);
    const brittle::PhaseFieldOptions& pf = b.solver.phase_field;
    EXPECT_DOUBLE_EQ(pf.mobility, 2000.0);
    EXPECT_DOUBLE_EQ(pf.length_scale, 0.0);
    EXPECT_DOUBLE_EQ(pf.residual, 1e-3);
    EXPECT_EQ(pf.solver, brittle::PhaseFieldSolver::ConjugateGradient);
    EXPECT_EQ(pf.gradient, brittle::PhaseFieldGradient::Spline);
    EXPECT_EQ(pf.interval, 1u);
  }
  s.solids[0].fracture->phase_field->solver = "cholmod";
  s.solids[0].fracture->phase_field->interval = 3;
  s.solids[0].material->phase_field->length_scale = 0.004;
  {
    const brittle::PhaseFieldOptions& pf = build(s).brittle_solids[0].solver.phase_field;
    EXPECT_EQ(pf.solver, brittle::PhaseFieldSolver::Cholmod);
    EXPECT_EQ(pf.interval, 3u);
    EXPECT_DOUBLE_EQ(pf.length_scale, 0.004);
  }
  Scene bad = s;
  bad.solids[0].material->phase_field->mobility.reset();
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/phase_field/mobility");
  bad = s;
  bad.solids[0].material->phase_field->mobility = -1.0;
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/phase_field/mobility");
  bad = s;
  bad.solids[0].material->failure_stress = 1e5;
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/damage_rule");
  bad = s;
  bad.solids[0].material->residual_stiffness = 1e-3;  // a Rankine key: the phase field has its own residual
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/damage_rule");
  bad = s;
  bad.solids[0].material->damage_model = "rankine";
  bad.solids[0].material->phase_field.reset();
  bad.solids[0].material->failure_stress = 1e5;
  EXPECT_EQ(refusal_path(bad), "/solids/0/fracture/phase_field");
}

// The NACC keys reach the material; defaults where the scene is silent; Rankine and phase-field keys,
// strength scatter and out-of-range parameters are refused at their paths, and "nacc" on another model.
TEST(BrittleSceneKeys, NaccKeysReachTheMaterial) {
  Scene s = load_scene(brittle_scene("pulled-bar-nacc").string());
  {
    const Model m = build(s);
    ASSERT_EQ(m.brittle_solids.size(), 1u);
    const brittle::BrittleMaterial& mat = m.brittle_solids[0].solid->material;
    EXPECT_EQ(mat.model, brittle::DamageModel::Nacc);
    EXPECT_DOUBLE_EQ(mat.nacc.alpha0, -0.02);
    EXPECT_DOUBLE_EQ(mat.nacc.beta, 0.5);
    EXPECT_DOUBLE_EQ(mat.nacc.xi, 1.0);
    EXPECT_DOUBLE_EQ(mat.nacc.friction, 1.0);
    EXPECT_TRUE(mat.nacc.hardening);
  }
  s.solids[0].material->nacc->beta.reset();
  s.solids[0].material->nacc->hardening = false;
  {
    const Model m = build(s);
    const brittle::BrittleMaterial& mat = m.brittle_solids[0].solid->material;
    EXPECT_DOUBLE_EQ(mat.nacc.beta, brittle::NaccParams{}.beta);
    EXPECT_FALSE(mat.nacc.hardening);
  }
  Scene bad = s;
  bad.solids[0].material->nacc->alpha0 = 0.0;
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/nacc/alpha0");
  bad = s;
  bad.solids[0].material->nacc->xi = 0.0;
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/nacc/xi");
  bad = s;
  bad.solids[0].material->nacc->beta = -0.5;
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/nacc/beta");
  bad = s;
  bad.solids[0].material->fracture_energy = 8.0;
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/damage_rule");
  bad = s;
  bad.solids[0].material->damage_model = "rankine";
  bad.solids[0].material->failure_stress = 1e5;
  bad.solids[0].material->fracture_energy = 8.0;
  EXPECT_EQ(refusal_path(bad), "/solids/0/material/nacc");
}

TEST(BrittleSceneKeys, SceneBuiltInCodeIsRefusedLikeTheFile) {
  Scene s = load_scene(brittle_scene("notched-beam").string());
  s.solids[0].impacts.emplace_back();
  s.solids[0].impacts[0].point = Vec3{0, 0.01, 0.04};
  s.solids[0].impacts[0].direction = Vec3{0, 0, -1};
  s.solids[0].impacts[0].impulse = -1.0;
  s.solids[0].impacts[0].duration = 1e-4;
  try {
    build(s);
    ADD_FAILURE() << "a negative impulse was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/impacts/0/impulse");
  }
  s.solids[0].impacts[0].impulse = 1.0;
  s.solids[0].impacts[0].point = Vec3{0.5, 0.01, 0.02};  // 0.4 m beyond the end of the beam
  try {
    build(s);
    ADD_FAILURE() << "an impact off the object was accepted";
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/solids/0/impacts/0");
    EXPECT_NE(e.message().find("impacts must touch the object"), std::string::npos) << e.message();
  }
}

}  // namespace
}  // namespace shellfrac::scene
