// The crack graph closes: joins to cracks, cuts and the border, merging of overlapping
// branches, separation of intact pieces linked by fully damaged material, strict-subset growth.
// Pieces are counted with count_regions (crack2d/region_count.hpp) on a probe grid finer than a cell.
#include "crack2d/consistent_extraction.hpp"
#include "crack2d/region_count.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <functional>

namespace shellfrac::crack2d {
namespace {

const Box kUnit{Point(0, 0), Point(1, 1)};
constexpr int kCells = 24;                   // simulation cells per side, as in the shipped scenes
constexpr double kCell = 1.0 / kCells;
constexpr double kSpacing = kCell / 4;       // 4 x 4 quadrature points per cell
constexpr int kProbes = 240;                 // region probes per side: 10 per cell
constexpr size_t kProbesPerCell = 100;

// 4 x 4 Gauss-Legendre points per cell, as the shell samples its damage.
std::vector<Point> gauss_samples() {
  const double g[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
  std::vector<Point> pts;
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i)
      for (int b = 0; b < 4; ++b)
        for (int a = 0; a < 4; ++a) pts.emplace_back((i + g[a]) * kCell, (j + g[b]) * kCell);
  return pts;
}

std::vector<unsigned char> flags(const std::vector<Point>& pts, const std::function<bool(const Point&)>& damaged) {
  std::vector<unsigned char> f(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) f[i] = damaged(pts[i]) ? 1 : 0;
  return f;
}

double to_segment(const Point& p, const Point& a, const Point& b) { return point_segment_distance(p, {a, b}); }

// Connected parts of the crack, counting a join that ends inside a segment as connected to it.
int components(const ConsistentCrackExtractor& x) {
  int n = 0;
  touching_components(x.graph(), x.index(), 1e-9, &n);
  return n;
}

// Degree-1 vertices off the patch border that are not the end of a join landing on another segment.
int free_tips(const CrackGraph& g) {
  int tips = 0;
  for (size_t v = 0; v < g.num_vertices(); ++v) {
    if (g.degree(static_cast<int>(v)) != 1 || on_box_boundary(g.vertices()[v], kUnit, 1e-12)) continue;
    bool attached = false;
    for (size_t e = 0; e < g.num_edges() && !attached; ++e) {
      const auto& ed = g.edges()[e];
      if (ed[0] != static_cast<int>(v) && ed[1] != static_cast<int>(v))
        attached = point_segment_distance(g.vertices()[v], g.segment(e)) < 1e-9;
    }
    tips += attached ? 0 : 1;
  }
  return tips;
}

RegionCount regions(const ConsistentCrackExtractor& x) { return count_regions(x.index(), kUnit, kProbes, kProbes); }

TEST(RegionCount, CountsPiecesOfKnownGraphs) {
  auto count = [](const std::vector<std::array<Point, 2>>& segments) {
    CrackGraph g;
    for (const auto& s : segments) g.add_edge(g.add_vertex(s[0]), g.add_vertex(s[1]));
    CrackIndex index(kUnit);
    index.rebuild(g);
    return count_regions(index, kUnit, 50, 50);
  };
  EXPECT_EQ(count({}).regions, 1);
  EXPECT_EQ(count({{Point(0.0, 0.5), Point(0.7, 0.5)}}).regions, 1);          // open slit: one piece
  const RegionCount halves = count({{Point(0.0, 0.52), Point(1.0, 0.52)}});     // edge to edge
  ASSERT_EQ(halves.regions, 2);
  EXPECT_EQ(halves.size[0] + halves.size[1], 2500u);
  EXPECT_EQ(halves.size[0], 50u * 26u);                                         // probes below v = 0.52 (rows 0.01 ... 0.51)
  const RegionCount cross = count({{Point(0.0, 0.52), Point(1.0, 0.52)}, {Point(0.52, 0.0), Point(0.52, 1.0)}});
  EXPECT_EQ(cross.regions, 4);
  EXPECT_EQ(cross.regions_with_at_least(24u * 24u), 4);  // the smallest quadrant: 24 x 24 probes
  const RegionCount loop = count({{Point(0.2, 0.2), Point(0.6, 0.2)}, {Point(0.6, 0.2), Point(0.6, 0.6)},
                                  {Point(0.6, 0.6), Point(0.2, 0.6)}, {Point(0.2, 0.6), Point(0.2, 0.2)}});
  ASSERT_EQ(loop.regions, 2);
  EXPECT_EQ(loop.size[1], 20u * 20u);  // the probes inside the 0.4 x 0.4 square, 0.02 apart
  EXPECT_THROW(count_regions(CrackIndex(kUnit), kUnit, 0, 5), std::invalid_argument);
}

// (a) A band four cells wide across the whole sheet: one crack line, two pieces, on the mid-line.
TEST(CrackClosure, FourCellWideBandSplitsTheSheetInTwo) {
  const auto pts = gauss_samples();
  const double mid = 0.5 + 0.3 * kCell, half_width = 2.0 * kCell;
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  const ExtractionStats st = x.extract(pts, flags(pts, [&](const Point& p) { return std::abs(p.y() - mid) < half_width; }));
  const CrackGraph& g = x.graph();
  const RegionCount rc = regions(x);
  EXPECT_EQ(rc.regions, 2);
  EXPECT_EQ(rc.regions_with_at_least(kProbesPerCell), 2);
  EXPECT_EQ(components(x), 1);
  EXPECT_EQ(free_tips(g), 0);
  EXPECT_EQ(st.subset_violations, 0u);
  // The mid-line of the band of damaged samples: halfway between its outermost damaged sample rows.
  double lo = 1.0, hi = 0.0;
  for (const Point& p : pts)
    if (std::abs(p.y() - mid) < half_width) lo = std::min(lo, p.y()), hi = std::max(hi, p.y());
  const double medial = 0.5 * (lo + hi);
  for (size_t v = 0; v < g.num_vertices(); ++v) EXPECT_LE(std::abs(g.vertices()[v].y() - medial), kSpacing);
  // Each piece holds the material on its side: the probes below the mid-line, within a probe row.
  const size_t below = static_cast<size_t>(std::lround(medial * kProbes)) * kProbes;
  EXPECT_NEAR(static_cast<double>(rc.size[0]), static_cast<double>(below), kProbes);
}

// (b) A band grows from the tip of a notch (a prescribed cut) over several extractions. As at a real
// notch, the material right at the cut flanks stays intact (a stress-free surface), so the damaged
// region wraps around the notch tip. The grown crack must join the notch and finally split the sheet.
TEST(CrackClosure, BandGrownFromANotchJoinsTheNotch) {
  const auto pts = gauss_samples();
  const Point notch_end(0.2, 0.5);
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  x.add_prescribed_cut({Point(0.0, 0.5), notch_end}, false);
  for (int stage = 1; stage <= 6; ++stage) {
    SCOPED_TRACE("stage " + std::to_string(stage));
    const double front = 0.2 + 0.8 * stage / 6.0;
    const double half_width = (1.0 + 0.15 * stage) * kCell;
    const auto damaged = flags(pts, [&](const Point& p) {
      const bool at_flank = std::abs(p.y() - 0.5) < 0.6 * kSpacing && p.x() < notch_end.x();
      return to_segment(p, Point(0.19, 0.5), Point(front, 0.5)) < half_width && !at_flank;
    });
    const CrackGraph before = x.graph();
    const ExtractionStats st = x.extract(pts, damaged);
    EXPECT_EQ(st.subset_violations, 0u);
    EXPECT_TRUE(x.graph().contains(before));
    // Everything grown so far hangs together with the notch (vertices 0 and 1).
    const std::vector<int> label = touching_components(x.graph(), x.index(), 1e-9);
    for (const auto& e : x.graph().edges()) EXPECT_EQ(label[e[0]], label[0]);
  }
  EXPECT_EQ(regions(x).regions, 2);
  EXPECT_EQ(free_tips(x.graph()), 0);
}

// (c) Two overlapping, near-parallel bands: the first is extracted alone, then a wider one, shifted by
// most of a cell, continues it to the far edge in one damaged region (as in tear-mode-one, where a new
// line formed beside the end of the old one). The crack must run on as one line with no band of
// material left linking the halves between two crack lines. (Before closure: one piece, a strand.)
TEST(CrackClosure, OverlappingParallelBandsMergeIntoOneCrack) {
  const auto pts = gauss_samples();
  auto first = [&](const Point& p) { return to_segment(p, Point(0.0, 0.5), Point(0.7, 0.5)) < 1.2 * kCell; };
  auto second = [&](const Point& p) { return to_segment(p, Point(0.6, 0.5 + 0.9 * kCell), Point(1.0, 0.5 + 0.9 * kCell)) < 1.6 * kCell; };
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  x.extract(pts, flags(pts, first));
  ASSERT_EQ(components(x), 1);
  const CrackGraph before = x.graph();
  const ExtractionStats st = x.extract(pts, flags(pts, [&](const Point& p) { return first(p) || second(p); }));
  EXPECT_TRUE(x.graph().contains(before));
  EXPECT_EQ(st.subset_violations, 0u);
  EXPECT_EQ(components(x), 1);
  const RegionCount rc = regions(x);
  EXPECT_EQ(rc.regions, 2);  // two halves; a lens or an island would be a third region
  EXPECT_EQ(rc.regions_with_at_least(kProbesPerCell), 2);
}

// (d) Spurs and pockets: a band across the sheet with a damaged spur sticking out of one flank, a
// damaged bulge on the other, and a small intact pocket (less than a cell) inside. Still two pieces:
// no region is cut out around the pocket and the spur and bulge cut nothing off.
TEST(CrackClosure, SpursBulgesAndSmallPocketsCutNothingOff) {
  const auto pts = gauss_samples();
  const double hw = 1.5 * kCell;
  const Point pocket(0.3, 0.5);
  auto damaged = [&](const Point& p) {
    if ((p - pocket).norm() < 0.3 * kCell) return false;                                      // intact pocket
    if (std::abs(p.y() - 0.5) < hw) return true;                                               // the band
    if (to_segment(p, Point(0.6, 0.5), Point(0.6, 0.5 + hw + 2.0 * kCell)) < 0.5 * kCell) return true;  // spur
    return (p - Point(0.8, 0.5 - hw)).norm() < 2.0 * kCell;                                    // bulge
  };
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  x.extract(pts, flags(pts, damaged));
  const RegionCount rc = regions(x);
  EXPECT_EQ(rc.regions, 2);
  EXPECT_EQ(components(x), 1);
  // The line runs inside the damaged region (its vertices are within a sample spacing of a damaged
  // sample), or through the pocket, which counts as damaged because it holds less than a cell.
  for (size_t v = 0; v < x.graph().num_vertices(); ++v) {
    const Point& q = x.graph().vertices()[v];
    bool near_damage = (q - pocket).norm() < 0.3 * kCell + kSpacing;
    for (const Point& p : pts) near_damage = near_damage || ((p - q).norm() < kSpacing && damaged(p));
    EXPECT_TRUE(near_damage) << "vertex " << v << " at (" << q.x() << ", " << q.y() << ")";
  }
}

// (d') A large intact island (2 x 2 cells) enclosed by a wide damaged band is cut out whole: fully
// damaged material links it to both halves, so it becomes a third piece of the size of the island.
TEST(CrackClosure, LargeIntactIslandInsideTheBandIsCutOut) {
  const auto pts = gauss_samples();
  const Point centre(0.5, 0.5);
  auto in_island = [&](const Point& p) { return std::abs(p.x() - centre.x()) < kCell && std::abs(p.y() - centre.y()) < kCell; };
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  x.extract(pts, flags(pts, [&](const Point& p) { return std::abs(p.y() - 0.5) < 3.0 * kCell && !in_island(p); }));
  const RegionCount rc = regions(x);
  EXPECT_EQ(rc.regions, 3);
  ASSERT_EQ(rc.regions_with_at_least(kProbesPerCell), 3);
  // The island's piece: between the island (2 x 2 cells = 400 probes) and the island plus the half
  // band around it (6 x 6 cells); the two halves hold the rest.
  size_t smallest = rc.size[0];
  for (size_t s : rc.size) smallest = std::min(smallest, s);
  EXPECT_GE(smallest, 4 * kProbesPerCell);
  EXPECT_LE(smallest, 36 * kProbesPerCell);
}

// (e) Two bands crossing the whole sheet (an X made of a horizontal and a vertical band, the second one
// grown after the first was cracked): four pieces.
TEST(CrackClosure, CrossingBandsGiveFourPieces) {
  const auto pts = gauss_samples();
  const double hw = 1.3 * kCell;
  auto horizontal = [&](const Point& p) { return std::abs(p.y() - 0.45) < hw; };
  auto vertical = [&](const Point& p) { return std::abs(p.x() - 0.55) < hw; };
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  x.extract(pts, flags(pts, horizontal));
  EXPECT_EQ(regions(x).regions, 2);
  for (int stage = 1; stage <= 3; ++stage) {
    const double reach = stage / 3.0;  // the vertical band grows from the bottom edge
    const CrackGraph before = x.graph();
    x.extract(pts, flags(pts, [&](const Point& p) { return horizontal(p) || (vertical(p) && p.y() < reach); }));
    EXPECT_TRUE(x.graph().contains(before));
  }
  const RegionCount rc = regions(x);
  EXPECT_EQ(rc.regions, 4);
  EXPECT_EQ(rc.regions_with_at_least(20 * kProbesPerCell), 4);  // each quadrant is large
  EXPECT_EQ(x.total_subset_violations(), 0u);
}

// (f) Strict-subset growth over many extractions of a curved band that lengthens and thickens, with
// a prescribed cut in its way; and the same inputs give the same graph (determinism).
TEST(CrackClosure, MultiStepGrowthKeepsEveryEarlierVertexAndEdge) {
  const auto pts = gauss_samples();
  auto damaged_at_stage = [&](int stage) {
    const double reach = stage / 10.0;
    const double hw = (0.8 + 0.1 * stage) * kCell;
    return flags(pts, [&](const Point& p) {
      if (p.x() > reach) return false;
      const double centre = 0.35 + 0.25 * std::sin(3.0 * p.x());  // a curved path across the sheet
      return std::abs(p.y() - centre) < hw;
    });
  };
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell), twin(kUnit, kSpacing, kCell);
  for (ConsistentCrackExtractor* e : {&x, &twin}) e->add_prescribed_cut({Point(0.7, 0.2), Point(0.7, 0.45)}, false);
  for (int stage = 1; stage <= 10; ++stage) {
    SCOPED_TRACE("stage " + std::to_string(stage));
    const CrackGraph before = x.graph();
    const auto damaged = damaged_at_stage(stage);
    const ExtractionStats st = x.extract(pts, damaged);
    twin.extract(pts, damaged);
    EXPECT_EQ(st.subset_violations, 0u);
    ASSERT_TRUE(x.graph().contains(before));
    // Every earlier vertex at the same index with bit-identical coordinates, every earlier edge kept.
    for (size_t v = 0; v < before.num_vertices(); ++v) {
      EXPECT_EQ(x.graph().vertices()[v].x(), before.vertices()[v].x());
      EXPECT_EQ(x.graph().vertices()[v].y(), before.vertices()[v].y());
    }
    for (const auto& e : before.edges()) EXPECT_TRUE(x.graph().has_edge(e[0], e[1]));
    EXPECT_TRUE(twin.graph().contains(x.graph()));
    EXPECT_TRUE(x.graph().contains(twin.graph()));
  }
  EXPECT_EQ(x.total_subset_violations(), 0u);
  EXPECT_EQ(regions(x).regions, 2);  // the band has crossed the sheet
}

// A fully damaged patch corner comes off (cloth-two-balls: the pinned corners of a falling cloth). A
// band grows in from the left border, then damage fills the whole corner below and beside it: the tip
// continues to the bottom border, and the corner, with no intact sample left, is a piece of its own
// instead of hanging on to the sheet as a strand. The same band away from any corner cuts nothing off.
TEST(CrackClosure, FullyDamagedCornerComesOff) {
  const auto pts = gauss_samples();
  const double y0 = 1.0 * kCell, hw = 0.6 * kCell;
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  x.extract(pts, flags(pts, [&](const Point& p) { return p.x() < 1.2 * kCell && std::abs(p.y() - y0) < hw; }));
  ASSERT_GE(x.graph().num_edges(), 1u);
  EXPECT_EQ(regions(x).regions, 1);  // a crack from the border into the sheet separates nothing yet
  x.extract(pts, flags(pts, [&](const Point& p) { return p.x() < 2.0 * kCell && p.y() < y0 + hw; }));
  const RegionCount rc = regions(x);
  EXPECT_EQ(rc.regions, 2);
  EXPECT_EQ(rc.regions_with_at_least(200 * kProbesPerCell), 1);  // the sheet, and a corner of < 2 cells^2
  EXPECT_EQ(free_tips(x.graph()), 0);
  EXPECT_EQ(x.total_subset_violations(), 0u);
}

// Joins: a crack tip a fraction of a cell short of the border joins it when the ligament is fully
// damaged, and stays a tip when the ligament is intact.
TEST(CrackClosure, TipJoinsTheBorderOnlyThroughDamagedMaterial) {
  const auto pts = gauss_samples();
  const double hw = 1.2 * kCell;
  auto band = [&](const Point& p, double end) { return std::abs(p.y() - 0.5) < hw && p.x() < end; };
  // The band stops 0.6 cells short of the right edge, then reaches it.
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  x.extract(pts, flags(pts, [&](const Point& p) { return band(p, 1.0 - 0.6 * kCell); }));
  EXPECT_EQ(regions(x).regions, 1);  // the intact ligament holds
  const ExtractionStats st = x.extract(pts, flags(pts, [&](const Point& p) { return band(p, 2.0); }));
  EXPECT_EQ(regions(x).regions, 2);
  EXPECT_GE(st.border_joins + st.tip_extensions + st.new_edges, 1u);
  EXPECT_EQ(free_tips(x.graph()), 0);
}

// Damage symmetric about the diagonal u = v (plate-pressure's cracks run from the centre to the
// corners): the medial axis lies on the diagonal, where quadrature points sit. No sample point may lie
// exactly on a crack segment (it would see no control point on either side), and the crack still
// follows the diagonal within a sample spacing.
TEST(CrackClosure, SymmetricDamageKeepsTheCrackOffTheSamples) {
  const auto pts = gauss_samples();
  ConsistentCrackExtractor x(kUnit, kSpacing, kCell);
  for (int stage = 1; stage <= 3; ++stage) {
    const double reach = 0.3 * stage;
    x.extract(pts, flags(pts, [&](const Point& p) {
      return to_segment(p, Point(0.5, 0.5), Point(0.5 - reach, 0.5 - reach)) < 1.2 * kCell ||
             to_segment(p, Point(0.5, 0.5), Point(0.5 + reach, 0.5 - reach)) < 1.2 * kCell;
    }));
  }
  const CrackGraph& g = x.graph();
  ASSERT_GT(g.num_edges(), 20u);
  size_t on_crack = 0;
  for (const Point& p : pts)
    for (size_t e = 0; e < g.num_edges(); ++e) {
      const Segment s = g.segment(e);
      if (orientation(s.a, s.b, p) == 0 && p.x() >= std::min(s.a.x(), s.b.x()) && p.x() <= std::max(s.a.x(), s.b.x()) &&
          p.y() >= std::min(s.a.y(), s.b.y()) && p.y() <= std::max(s.a.y(), s.b.y()))
        ++on_crack;
    }
  EXPECT_EQ(on_crack, 0u);
  for (size_t v = 0; v < g.num_vertices(); ++v) {
    const Point& q = g.vertices()[v];
    if (q.y() > 0.5 - kCell) continue;  // the junction at the centre
    EXPECT_LE(std::min(std::abs(q.x() - q.y()), std::abs(q.x() + q.y() - 1.0)) / std::sqrt(2.0), 1.5 * kSpacing);
  }
  EXPECT_EQ(x.total_subset_violations(), 0u);
}

}  // namespace
}  // namespace shellfrac::crack2d
