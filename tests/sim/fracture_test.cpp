// Fracture in whole simulations: consistent mode-I tearing, no lost area, fragments that separate with
// phantom nodes and glue without them, and contact between fragments (thesis sec. 4.4-4.7, 4.9).
#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <memory>

#include "core/weibull.hpp"
#include "render_mesh/cracked_tessellation.hpp"
#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "output/frame_render.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::sim {
namespace {

// A 1 m^2 sheet in the xy plane with a notch at v = 0.5 from the left edge; the bottom edge is held and
// the top edge pulled up by 0.15 m over 0.6 s, then held while the fragments relax (thesis Fig. 4.10,
// 4.19a). The rows next to the pins are reinforced so that the sheet tears at the notch, not at the pins.
std::string tear_scene(const std::string& material_extra, const std::string& scene_extra = "") {
  return R"({"name": "tear", "gravity": [0, 0, 0], "damping": 4.0,
    "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [1.0, 1.0], "cells": [16, 16]},
      "thickness": 0.002,
      "material": {"E": 5e5, "nu": 0.3, "density": 500)" + material_extra + R"(,
        "fracture": {"failure_stress": 2e4, "fracture_energy": 60,
          "regions": [{"polygon": [[0, 0], [1, 0], [1, 0.12], [0, 0.12]], "failure_stress": 1e7},
                      {"polygon": [[0, 0.88], [1, 0.88], [1, 1], [0, 1]], "failure_stress": 1e7}]}},
      "cuts": [{"points": [[0.0, 0.5], [0.2, 0.5]]}]}],
    "pins": [{"shell": "sheet", "region": {"v": [0.0, 0.02]}},
             {"shell": "sheet", "region": {"v": [0.98, 1.0]},
              "motion": {"keyframes": [{"time": 0, "translation": [0, 0, 0]},
                                       {"time": 0.6, "translation": [0, 0.15, 0]}]}}])" +
         scene_extra + "}";
}

TEST(Fracture, ModeOneTearIsStraightConsistentAndKeepsItsArea) {
  Simulation sim(scene::build_model(tear_scene(""), "tear.json"));
  // By default (cracking_shells "pic_where_damaged") the sheet never runs PIC as a whole, not even while
  // it tears.
  bool turned_at_some_step = false, damaged_at_some_step = false;
  sim.advance_to(1.2, [&] {
    damaged_at_some_step = damaged_at_some_step || sim.world().shell(0).max_damage() > 0;
    turned_at_some_step = turned_at_some_step || sim.transfer_turned(0);
    return false;
  });
  EXPECT_TRUE(damaged_at_some_step);
  EXPECT_FALSE(turned_at_some_step);
  const CrackStats& st = sim.crack_stats();
  EXPECT_GE(st.extractions, 5);  // extractions run only when the fully damaged set grew
  EXPECT_EQ(st.subset_violations, 0u);  // every extraction contains the previous crack exactly
  const crack2d::CrackGraph& g = *sim.crack_graph(0);
  double u_max = 0, v_dev = 0;
  for (const auto& v : g.vertices()) {
    u_max = std::max(u_max, v.x());
    v_dev = std::max(v_dev, std::abs(v.y() - 0.5));
  }
  EXPECT_GE(u_max, 1.0 - 1e-9);          // torn right through
  EXPECT_LE(v_dev, 2.0 / 16.0);          // within two cells of the straight line
  const auto meshes = output::render_meshes(sim);
  EXPECT_EQ(render_mesh::count_components(meshes[0]), 2);
  // After tearing, the relaxed fragments keep the sheet's area (the thesis reports 0.994 m^2 for its
  // stress, 0.668 m^2 for a 2D deformation gradient). Measured here: 1.011 m^2; the excess is damaged
  // material beside the crack that stays stretched (its tensile stress is fully weakened).
  const double area = render_mesh::surface_area(meshes[0]);
  EXPECT_GE(area, 0.99);
  EXPECT_LE(area, 1.02);
}

