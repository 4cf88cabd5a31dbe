// The resource estimate (scene/estimate.hpp): element counts against the built simulation (an
// independent computation; flat, control-net, cylinder and cone patches), the stable step against the simulation's bound, and the refusals of
// memory bombs and endless runs, which must come from the estimate alone (nothing is allocated).
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <climits>
#include <cstdio>

#include "mpm/level_set_shape.hpp"
#include "scene/build.hpp"
#include "scene/estimate.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::scene {
namespace {

using ::testing::HasSubstr;

double count_of(const ResourceEstimate& e, const std::string& what) {
  double n = 0;
  for (const ResourceItem& item : e.memory)
    if (item.what.find(what) != std::string::npos) n += item.count;
  return n;
}

std::string sheet_scene(const std::string& patch, const std::string& extra = "", const std::string& shell_extra = "",
                        const std::string& time = R"({"end": 0.1, "frame_rate": 30})") {
  return R"({"time": )" + time + R"(, "output": {"resolution": [4, 4]}, )" + extra +
         R"("shells": [{"name": "s", "patch": )" + patch + R"(, "thickness": 0.001, )" + shell_extra +
         R"("material": {"E": 1e5, "nu": 0.3, "density": 200}}]})";
}

TEST(Estimate, ShellCountsMatchTheBuiltSimulation) {
  for (const std::string& patch :
       {std::string(R"({"type": "flat", "size": [1, 2], "cells": [5, 7]})"),
        std::string(R"({"type": "control_net", "degree": [2, 1], "knots_u": [0, 0, 0, 1, 1, 1], "knots_v": [0, 0, 1, 1],
             "control_points": [[0,0,0],[1,0,0],[2,0,0],[0,1,0],[1,1,0.2],[2,1,0]], "refine": [3, 4]})")}) {
    const Scene scene = read_scene(sheet_scene(patch, "", R"("quadrature": {"points": 3},)"), "t");
    const ResourceEstimate e = estimate_resources(scene);
    const sim::Simulation sim(build(scene));
    EXPECT_EQ(count_of(e, "control points"), static_cast<double>(sim.num_control_points())) << patch;
    EXPECT_EQ(count_of(e, "quadrature points"), static_cast<double>(sim.num_quadrature_points())) << patch;
    EXPECT_EQ(count_of(e, "shear particles"), static_cast<double>(sim.num_shear_particles())) << patch;
  }
}

// Raised degrees: control points of flat, cylinder and cone patches at degrees 3 and 4 (and 5 x 2), a
// control net elevated and refined, and the default quadrature of p + 1 points per direction above p = 3.
TEST(Estimate, ShellCountsAtRaisedDegreesMatchTheBuiltSimulation) {
  for (const std::string& patch :
       {std::string(R"({"type": "flat", "size": [1, 2], "cells": [5, 7], "degree": [3, 4]})"),
        std::string(R"({"type": "flat", "size": [1, 2], "cells": [3, 2], "degree": [5, 2]})"),
        std::string(R"({"type": "cylinder", "radius": 0.3, "height": 1, "cells": [9, 4], "degree": [3, 3]})"),
        std::string(R"({"type": "cone", "radius_bottom": 0.3, "radius_top": 0.1, "height": 1, "sweep_degrees": 200,
             "cells": [7, 3], "degree": [4, 2]})"),
        std::string(R"({"type": "control_net", "degree": [2, 1], "knots_u": [0, 0, 0, 0.5, 1, 1, 1], "knots_v": [0, 0, 1, 1],
             "control_points": [[0,0,0],[1,0,0],[2,0,0],[3,0,0],[0,1,0],[1,1,0.2],[2,1,0],[3,1,0]], "elevate": [1, 2],
             "refine": [2, 3]})")}) {
    const Scene scene = read_scene(sheet_scene(patch), "t");
    const ResourceEstimate e = estimate_resources(scene);
    const sim::Simulation sim(build(scene));
    EXPECT_EQ(count_of(e, "control points"), static_cast<double>(sim.num_control_points())) << patch;
    EXPECT_EQ(count_of(e, "quadrature points"), static_cast<double>(sim.num_quadrature_points())) << patch;
    EXPECT_EQ(count_of(e, "shear particles"), static_cast<double>(sim.num_shear_particles())) << patch;
  }
}

