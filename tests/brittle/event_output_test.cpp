// Per-event outputs: the fracture event of a sampled solid, its summary, and the particles as OpenVDB
// Points.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "brittle/fracture_event.hpp"
#include "brittle/particles_vdb.hpp"
#include "brittle_test_helpers.hpp"

namespace shellfrac::brittle {
namespace {

constexpr double kL = 0.05, kS = 0.005, kH = 0.01;

TEST(FractureEvent, SlabThroughASampledBlockGivesTwoHalvesAndASummary) {
  const TriMesh block = [] {
    TriMesh m = box_mesh(Vec3::Zero(), Vec3::Constant(kL), 2);
    m.name = "block";
    return m;
  }();
  BrittleSolid solid = make_solid(block, testing::soft_material(), kS, Sampling::Regular, 1, "block.obj");
  solid.set_strength({}, WeibullStrength{}, kH);
  for (size_t p = 0; p < solid.size(); ++p)
    if (std::abs(solid.rest[p].z()) < kS) solid.damage[p].c_his = 1.0;
  FractureEventOptions o;
  o.crack.grid.spacing = kH;
  o.fragments.cutter = Cutter::Exact;
  const FractureEvent ev = fracture_event(solid, block, o, "block.obj");
  ASSERT_EQ(ev.fragments.fragments.size(), 2u);
  EXPECT_LT(std::abs(ev.fragments.volume_change()), 1e-9);
  EXPECT_NEAR(surface_area(ev.crack_surface_clipped), 4 * kL * kL, 0.05 * 4 * kL * kL);
  const nlohmann::json j = fracture_summary(ev);
  EXPECT_EQ(j["fragments"]["count"], 2);
  EXPECT_EQ(j["fragments"]["fragments"][0]["name"], "block_fragment_0");
  // Masses use the solid's density and add up to the block's.
  const double mass = j["fragments"]["fragments"][0]["mass"].get<double>() + j["fragments"]["fragments"][1]["mass"].get<double>();
  EXPECT_NEAR(mass, 1000 * 8 * kL * kL * kL, 1e-9);
  EXPECT_EQ(j["damaged_particles"], solid.count_damaged());
  EXPECT_GT(j["node_sets"]["I"].get<size_t>(), 0u);
}

TEST(ParticlesVdb, WritesAndReadsBackEveryAttribute) {
  BrittleSolid solid = testing::lattice_box(Vec3::Zero(), Vec3(0.02, 0.01, 0.01), kS, testing::soft_material(), kH);
  for (size_t p = 0; p < solid.size(); ++p) {
    solid.particles.x[p] += Vec3(0.001 * p, 0, 0);
    solid.particles.v[p] = Vec3(0.1, -0.2 * p, 0.3);
    solid.damage[p] = {0.5, p % 2 ? 1.0 : 0.25, p % 2 ? 0.001 * p : -1.0};
  }
  const std::filesystem::path file = std::filesystem::temp_directory_path() / "shellfrac_brittle_points_test.vdb";
  std::ofstream(file, std::ios::binary) << particles_vdb_bytes(solid);
  const ParticlePoints back = read_particles_vdb(file);
  ASSERT_EQ(back.position.size(), solid.size());
  for (size_t p = 0; p < solid.size(); ++p) {
    // Positions are stored as voxel-relative floats: about 1e-7 of the voxel.
    EXPECT_LT((back.position[p] - solid.particles.x[p]).norm(), 1e-6) << p;
    EXPECT_LT((back.velocity[p] - solid.particles.v[p]).norm(), 1e-6 * (1 + solid.particles.v[p].norm())) << p;
    EXPECT_FLOAT_EQ(back.damage[p], 0.5f);
    EXPECT_FLOAT_EQ(back.c_his[p], static_cast<float>(solid.damage[p].c_his));
    EXPECT_FLOAT_EQ(back.tau[p], static_cast<float>(solid.damage[p].tau));
  }
  std::filesystem::remove(file);
}

}  // namespace
}  // namespace shellfrac::brittle