// cracking_shells "pic_while_damaged" (the default before 2026-12-07): the sheet runs PIC as a whole
// exactly while some point is damaged: during the tear, and no longer once the healing damage is gone.
TEST(Fracture, PicWhileDamagedTurnsTheWholeSheetExactlyWhileDamaged) {
  Simulation sim(scene::build_model(tear_scene("", R"(, "grid": {"cracking_shells": "pic_while_damaged"})"), "tear.json"));
  bool pic_while_damaged = true, turned_at_some_step = false;
  sim.advance_to(1.2, [&] {
    const bool damaged = sim.world().shell(0).max_damage() > 0;
    turned_at_some_step = turned_at_some_step || sim.transfer_turned(0);
    pic_while_damaged = pic_while_damaged && sim.transfer_turned(0) == damaged;
    return false;
  });
  EXPECT_TRUE(turned_at_some_step);
  EXPECT_TRUE(pic_while_damaged);
  EXPECT_EQ(render_mesh::count_components(output::render_meshes(sim)[0]), 2);
}

// The default (cracking_shells "pic_where_damaged"): while the sheet tears, only the particles whose
// support holds a damaged point run PIC; the rest keep the adaptive shares. Checked at every step of the
// mode-I tear: the shell never turns as a whole, every control point of a damaged cell's support has share
// 0 and no affine velocity after g2p (PIC), and while damaged some control points far from it keep share
// 1 (affine-FLIP, times the scene damping factor). The tear still goes through.
TEST(Fracture, ByDefaultOnlyTheDamagedSupportRunsAsPic) {
  Simulation sim(scene::build_model(tear_scene(""), "tear.json"));
  const World& w = sim.world();
  const shell::ShellPatch& p = w.shell(0);
  const mpm::ParticleSet& control = w.particle_sets()[w.control_set(0)];
  size_t damaged_steps = 0, pic_checked = 0, flip_while_damaged = 0, nonzero_affine_elsewhere = 0;
  bool turned = false, pic_broken = false;
  sim.advance_to(1.2, [&] {
    turned = turned || sim.transfer_turned(0);
    const size_t layers = static_cast<size_t>(p.num_layers());
    std::vector<unsigned char> in_damaged_support(p.num_control_points(), 0);
    bool damaged = false;
    for (size_t q = 0; q < p.num_inplane_points(); ++q) {
      bool hit = false;
      for (size_t l = 0; l < layers; ++l) hit = hit || p.damage_values()[q * layers + l] > 0;
      if (!hit) continue;
      damaged = true;
      const int* ids = p.support(p.cell_of(q));
      for (int j = 0; j < p.support_size(); ++j) in_damaged_support[static_cast<size_t>(ids[j])] = 1;
    }
    if (!damaged) return false;
    ++damaged_steps;
    for (size_t k = 0; k < control.count; ++k) {
      if (in_damaged_support[k]) {
        ++pic_checked;
        pic_broken = pic_broken || control.flip_share[k] != 0.0 || control.affine[k].norm() != 0.0;
      } else {
        flip_while_damaged += control.flip_share[k] > 0.99;  // 1 x the damping factor exp(-4 dt)
        nonzero_affine_elsewhere += control.affine[k].norm() > 0.0;
      }
    }
    return false;
  });
  EXPECT_FALSE(turned);
  EXPECT_GT(damaged_steps, 0u);
  EXPECT_GT(pic_checked, 0u);
  EXPECT_FALSE(pic_broken);
  EXPECT_GT(flip_while_damaged, 0u);
  EXPECT_GT(nonzero_affine_elsewhere, 0u);
  EXPECT_EQ(render_mesh::count_components(output::render_meshes(sim)[0]), 2);
}