TEST(Estimate, StepMatchesTheSimulationsStabilityBound) {
  // A flat sheet: the cell size sqrt(area / cells) and the wave speed are those of sim::Simulation, so
  // the estimated step is cfl x the elastic-wave bound to rounding.
  const Scene scene = read_scene(sheet_scene(R"({"type": "flat", "size": [1, 2], "cells": [5, 7]})"), "t");
  const ResourceEstimate e = estimate_resources(scene);
  const sim::Simulation sim(build(scene));
  EXPECT_NEAR(e.dt, 0.5 * sim.elastic_wave_bound(), 1e-12 * e.dt);
  EXPECT_NEAR(e.grid_dx, sim.dx(), 1e-12 * sim.dx());
  EXPECT_EQ(e.frames, 4);  // 0.1 s at 30 frames/s: frames 0..3
  EXPECT_NEAR(e.steps, 0.1 / e.dt, 1e-9 * e.steps);
}

TEST(Estimate, SolidParticlesWithinTenPercent) {
  // Jittered sampling puts one particle per spacing^3 cell inside the box: 0.4^3 / 0.02^3 = 8000.
  const Scene scene = read_scene(std::string(R"({"time": {"end": 0.01}, "solids": [{"shape": "box", "center": [0, 0, 0],
      "half_extents": [0.2, 0.2, 0.2], "spacing": 0.02, "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})"), "t");
  const ResourceEstimate e = estimate_resources(scene);
  const sim::Simulation sim(build(scene));
  EXPECT_NEAR(count_of(e, "particles"), 8000.0, 1e-6);
  EXPECT_NEAR(static_cast<double>(sim.num_solid_particles()), count_of(e, "particles"), 0.1 * 8000);
}

// The solid and level-set counts of the estimate (from the shape's volume, the mesh's area
// and the voxel size; nothing is sampled or built) against what the build makes, within 30%.
TEST(Estimate, BoxSolidParticlesAtAModerateSpacingWithinThirtyPercent) {
  // 0.3^3 m^3 / 0.005^3 m^3 = 216000 particles.
  const Scene scene = read_scene(std::string(R"({"time": {"end": 0.01}, "solids": [{"shape": "box", "center": [0, 0, 0],
      "half_extents": [0.15, 0.15, 0.15], "spacing": 0.005, "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})"), "t");
  const ResourceEstimate e = estimate_resources(scene);
  EXPECT_NEAR(count_of(e, "particles"), 216000.0, 1.0);
  const sim::Simulation sim(build(scene));
  const double built = static_cast<double>(sim.num_solid_particles());
  std::printf("box solid, spacing 0.005: estimated %.0f particles, built %.0f\n", count_of(e, "particles"), built);
  EXPECT_NEAR(count_of(e, "particles"), built, 0.3 * built);
}

// The ellipsoid mesh scaled to 0.2 m, as a solid and as a collider.
std::string mesh_key(double voxel) {
  return R"("file": ")" + std::string(SHELLFRAC_SOURCE_DIR) + R"(/scenes/meshes/ellipsoid.obj", "scale": 0.3333333, "voxel_size": )" +
         std::to_string(voxel);
}

size_t active_voxels(const std::shared_ptr<const mpm::Shape>& shape) {
  const auto* level_set = dynamic_cast<const mpm::LevelSetShape*>(shape.get());
  return level_set ? level_set->active_voxels() : 0;
}

TEST(Estimate, MeshSolidParticlesAndVoxelsWithinThirtyPercent) {
  for (const double voxel : {0.004, 0.002, 0.001}) {
    const Scene scene = read_scene(R"({"time": {"end": 0.01}, "solids": [{"shape": "mesh", )" + mesh_key(voxel) +
                                       R"(, "spacing": 0.005, "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})",
                                   "t");
    const ResourceEstimate e = estimate_resources(scene);
    const Model model = build(scene);
    const double voxels = static_cast<double>(active_voxels(model.solids[0].geometry));
    const sim::Simulation sim(model);
    const double particles = static_cast<double>(sim.num_solid_particles());
    std::printf("mesh solid, voxel %g: estimated %.0f voxels, built %.0f; estimated %.0f particles, built %.0f\n", voxel,
                count_of(e, "level-set voxels"), voxels, count_of(e, "particles"), particles);
    EXPECT_NEAR(count_of(e, "level-set voxels"), voxels, 0.3 * voxels) << voxel;
    EXPECT_NEAR(count_of(e, "particles"), particles, 0.3 * particles) << voxel;
  }
}

TEST(Estimate, MeshColliderVoxelsWithinThirtyPercent) {
  for (const double voxel : {0.002, 0.0005}) {
    const Scene scene =
        read_scene(sheet_scene(R"({"type": "flat", "size": [1, 1], "cells": [2, 2]})",
                               R"("colliders": [{"shape": "mesh", )" + mesh_key(voxel) + R"(, "band_voxels": 2}], )"),
                   "t");
    const ResourceEstimate e = estimate_resources(scene);
    const double voxels = static_cast<double>(active_voxels(build(scene).colliders[0].collider.shape));
    std::printf("mesh collider, voxel %g, band 2: estimated %.0f voxels, built %.0f\n", voxel, count_of(e, "level-set voxels"), voxels);
    EXPECT_NEAR(count_of(e, "level-set voxels"), voxels, 0.3 * voxels) << voxel;
  }
}

