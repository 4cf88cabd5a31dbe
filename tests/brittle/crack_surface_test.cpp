// Crack surface extraction (thesis sec. 3.3) and Voronoi regions (sec. 3.5.1) on synthetic damage.
#include "brittle/crack_surface.hpp"

#include <gtest/gtest.h>

#include <cstdio>

#include "brittle/errors.hpp"
#include "brittle/regions.hpp"
#include "crack_fixtures.hpp"

namespace shellfrac::brittle {
namespace {

using testing::DamagedBox;

constexpr double kL = 0.05, kS = 0.005, kH = 0.01;  // box half size, particle spacing, h_v

CrackExtractionOptions options() {
  CrackExtractionOptions o;
  o.grid.spacing = kH;
  return o;
}

// Number of regions holding particles, and the region of each particle.
std::vector<size_t> occupied_regions(const CrackExtraction& c, const Regions& r, const std::vector<Vec3>& x) {
  std::vector<size_t> counts = points_per_region(c.diagram, r, x), occupied;
  for (size_t k = 0; k < counts.size(); ++k)
    if (counts[k] > 0) occupied.push_back(counts[k]);
  return occupied;
}

TEST(CrackSurface, SlabGivesAPlanarCrackOfTheCrossSectionAndTwoFragments) {
  for (const double z0 : {0.0, 0.0025}) {  // mid-plane on a node plane and between node planes
    const DamagedBox box(kL, kS, [&](const Vec3& p) { return std::abs(p.z() - z0) < kS; });
    const CrackExtraction c = extract_crack(box.x, box.c_his, options());
    // The diagram tiles its box.
    double volume = 0;
    for (double v : c.diagram.cell_volume) volume += v;
    EXPECT_NEAR(volume, (c.diagram.box_hi - c.diagram.box_lo).prod(), 1e-9 * volume);
    EXPECT_GT(c.interior_faces, 0u);
    EXPECT_GT(c.extension_faces, 0u);
    const TriMesh crack = crack_surface_mesh(c);
    double worst = 0;
    for (const Vec3& v : crack.positions)
      if (std::abs(v.x()) <= kL && std::abs(v.y()) <= kL) worst = std::max(worst, std::abs(v.z() - z0));
    const double area = testing::area_inside_xy(crack, kL);
    std::printf("MEASURE slab z0=%g: max |z - z0| %.4g (h_v/2 = %.4g), area %.5g of %.5g, faces %zu+%zu\n", z0, worst,
                kH / 2, area, 4 * kL * kL, c.interior_faces, c.extension_faces);
    EXPECT_LE(worst, 0.5 * kH);
    EXPECT_NEAR(area, 4 * kL * kL, 0.05 * 4 * kL * kL);
    const Regions r = find_regions(c.diagram, c.crack_face);
    const std::vector<size_t> occupied = occupied_regions(c, r, box.x);
    ASSERT_EQ(occupied.size(), 2u);
    // The halves: every particle above the slab in one region, below in the other.
    const SiteLocator locate(c.diagram);
    int up = -1, down = -1;
    bool consistent = true;
    for (size_t p = 0; p < box.x.size(); ++p) {
      if (box.c_his[p] > 0) continue;
      const int reg = r.cell_region[static_cast<size_t>(locate.cell_of(box.x[p]))];
      int& side = box.x[p].z() > z0 ? up : down;
      if (side < 0) side = reg;
      consistent = consistent && side == reg;
    }
    EXPECT_TRUE(consistent);
    EXPECT_NE(up, down);
  }
}

TEST(CrackSurface, ThreeSlabsMeetingInAYGiveThreeFragments) {
  // The Y at several orientations and jitter seeds (the junction and oblique exits are the hard cases).
  const double pi = 3.14159265358979323846;
  for (const double rot : {0.0, 0.35, 0.7, 1.05}) {
    std::vector<Vec3> arms;
    for (int k = 0; k < 3; ++k) arms.emplace_back(std::cos(rot + pi / 2 + 2 * pi * k / 3), std::sin(rot + pi / 2 + 2 * pi * k / 3), 0);
    const DamagedBox box(kL, kS, [&](const Vec3& p) {
      for (const Vec3& u : arms)
        if (testing::half_plane_distance(p, u) < kS) return true;
      return false;
    });
    for (unsigned long long seed : {1ULL, 2ULL}) {
      CrackExtractionOptions o = options();
      o.seed = seed;
      const CrackExtraction c = extract_crack(box.x, box.c_his, o);
      const Regions r = find_regions(c.diagram, c.crack_face);
      EXPECT_EQ(occupied_regions(c, r, box.x).size(), 3u) << "rotation " << rot << " seed " << seed;
    }
  }
}

TEST(CrackSurface, ObliqueSlabsAndACrossSplitTheBox) {
  for (const double tilt : {0.3, 0.6, 0.9}) {
    const Vec3 n = Vec3(std::sin(tilt), 0.5 * std::sin(tilt), std::cos(tilt)).normalized();
    const DamagedBox box(kL, kS, [&](const Vec3& p) { return std::abs(p.dot(n) - 0.001) < kS; });
    const CrackExtraction c = extract_crack(box.x, box.c_his, options());
    EXPECT_EQ(occupied_regions(c, find_regions(c.diagram, c.crack_face), box.x).size(), 2u) << "tilt " << tilt;
  }
  // Two slabs crossing: four quarters (a junction of four sheets, where Algorithm 3's parity is even).
  const DamagedBox cross(kL, kS, [](const Vec3& p) { return std::abs(p.z()) < kS || std::abs(p.x()) < kS; });
  const CrackExtraction c = extract_crack(cross.x, cross.c_his, options());
  EXPECT_EQ(occupied_regions(c, find_regions(c.diagram, c.crack_face), cross.x).size(), 4u);
}

TEST(CrackSurface, PennyShapedDiscIsAPartialCrackInOneFragment) {
  const double R = 0.5 * kL;
  const DamagedBox box(kL, kS, [&](const Vec3& p) { return std::abs(p.z()) < kS && std::hypot(p.x(), p.y()) < R; });
  const CrackExtraction c = extract_crack(box.x, box.c_his, options());
  EXPECT_GT(c.interior_faces, 0u);
  EXPECT_EQ(c.extension_faces, 0u);  // the damage does not reach the surface
  const TriMesh crack = crack_surface_mesh(c);
  double area = 0, rmax = 0;
  for (const Tri& t : crack.triangles)
    area += 0.5 * (crack.positions[t[1]] - crack.positions[t[0]]).cross(crack.positions[t[2]] - crack.positions[t[0]]).norm();
  for (const Vec3& v : crack.positions) rmax = std::max(rmax, std::hypot(v.x(), v.y()));
  const double disc = 3.14159265358979 * R * R;
  std::printf("MEASURE penny: area %.4g (disc %.4g), radius %.4g (R %.4g)\n", area, disc, rmax, R);
  EXPECT_LT(rmax, R + 1.5 * kH);  // the medial face stays within the damaged disc and its kernel halo
  EXPECT_GT(area, 0.3 * disc);
  const Regions r = find_regions(c.diagram, c.crack_face);
  EXPECT_EQ(occupied_regions(c, r, box.x).size(), 1u);
}

// |sum of the diagram's cell volumes - volume of its box| / volume of its box (0 for an empty diagram).
double tiling_error(const CrackExtraction& c) {
  double volume = 0;
  for (double v : c.diagram.cell_volume) volume += v;
  const double box = (c.diagram.box_hi - c.diagram.box_lo).prod();
  return c.diagram.cell_volume.empty() ? 0.0 : std::abs(volume - box) / box;
}

TEST(CrackSurface, DegenerateDamageGivesNoCrack) {
  // No damage at all: no crack face, no crack triangle, and one region holding every particle.
  const DamagedBox intact(kL, kS, [](const Vec3&) { return false; });
  const CrackExtraction none = extract_crack(intact.x, intact.c_his, options());
  EXPECT_TRUE(none.empty());
  EXPECT_EQ(none.count_D, 0u);
  EXPECT_EQ(crack_surface_mesh(none).triangles.size(), 0u);
  EXPECT_LT(tiling_error(none), 1e-9);  // the cells tile their box
  EXPECT_EQ(find_regions(none.diagram, none.crack_face).count, 1);
  EXPECT_EQ(occupied_regions(none, find_regions(none.diagram, none.crack_face), intact.x),
            std::vector<size_t>{intact.x.size()});
  // Damage in a skin one particle layer thick (kS = h_v / 2) on the x = +L face: it has undamaged
  // material on one side only, so there is no medial surface between intact parts and nothing is cut
  // off: no crack face, and all 8000 particles in the one region.
  const DamagedBox skin(kL, kS, [](const Vec3& p) { return p.x() > kL - kS; });
  ASSERT_EQ(skin.x.size(), 8000u);
  const CrackExtraction sc = extract_crack(skin.x, skin.c_his, options());
  EXPECT_GT(sc.count_D, 0u);  // the skin did damage nodes ...
  EXPECT_TRUE(sc.empty());    // ... but no face separates anything
  EXPECT_EQ(sc.interior_faces, 0u);
  EXPECT_EQ(sc.extension_faces, 0u);
  EXPECT_EQ(crack_surface_mesh(sc).triangles.size(), 0u);
  EXPECT_LT(tiling_error(sc), 1e-9);
  const Regions sr = find_regions(sc.diagram, sc.crack_face);
  EXPECT_EQ(sr.count, 1);
  EXPECT_EQ(occupied_regions(sc, sr, skin.x), std::vector<size_t>{8000u});
  // Everything damaged: no node is undamaged (V is empty), so there are no two intact sides for a medial
  // face to lie between: the crack is empty.
  const DamagedBox all(kL, kS, [](const Vec3&) { return true; });
  const CrackExtraction ac = extract_crack(all.x, all.c_his, options());
  EXPECT_EQ(ac.count_V, 0u);
  EXPECT_GT(ac.count_D, 0u);
  EXPECT_TRUE(ac.empty());
  EXPECT_EQ(crack_surface_mesh(ac).triangles.size(), 0u);
  // A single particle, damaged (again no undamaged node, no crack) or intact (one region holding it).
  const CrackExtraction one = extract_crack({Vec3(0, 0, 0)}, {1.0}, options());
  EXPECT_EQ(one.count_V, 0u);
  EXPECT_TRUE(one.empty());
  const CrackExtraction one_intact = extract_crack({Vec3(0, 0, 0)}, {0.0}, options());
  EXPECT_TRUE(one_intact.empty());
  EXPECT_LT(tiling_error(one_intact), 1e-9);
  const Regions r1 = find_regions(one_intact.diagram, one_intact.crack_face);
  EXPECT_EQ(r1.count, 1);
  EXPECT_EQ(occupied_regions(one_intact, r1, {Vec3(0, 0, 0)}), std::vector<size_t>{1u});
  // No particles: no grid nodes, no sites, an empty diagram.
  const CrackExtraction nothing = extract_crack({}, {}, options());
  EXPECT_TRUE(nothing.empty());
  EXPECT_EQ(nothing.count_B, 0u);
  EXPECT_TRUE(nothing.diagram.cell_volume.empty());
}

TEST(CrackSurface, BadOptionsAreRefusedBeforeAllocating) {
  const DamagedBox box(kL, kS, [](const Vec3& p) { return std::abs(p.z()) < kS; });
  CrackExtractionOptions o = options();
  o.grid.spacing = 0;
  EXPECT_THROW(extract_crack(box.x, box.c_his, o), InputError);
  o.grid.spacing = 1e-7;  // 1e6 nodes per axis: far beyond the memory limit
  try {
    extract_crack(box.x, box.c_his, o);
    FAIL() << "a tiny h_v was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("GB"), std::string::npos) << e.what();
  }
}

TEST(Voronoi, CoplanarAndDuplicateSitesAreHandled) {
  // Sites in one plane: prisms through the whole box, volumes still tile it.
  std::vector<Vec3> plane;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j) plane.emplace_back(0.1 + 0.2 * i, 0.1 + 0.2 * j, 0.5);
  const VoronoiDiagram d = compute_voronoi(plane, Vec3::Zero(), Vec3::Ones());
  double v = 0;
  for (double c : d.cell_volume) v += c;
  EXPECT_NEAR(v, 1.0, 1e-12);
  for (double c : d.cell_volume) EXPECT_NEAR(c, 0.04, 1e-12);
  // Coincident and outside sites: a clear error naming them, not a crash.
  std::vector<Vec3> dup = plane;
  dup.push_back(plane[7]);
  try {
    compute_voronoi(dup, Vec3::Zero(), Vec3::Ones());
    FAIL() << "duplicate sites were accepted";
  } catch (const NumericalError& e) {
    EXPECT_NE(std::string(e.what()).find("coincide"), std::string::npos) << e.what();
  }
  EXPECT_THROW(compute_voronoi({Vec3(2, 0.5, 0.5)}, Vec3::Zero(), Vec3::Ones()), NumericalError);
}

}  // namespace
}  // namespace shellfrac::brittle