// The run's frame renderer keeps each cracked patch's vertex bases until its crack changes: at every
// frame of the mode-I tear, while the crack grows and after, its meshes equal a fresh render's exactly
// (positions, faces, and the rest positions of the quality metrics).
TEST(Fracture, KeptRenderBasesGiveTheFreshMeshAsTheCrackGrows) {
  Simulation sim(scene::build_model(tear_scene(""), "tear.json"));
  output::FrameRenderer renderer;
  size_t edges_seen = 0, changes = 0;
  for (int frame = 1; frame <= 24; ++frame) {
    sim.advance_to(0.05 * frame);
    const crack2d::CrackGraph* g = sim.crack_graph(0);
    const size_t edges = g ? g->num_edges() : 0;
    changes += edges != edges_seen;
    edges_seen = edges;
    const output::FrameMeshes kept = renderer.render(sim), fresh = output::render_frame(sim);
    ASSERT_EQ(kept.meshes.size(), fresh.meshes.size());
    EXPECT_EQ(kept.meshes[0].positions, fresh.meshes[0].positions) << "frame " << frame;
    EXPECT_EQ(kept.meshes[0].face_vertices, fresh.meshes[0].face_vertices) << "frame " << frame;
    EXPECT_EQ(kept.rest, fresh.rest) << "frame " << frame;
  }
  EXPECT_GE(changes, 3u);  // the crack grew between frames: the kept bases were rebuilt
}

// A 0.4 x 0.2 m sheet cut through at u = 0.5; the halves get opposite x velocities.
// fracture.weibull: every in-plane point's sigma_f is its material or region value times its own seeded
// Weibull factor; H (the softening slope) stays the point's. Checked against the inverse CDF written out
// here, against the Weibull CDF itself (Kolmogorov-Smirnov), and across seeds.
TEST(Fracture, WeibullStrengthGivesEachPointItsOwnSeededFailureStress) {
  auto build = [](int seed) {
    std::string s = tear_scene("");
    const std::string regions_end = R"("failure_stress": 1e7}]}},)";
    const size_t at = s.find(regions_end);
    EXPECT_NE(at, std::string::npos);
    s.replace(at, regions_end.size(),
              R"("failure_stress": 1e7}], "weibull": {"modulus": 8, "seed": )" + std::to_string(seed) + "}}},");
    return std::make_unique<Simulation>(scene::build_model(s, "weibull.json"));
  };
  const Simulation plain(scene::build_model(tear_scene(""), "tear.json"));
  const std::unique_ptr<Simulation> a = build(7), b = build(8);
  const shell::ShellPatch& p0 = plain.world().shell(0);
  const shell::ShellPatch& pa = a->world().shell(0);
  const shell::ShellPatch& pb = b->world().shell(0);
  const size_t n = p0.num_inplane_points();
  ASSERT_EQ(pa.num_inplane_points(), n);
  const double m = 8.0;
  std::vector<double> bulk;  // factors of the points outside the reinforced bands
  size_t differ = 0;
  for (size_t q = 0; q < n; ++q) {
    // Inverse CDF, P(s <= x) = 1 - exp(-(x / s0)^m), from the point's uniform draw.
    const double u = core::hashed_uniform(7, q);
    const double expected = p0.failure_stress(q) * std::pow(-std::log(1.0 - u), 1.0 / m);
    EXPECT_NEAR(pa.failure_stress(q), expected, 1e-12 * expected) << "point " << q;
    EXPECT_EQ(pa.brittleness(q), p0.brittleness(q)) << "point " << q;  // H is kept
    if (p0.failure_stress(q) == 2e4) bulk.push_back(pa.failure_stress(q) / 2e4);
    differ += pb.failure_stress(q) != pa.failure_stress(q);
  }
  EXPECT_EQ(differ, n);  // another seed, another field
  // Kolmogorov-Smirnov distance of the bulk factors from the unit Weibull CDF; 1.63 / sqrt(N) is the 1%
  // critical value.
  std::sort(bulk.begin(), bulk.end());
  double d = 0;
  for (size_t i = 0; i < bulk.size(); ++i) {
    const double cdf = 1.0 - std::exp(-std::pow(bulk[i], m));
    d = std::max({d, cdf - static_cast<double>(i) / bulk.size(), static_cast<double>(i + 1) / bulk.size() - cdf});
  }
  ASSERT_GT(bulk.size(), 500u);
  EXPECT_LT(d, 1.63 / std::sqrt(static_cast<double>(bulk.size())));
}