// The error check_budget gives with an 8 GiB budget and no force.
SceneError refusal(const std::string& text, bool force = false) {
  ResourceBudget budget;
  budget.memory_bytes = 8.0 * (1u << 30);
  budget.force = force;
  try {
    check_budget(estimate_resources(read_scene(text, "bomb.json")), budget, "bomb.json");
  } catch (const SceneError& e) {
    return e;
  }
  ADD_FAILURE() << "accepted: " << text;
  return SceneError("", "", "");
}

TEST(Estimate, MemoryBombsAreRefusedNamingTheValue) {
  // Each of these once passed 8 GB and was killed; the estimate refuses them at once.
  const SceneError cells = refusal(sheet_scene(R"({"type": "flat", "size": [1, 1], "cells": [10000, 10000]})"));
  EXPECT_EQ(cells.json_path(), "/shells/0/patch/cells");
  EXPECT_THAT(cells.message(), HasSubstr("more than the budget of 8.0 GiB"));
  EXPECT_THAT(cells.message(), HasSubstr("quadrature points"));
  // A 101-span control net refined 64 x 64.
  std::string knots = "[0, 0";
  for (int i = 1; i < 101; ++i) knots += ", " + std::to_string(i);
  knots += ", 101, 101]";
  std::string points;
  for (int j = 0; j < 102; ++j)
    for (int i = 0; i < 102; ++i) points += std::string(points.empty() ? "" : ",") + "[" + std::to_string(i) + "," + std::to_string(j) + ",0]";
  const SceneError net = refusal(sheet_scene(R"({"type": "control_net", "degree": [1, 1], "knots_u": )" + knots +
                                             R"(, "knots_v": )" + knots + R"(, "control_points": [)" + points +
                                             R"(], "refine": [64, 64]})"));
  EXPECT_EQ(net.json_path(), "/shells/0/patch/refine");
  const SceneError box = refusal(std::string(R"({"solids": [{"shape": "box", "center": [0, 0, 0], "half_extents": [1.8, 1.8, 1.8],
      "spacing": 0.01, "material": {"E": 1e5, "nu": 0.3, "density": 100}}]})"));
  EXPECT_EQ(box.json_path(), "/solids/0/spacing");
}

TEST(Estimate, RenderResolutionAndVoxelSizeDriveMemory) {
  std::string three = R"({"output": {"resolution": [4096, 4096]}, "shells": [)";
  for (int i = 0; i < 3; ++i)
    three += std::string(i ? "," : "") + R"({"patch": {"type": "flat", "size": [1, 1], "cells": [2, 2]},
      "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 100}})";
  const SceneError r = refusal(three + "]}");
  EXPECT_EQ(r.json_path(), "/output/resolution");
  EXPECT_THAT(r.message(), HasSubstr("render vertices"));
}

TEST(Estimate, TinyVoxelSizeIsRefusedBeforeTheLevelSet) {
  // voxel_size 3e-5 once grew past 4 GB in OpenVDB; the ellipsoid's area (about 0.6 m^2) over
  // voxel^2 times the 6-voxel band is billions of voxels.
  const std::string mesh = std::string(SHELLFRAC_SOURCE_DIR) + "/scenes/meshes/ellipsoid.obj";
  const SceneError e = refusal(sheet_scene(R"({"type": "flat", "size": [1, 1], "cells": [2, 2]})",
                                           R"("colliders": [{"shape": "mesh", "file": ")" + mesh + R"(", "voxel_size": 3e-5}], )"));
  EXPECT_EQ(e.json_path(), "/colliders/0/voxel_size");
  EXPECT_THAT(e.message(), HasSubstr("level-set voxels"));
}

TEST(Estimate, TinyGridSpacingCannotHoldTheScene) {
  try {
    estimate_resources(read_scene(sheet_scene(R"({"type": "flat", "size": [1, 1], "cells": [2, 2]})", R"("grid": {"dx": 1e-9}, )"), "t"));
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/grid/dx");
    EXPECT_THAT(e.message(), HasSubstr("cannot hold the scene"));
  }
}

