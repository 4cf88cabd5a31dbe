// Breakage ordered by the damage time (brittle/breakage_order.*): the crack is taken from the particles
// broken by a chosen time when later damage has filled in the structure the first cracks left.
#include "brittle/breakage_order.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "brittle/fracture_event.hpp"
#include "brittle/primitives.hpp"
#include "crack_fixtures.hpp"

namespace shellfrac::brittle {
namespace {

using testing::DamagedBox;

constexpr double kL = 0.05, kS = 0.005, kH = 0.01;

// A 0.1 m block of particles whose damage history is complete everywhere: the three mid-planes broke
// first (tau 1 ms), everything else later (tau 2 ms), as when the pieces a shattering object fell into
// were crushed before the run stopped.
BrittleSolid octants_then_everything() {
  const DamagedBox box(kL, kS, [](const Vec3&) { return true; });
  BrittleSolid s;
  s.rest = box.x;
  s.damage.resize(box.x.size());
  for (size_t p = 0; p < box.x.size(); ++p) {
    const Vec3& x = box.x[p];
    const bool plane = std::abs(x.x()) < kS || std::abs(x.y()) < kS || std::abs(x.z()) < kS;
    s.damage[p] = ParticleDamage{1.0, 1.0, plane ? 1e-3 : 2e-3};
  }
  return s;
}

CrackExtractionOptions grid_options() {
  CrackExtractionOptions o;
  o.grid.spacing = kH;
  return o;
}

// The whole block is fully damaged, so the medial-surface extraction has no intact structure and the
// block stays one piece; along the valleys of the damage time (the three mid-planes broke first) it
// comes apart into its eight octants, each an eighth of the particles.
TEST(Breakage, FilledInDamageStillGivesThePiecesOfTheFirstCracks) {
  const BrittleSolid s = octants_then_everything();
  const CrackExtractionOptions o = grid_options();
  const CrackExtraction all = extract_crack(s.rest, s.damage_history(), o);
  const CrackExtraction ce = damage_time_crack(s.rest, s.damage, o, 0.1);
  const Regions r = find_regions(ce.diagram, ce.crack_face);
  std::vector<size_t> per = points_per_region(ce.diagram, r, s.rest);
  std::printf("MEASURE breakage: medial surface %zu crack faces, damage-time valleys %d pieces (%d regions)\n",
              all.interior_faces + all.extension_faces, count_pieces(per, 0.01), r.count);
  EXPECT_TRUE(all.empty());  // no crack: the block would stay whole
  per.erase(std::remove(per.begin(), per.end(), size_t{0}), per.end());
  ASSERT_EQ(per.size(), 8u);
  // The crack runs along the planes: every crack face inside the block lies within h_v/2 (plus the
  // jitter of its two sites, 0.05 h_v each) of one of the three mid-planes (a valley one node wide goes
  // to one side of it).
  size_t inside = 0;
  for (size_t f = 0; f < ce.diagram.faces.size(); ++f) {
    const Vec3& c = ce.diagram.faces[f].centroid;
    if (!ce.crack_face[f] || (c.cwiseAbs().array() > kL).any()) continue;
    ++inside;
    EXPECT_LE(c.cwiseAbs().minCoeff(), 0.6 * kH) << c.transpose();
  }
  EXPECT_GT(inside, 0u);
  // Each octant's centre lies in its own region.
  const SiteLocator locate(ce.diagram);
  std::vector<int> seen;
  for (int k = 0; k < 8; ++k) {
    const Vec3 q(k & 1 ? 0.025 : -0.025, k & 2 ? 0.025 : -0.025, k & 4 ? 0.025 : -0.025);
    const int reg = r.cell_region[static_cast<size_t>(locate.cell_of(q))];
    EXPECT_EQ(std::count(seen.begin(), seen.end(), reg), 0) << k;
    seen.push_back(reg);
  }
}

// Through fracture_event: eight closed fragments that keep the block's volume exactly.
TEST(Breakage, FractureEventCutsTheOctantsAndKeepsTheVolume) {
  BrittleSolid s = octants_then_everything();
  s.material.density = 2000;
  TriMesh block = box_mesh(Vec3::Zero(), Vec3::Constant(kL), 2);
  block.name = "block";
  FractureEventOptions o;
  o.crack = grid_options();
  o.breakage.enabled = true;
  o.breakage.min_share = 0.01;
  const FractureEvent ev = fracture_event(s, block, o, "block.obj");
  std::printf("MEASURE breakage event: %zu fragments, volume change %.3g, merged %d\n", ev.fragments.fragments.size(),
              ev.fragments.volume_change(), ev.merged_regions);
  ASSERT_EQ(ev.fragments.fragments.size(), 8u);
  // With each plane's crack within 0.6 h_v of it, an octant's edges are L +- 0.6 h_v long: its share
  // lies between 0.125 (1 - 0.12)^3 and 0.125 (1 + 0.12)^3.
  for (const Fragment& f : ev.fragments.fragments) {
    const double share = f.properties.volume / ev.fragments.input_volume;
    EXPECT_GT(share, 0.125 * std::pow(1 - 0.6 * kH / kL, 3)) << f.mesh.name;
    EXPECT_LT(share, 0.125 * std::pow(1 + 0.6 * kH / kL, 3)) << f.mesh.name;
    EXPECT_TRUE(inspect_mesh(f.mesh).closed()) << f.mesh.name;
  }
  EXPECT_LT(std::abs(ev.fragments.volume_change()), 1e-9);
}

// A slab of damage 1.5 cm below the top face cuts off a thin plate (about 10 % of the block): kept as
// its own region with a 5 % minimum share, merged into the rest with a 20 % one. Regions partition the
// container either way, so the particle counts add up.
TEST(Breakage, RegionsUnderTheMinimumShareJoinTheirNeighbour) {
  const DamagedBox box(kL, kS, [](const Vec3& p) { return std::abs(p.z() - 0.035) < kS; });
  const CrackExtraction ce = extract_crack(box.x, box.c_his, grid_options());
  const Regions r0 = find_regions(ce.diagram, ce.crack_face);
  const std::vector<size_t> per0 = points_per_region(ce.diagram, r0, box.x);
  ASSERT_EQ(count_pieces(per0, 0.05), 2);
  Regions keep = r0, merged = r0;
  merge_small_regions(ce.diagram, keep, per0, 0.05);
  merge_small_regions(ce.diagram, merged, per0, 0.2);
  EXPECT_EQ(count_pieces(points_per_region(ce.diagram, keep, box.x), 0.05), 2);
  const std::vector<size_t> per1 = points_per_region(ce.diagram, merged, box.x);
  EXPECT_EQ(merged.count, 1);
  EXPECT_EQ(std::accumulate(per1.begin(), per1.end(), size_t{0}), box.x.size());
}

// Five cells in a row (sites at x = 0..4), no crack face: one region. With points only in cells 0, 1, 3
// and 4 the region's material parts (0-1 and 3-4) are joined only through the empty cell 2, as a basin of
// the damage time reaching round a crack sheet through the rim outside the object: it is split in two,
// the empty cell going to the part that reaches it first (0-1). Points in every cell, or a crack face
// between cells 1 and 2 (two regions already), leave the regions as they were; a region without points
// stays whole.
TEST(Breakage, RegionsSplitWhereOnlyEmptyCellsJoinThem) {
  std::vector<Vec3> sites;
  for (int i = 0; i < 5; ++i) sites.emplace_back(i, 0.5, 0.5);
  const VoronoiDiagram d = compute_voronoi(sites, Vec3(-0.5, 0, 0), Vec3(4.5, 1, 1));
  std::vector<char> no_crack(d.faces.size(), 0);
  const std::vector<Vec3> ends = {{0, 0.5, 0.5}, {1.1, 0.4, 0.5}, {2.9, 0.5, 0.6}, {4, 0.5, 0.5}};
  Regions r = find_regions(d, no_crack);
  ASSERT_EQ(r.count, 1);
  EXPECT_EQ(split_regions_at_empty_cells(d, no_crack, r, ends), 1);
  ASSERT_EQ(r.count, 2);
  EXPECT_EQ(r.cell_region, (std::vector<int>{0, 0, 0, 1, 1}));

  Regions full = find_regions(d, no_crack);
  EXPECT_EQ(split_regions_at_empty_cells(d, no_crack, full, sites), 0);
  EXPECT_EQ(full.cell_region, (std::vector<int>{0, 0, 0, 0, 0}));

  std::vector<char> cut = no_crack;  // the face between cells 1 and 2
  for (size_t f = 0; f < d.faces.size(); ++f)
    if (!d.faces[f].wall() && std::min(d.faces[f].cell_a, d.faces[f].cell_b) == 1 && std::max(d.faces[f].cell_a, d.faces[f].cell_b) == 2)
      cut[f] = 1;
  Regions two = find_regions(d, cut);
  ASSERT_EQ(two.count, 2);
  EXPECT_EQ(split_regions_at_empty_cells(d, cut, two, ends), 0);
  EXPECT_EQ(two.cell_region, (std::vector<int>{0, 0, 1, 1, 1}));

  Regions none = find_regions(d, no_crack);
  EXPECT_EQ(split_regions_at_empty_cells(d, no_crack, none, {}), 0);
  EXPECT_EQ(none.count, 1);
}

}  // namespace
}  // namespace shellfrac::brittle