std::string cut_sheet_scene(bool phantom_nodes) {
  return std::string(R"({"name": "cut", "gravity": [0, 0, 0],
    "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [0.4, 0.2], "cells": [16, 8]},
      "thickness": 0.001, "material": {"E": 1e5, "nu": 0.3, "density": 200},
      "cuts": [{"points": [[0.5, 0.0], [0.5, 1.0]]}]}],
    "cracks": {"contact_friction": 0.0, "phantom_nodes": )") +
         (phantom_nodes ? "true" : "false") + "}}";
}

struct Halves {
  double left_mean, right_mean, left_max, right_min;
};

Halves halves(const shell::ShellPatch& p) {
  Halves h{0, 0, -1e9, 1e9};
  int nl = 0, nr = 0;
  for (size_t k = 0; k < p.x.size(); ++k) {
    if (p.control_parameter(k).x() < 0.5) {
      h.left_mean += p.x[k].x();
      h.left_max = std::max(h.left_max, p.x[k].x());
      ++nl;
    } else {
      h.right_mean += p.x[k].x();
      h.right_min = std::min(h.right_min, p.x[k].x());
      ++nr;
    }
  }
  h.left_mean /= nl;
  h.right_mean /= nr;
  return h;
}

void set_half_velocities(Simulation& sim, double vx) {
  const shell::ShellPatch& p = sim.world().shell(0);
  const auto v = sim.velocities(0), shear_v = sim.shear_velocities(0);
  for (size_t k = 0; k < p.x.size(); ++k) v[k] = Eigen::Vector3d(p.control_parameter(k).x() < 0.5 ? -vx : vx, 0, 0);
  for (size_t c = 0; c < p.shear.x.size(); ++c)
    shear_v[c] = Eigen::Vector3d(p.shear_parameter(c).x() < 0.5 ? -vx : vx, 0, 0);
}

TEST(Fracture, PhantomNodesLetFragmentsSeparateASingleFieldGluesThem) {
  double opened[2];
  for (int phantom = 0; phantom < 2; ++phantom) {
    Simulation sim(scene::build_model(cut_sheet_scene(phantom == 1), "cut.json"));
    const auto& p = sim.world().shell(0);
    EXPECT_GT(p.num_mls_points(), 0u);
    set_half_velocities(sim, 0.5);
    const Halves before = halves(p);
    sim.advance_to(0.1);
    const Halves after = halves(p);
    opened[phantom] = (after.right_mean - after.left_mean) - (before.right_mean - before.left_mean);
  }
  // Free flight apart at 1 m/s relative speed for 0.1 s opens 0.1 m; a shared velocity field ties the
  // crack faces together and the halves stop within an elastic wave transit (0.2 m / 22 m/s).
  EXPECT_NEAR(opened[1], 0.1, 0.01);
  EXPECT_LT(opened[0], 0.02);
}

TEST(Fracture, FragmentsPressedTogetherDoNotInterpenetrate) {
  Simulation sim(scene::build_model(cut_sheet_scene(true), "cut.json"));
  const auto& p = sim.world().shell(0);
  set_half_velocities(sim, -0.5);  // towards each other at 1 m/s: 0.05 m of overlap in 0.05 s if unchecked
  const Eigen::Vector3d momentum = sim.linear_momentum();
  const Halves before = halves(p);
  EXPECT_NEAR(before.right_min - before.left_max, 0.025, 1e-12);  // nearest control points across the cut
  sim.advance_to(0.05);
  const Halves after = halves(p);
  EXPECT_GE(after.right_min - after.left_max, -0.5 * sim.dx());
  EXPECT_GT(sim.crack_stats().contact_pairs, 0u);
  EXPECT_LE((sim.linear_momentum() - momentum).norm(), 1e-10);  // contact forces are equal and opposite
}