TEST(Estimate, EndlessRunsNeedForce) {
  const std::string patch = R"({"type": "flat", "size": [1, 1], "cells": [2, 2]})";
  auto with_time = [&](const std::string& time) { return sheet_scene(patch, "", "", time); };
  EXPECT_EQ(refusal(with_time(R"({"end": 1, "dt": 1e-300})")).json_path(), "/time/dt");
  EXPECT_EQ(refusal(with_time(R"({"end": 1, "cfl": 1e-300})")).json_path(), "/time/cfl");
  EXPECT_EQ(refusal(with_time(R"({"end": 1e300})")).json_path(), "/time/end");
  EXPECT_EQ(refusal(with_time(R"({"end": 1, "frame_rate": 1e9})")).json_path(), "/time/frame_rate");
  const SceneError stiff = refusal(sheet_scene(patch).replace(sheet_scene(patch).find("1e5"), 3, "1e300"));
  EXPECT_EQ(stiff.json_path(), "/shells/0/material/E");
  EXPECT_THAT(stiff.message(), HasSubstr("--force"));
  const SceneError light = refusal(sheet_scene(patch).replace(sheet_scene(patch).find("200}"), 3, "1e-300"));
  EXPECT_EQ(light.json_path(), "/shells/0/material/density");
  const SceneError fast = refusal(sheet_scene(patch, "", R"("initial_velocity": [0, 1e30, 0], )"));
  EXPECT_EQ(fast.json_path(), "/shells/0/initial_velocity");
  // --force lifts step and frame budgets, but not a frame count no int holds.
  ResourceBudget forced;
  forced.force = true;
  EXPECT_NO_THROW(check_budget(estimate_resources(read_scene(with_time(R"({"end": 1, "frame_rate": 1e9})"), "t")), forced, "t"));
  const SceneError never = refusal(with_time(R"({"end": 1e300})"), true);
  EXPECT_THAT(never.message(), HasSubstr(std::to_string(INT_MAX)));
}

TEST(Estimate, CylinderAndConeCountsMatchTheAllocatedOnes) {
  // Curved patches: the control points of the rational arcs (pieces of at most 90 degrees), and the grid
  // nodes the built simulation activates at its first step (control points and shear particles on the
  // grid, the blocks of their stencils and the forward neighbours). The grid need only be within
  // 20%; counting the blocks from the particle positions gives them exactly (measured: equal for all five).
  for (const std::string& patch :
       {std::string(R"({"type": "flat", "size": [1, 2], "cells": [5, 7]})"),
        std::string(R"({"type": "cylinder", "radius": 0.3, "height": 1.0, "cells": [24, 8]})"),
        std::string(R"({"type": "cylinder", "radius": 0.3, "height": 1.0, "sweep_degrees": 180, "cells": [12, 8]})"),
        std::string(R"({"type": "cone", "radius_bottom": 0.4, "radius_top": 0.1, "height": 0.8, "cells": [24, 8]})"),
        std::string(R"({"type": "cone", "radius_bottom": 0.4, "radius_top": 0.0, "height": 0.8, "cells": [32, 12]})")}) {
    const Scene scene = read_scene(sheet_scene(patch), "t");
    const ResourceEstimate e = estimate_resources(scene);
    sim::Simulation sim(build(scene));
    sim.step(sim.stable_dt());
    EXPECT_EQ(count_of(e, "control points"), static_cast<double>(sim.num_control_points())) << patch;
    EXPECT_EQ(count_of(e, "quadrature points"), static_cast<double>(sim.num_quadrature_points())) << patch;
    EXPECT_EQ(count_of(e, "shear particles"), static_cast<double>(sim.num_shear_particles())) << patch;
    const double nodes = static_cast<double>(sim.num_grid_nodes());
    EXPECT_NEAR(count_of(e, "grid nodes"), nodes, 0.2 * nodes) << patch;
    EXPECT_NEAR(e.grid_dx, sim.dx(), 1e-12 * sim.dx()) << patch;
    EXPECT_NEAR(e.dt, 0.5 * sim.elastic_wave_bound(), 1e-12 * e.dt) << patch;
  }
}

TEST(Estimate, FreeDiskBudget) {
  const ResourceEstimate e = estimate_resources(read_scene(sheet_scene(R"({"type": "flat", "size": [1, 1], "cells": [2, 2]})"), "t"));
  ResourceBudget b;
  b.free_disk_bytes = e.disk_bytes / 2;
  EXPECT_THROW(check_budget(e, b, "t"), SceneError);
  b.force = true;
  EXPECT_NO_THROW(check_budget(e, b, "t"));
  EXPECT_EQ(format_bytes(1536), "1.5 KiB");
  EXPECT_EQ(format_bytes(3.0 * (1u << 30)), "3.0 GiB");
}

}  // namespace
}  // namespace shellfrac::scene