TEST(Fracture, TearingIsBitIdenticalForAnyThreadCount) {
  // Damage, crack extraction, MLS updates, the phantom partition and contact all run in parallel; the
  // result must not depend on the thread count.
  const scene::Model scene = scene::build_model(tear_scene(""), "tear.json");
  auto run = [&](int threads) {
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    Simulation sim(scene);
    sim.advance_to(0.45);
    EXPECT_GT(sim.crack_graph(0)->num_edges(), 10u);
    return sim.world().shell(0).x;
  };
  const auto one = run(1), two = run(2);
  bool identical = one.size() == two.size();
  for (size_t k = 0; identical && k < one.size(); ++k) identical = one[k] == two[k];
  EXPECT_TRUE(identical);
}

TEST(Fracture, ShapeCutOutOfAHangingClothFallsAway) {
  // Thesis Fig. 4.14: a shape cut out of a cloth falls away under gravity. The cloth hangs level from
  // its four edges, so the shape drops out of the plane (a vertical cloth would hold the shape on the
  // hole's lower edge: the fragments are coplanar and in-plane contact is real contact).
  Simulation sim(scene::build_model(R"({"name": "cutout", "gravity": [0, -9.81, 0],
    "shells": [{"name": "cloth", "patch": {"type": "flat", "size": [0.6, 0.6], "cells": [12, 12],
                "origin": [0, 1, 0], "axis_u": [1, 0, 0], "axis_v": [0, 0, 1]},
      "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 200},
      "cuts": [{"closed": true, "points": [[0.3, 0.3], [0.7, 0.3], [0.7, 0.7], [0.35, 0.6], [0.3, 0.7]]}]}],
    "pins": [{"shell": "cloth", "region": {"v": [0.0, 0.02]}}, {"shell": "cloth", "region": {"v": [0.98, 1.0]}},
             {"shell": "cloth", "region": {"u": [0.0, 0.02]}}, {"shell": "cloth", "region": {"u": [0.98, 1.0]}}]})",
                             "cutout.json"));
  const auto& p = sim.world().shell(0);
  const std::vector<Eigen::Vector2d> shape{{0.3, 0.3}, {0.7, 0.3}, {0.7, 0.7}, {0.35, 0.6}, {0.3, 0.7}};
  auto inside = [&](const Eigen::Vector2d& q) {  // crossing-number test
    bool in = false;
    for (size_t i = 0, j = shape.size() - 1; i < shape.size(); j = i++)
      if ((shape[i].y() > q.y()) != (shape[j].y() > q.y()) &&
          q.x() < shape[i].x() + (q.y() - shape[i].y()) * (shape[j].x() - shape[i].x()) / (shape[j].y() - shape[i].y()))
        in = !in;
    return in;
  };
  auto inner_centre = [&] {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    double m = 0;
    for (size_t k = 0; k < p.x.size(); ++k) {
      if (inside(p.control_parameter(k))) {
        c += p.mass[k] * p.x[k];
        m += p.mass[k];
      }
    }
    return Eigen::Vector3d(c / m);
  };
  const double y0 = inner_centre().y();
  sim.advance_to(1.0);
  const double fall = y0 - inner_centre().y();
  EXPECT_GE(fall, 0.8 * 0.5 * 9.81);  // at least 80% of free fall in 1 s
  EXPECT_EQ(render_mesh::count_components(output::render_meshes(sim)[0]), 2);  // the shape and the cloth: no glue
}

}  // namespace
}  // namespace shellfrac::sim
