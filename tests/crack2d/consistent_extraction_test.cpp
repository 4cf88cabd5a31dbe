#include "crack2d/consistent_extraction.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <limits>

namespace shellfrac::crack2d {
namespace {

constexpr int kCells = 100;
constexpr double kH = 1.0 / kCells;  // sample spacing
const Box kUnit{Point(0, 0), Point(1, 1)};

// Cell-centred sample grid on the unit patch.
std::vector<Point> sample_grid() {
  std::vector<Point> pts;
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) pts.emplace_back((i + 0.5) * kH, (j + 0.5) * kH);
  return pts;
}

std::vector<unsigned char> flags(const std::vector<Point>& pts, const std::function<bool(const Point&)>& damaged) {
  std::vector<unsigned char> f(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) f[i] = damaged(pts[i]) ? 1 : 0;
  return f;
}

double distance_to_segment(const Point& p, const Point& a, const Point& b) { return point_segment_distance(p, {a, b}); }

int count_components(const CrackGraph& g) {
  int n = 0;
  g.component_labels(&n);
  return n;
}

int max_degree(const CrackGraph& g) {
  int d = 0;
  for (size_t v = 0; v < g.num_vertices(); ++v) d = std::max(d, g.degree(static_cast<int>(v)));
  return d;
}

struct Extent {
  double u_min = std::numeric_limits<double>::infinity(), u_max = -std::numeric_limits<double>::infinity();
  double v_dev = 0.0;       // largest |v - 0.5| over vertices with edges
  double tip_v_dev = 0.0;   // |v - 0.5| of the vertex with the largest u
};

Extent measure(const CrackGraph& g) {
  Extent e;
  for (size_t v = 0; v < g.num_vertices(); ++v) {
    if (g.degree(static_cast<int>(v)) == 0) continue;
    const Point& p = g.vertices()[v];
    e.u_min = std::min(e.u_min, p.x());
    if (p.x() > e.u_max) {
      e.u_max = p.x();
      e.tip_v_dev = std::abs(p.y() - 0.5);
    }
    e.v_dev = std::max(e.v_dev, std::abs(p.y() - 0.5));
  }
  return e;
}

TEST(ConsistentExtraction, StraightBandGivesCentreLineFromEdgeToTip) {
  const auto pts = sample_grid();
  const auto damaged = flags(pts, [](const Point& p) { return std::abs(p.y() - 0.5) < 2 * kH && p.x() < 0.6; });
  ConsistentCrackExtractor extractor(kUnit, kH);
  const ExtractionStats stats = extractor.extract(pts, damaged);
  const CrackGraph& g = extractor.graph();
  ASSERT_GT(g.num_edges(), 0u);
  const Extent e = measure(g);
  EXPECT_LE(e.v_dev, 0.5 * kH);           // on the centre line v = 0.5 within h/2
  EXPECT_EQ(e.u_min, 0.0);                // reaches the patch edge exactly
  EXPECT_NEAR(e.u_max, 0.6, 2 * kH);      // reaches the end of the damaged band
  EXPECT_EQ(count_components(g), 1);
  EXPECT_EQ(stats.subset_violations, 0u);
  EXPECT_GT(stats.seeds, 100u);
  RecordProperty("u_max", std::to_string(e.u_max));
  RecordProperty("v_dev", std::to_string(e.v_dev));
}

TEST(ConsistentExtraction, DeterministicForSameInput) {
  const auto pts = sample_grid();
  const auto damaged = flags(pts, [](const Point& p) { return distance_to_segment(p, {0.0, 0.3}, {0.7, 0.6}) < 2.5 * kH; });
  ConsistentCrackExtractor a(kUnit, kH), b(kUnit, kH);
  a.extract(pts, damaged);
  b.extract(pts, damaged);
  ASSERT_GT(a.graph().num_edges(), 0u);
  EXPECT_TRUE(a.graph().contains(b.graph()));
  EXPECT_TRUE(b.graph().contains(a.graph()));
  // A slanted band: the crack stays within h of the band's axis line, and its tip reaches the rounded end
  // of the band (which lies 2.5 h beyond the axis end) within 2 h.
  const Point axis = Point(0.7, 0.3).normalized(), normal(-axis.y(), axis.x());
  double far_along = 0.0;
  for (size_t v = 0; v < a.graph().num_vertices(); ++v) {
    const Point d = a.graph().vertices()[v] - Point(0.0, 0.3);
    EXPECT_LE(std::abs(d.dot(normal)), 1.0 * kH);
    far_along = std::max(far_along, d.dot(axis));
  }
  EXPECT_NEAR(far_along, Point(0.7, 0.3).norm() + 2.5 * kH, 2 * kH);
}

TEST(ConsistentExtraction, GrowingThickeningBandStaysConsistent) {
  const auto pts = sample_grid();
  ConsistentCrackExtractor extractor(kUnit, kH);
  for (int k = 1; k <= 10; ++k) {
    const double length = 0.1 * k - 0.05;              // the last stage stops short of the far edge
    const double half_width = (1.6 + 0.25 * k) * kH;   // the band thickens while it grows
    const auto damaged = flags(pts, [&](const Point& p) { return std::abs(p.y() - 0.5) < half_width && p.x() < length; });
    const CrackGraph before = extractor.graph();
    const ExtractionStats stats = extractor.extract(pts, damaged);
    const CrackGraph& g = extractor.graph();
    SCOPED_TRACE("stage " + std::to_string(k));
    EXPECT_EQ(stats.subset_violations, 0u);
    EXPECT_TRUE(g.contains(before));
    const Extent e = measure(g);
    EXPECT_LE(e.tip_v_dev, 2 * kH);
    EXPECT_LE(e.v_dev, 2 * kH);
    EXPECT_EQ(e.u_min, 0.0);
    EXPECT_NEAR(e.u_max, length, 2 * kH);
    EXPECT_EQ(count_components(g), 1);  // no gaps between stages
  }
  EXPECT_EQ(extractor.total_subset_violations(), 0u);
}

// Damage around a polyline of "bone" segments with the given half width.
std::vector<unsigned char> band_along(const std::vector<Point>& pts, const std::vector<std::array<Point, 2>>& bones,
                                      double half_width) {
  return flags(pts, [&](const Point& p) {
    for (const auto& b : bones)
      if (distance_to_segment(p, b[0], b[1]) < half_width) return true;
    return false;
  });
}

bool has_vertex_near(const CrackGraph& g, const Point& q, double radius) {
  for (size_t v = 0; v < g.num_vertices(); ++v)
    if (g.degree(static_cast<int>(v)) > 0 && (g.vertices()[v] - q).norm() <= radius) return true;
  return false;
}

TEST(ConsistentExtraction, BranchingBandGivesJunction) {
  const auto pts = sample_grid();
  const Point fork(0.4, 0.5), upper(0.85, 0.78), lower(0.85, 0.22);
  ConsistentCrackExtractor extractor(kUnit, kH);
  // Stage 1: the stem; stage 2: short branches; stage 3: full branches (Fig. 4.8c).
  const double hw = 2.5 * kH;
  extractor.extract(pts, band_along(pts, {{Point(0, 0.5), fork}}, hw));
  EXPECT_EQ(count_components(extractor.graph()), 1);
  const Point upper_mid = fork + 0.5 * (upper - fork), lower_mid = fork + 0.5 * (lower - fork);
  extractor.extract(pts, band_along(pts, {{Point(0, 0.5), fork}, {fork, upper_mid}, {fork, lower_mid}}, hw));
  const ExtractionStats last = extractor.extract(pts, band_along(pts, {{Point(0, 0.5), fork}, {fork, upper}, {fork, lower}}, hw));
  const CrackGraph& g = extractor.graph();
  EXPECT_EQ(extractor.total_subset_violations(), 0u);
  EXPECT_EQ(last.subset_violations, 0u);
  EXPECT_GE(max_degree(g), 3);
  EXPECT_EQ(count_components(g), 1);
  EXPECT_TRUE(has_vertex_near(g, upper, 3 * kH));
  EXPECT_TRUE(has_vertex_near(g, lower, 3 * kH));
  // In floating point the stem band |v - 0.5| < 2.5 h holds the sample row v = 0.475 but not v = 0.525,
  // so its medial axis meets the edge at v = 0.495, exactly h/2 off; the Voronoi lattice (shifted off
  // the domain centre by a fraction of a 2^-28 step) may put the end a few 1e-9 beyond that.
  EXPECT_TRUE(has_vertex_near(g, Point(0, 0.5), 0.5 * kH + 1e-7));
}

TEST(ConsistentExtraction, BranchingBandInOneExtraction) {
  const auto pts = sample_grid();
  const Point fork(0.4, 0.5), upper(0.85, 0.78), lower(0.85, 0.22);
  ConsistentCrackExtractor extractor(kUnit, kH);
  extractor.extract(pts, band_along(pts, {{Point(0, 0.5), fork}, {fork, upper}, {fork, lower}}, 2.5 * kH));
  const CrackGraph& g = extractor.graph();
  EXPECT_GE(max_degree(g), 3);
  EXPECT_EQ(count_components(g), 1);
  for (size_t v = 0; v < g.num_vertices(); ++v) {
    const Point& p = g.vertices()[v];
    const double d = std::min({distance_to_segment(p, Point(0, 0.5), fork), distance_to_segment(p, fork, upper),
                               distance_to_segment(p, fork, lower)});
    EXPECT_LE(d, 2.5 * kH);  // every vertex inside the damaged band
  }
}

TEST(ConsistentExtraction, TwoBandsMerge) {
  const auto pts = sample_grid();
  const Point top(0.0, 0.75), bottom(0.0, 0.25), meet(0.55, 0.5), end(0.85, 0.5);
  const double hw = 2.5 * kH;
  ConsistentCrackExtractor extractor(kUnit, kH);
  // Stage 1: two separate cracks from the left edge.
  const Point top_part = top + 0.5 * (meet - top), bottom_part = bottom + 0.5 * (meet - bottom);
  extractor.extract(pts, band_along(pts, {{top, top_part}, {bottom, bottom_part}}, hw));
  EXPECT_EQ(count_components(extractor.graph()), 2);
  // Stage 2: they run into each other and continue as one.
  extractor.extract(pts, band_along(pts, {{top, meet}, {bottom, meet}, {meet, end}}, hw));
  const CrackGraph& g = extractor.graph();
  EXPECT_EQ(extractor.total_subset_violations(), 0u);
  EXPECT_GE(max_degree(g), 3);
  EXPECT_EQ(count_components(g), 1);
  EXPECT_TRUE(has_vertex_near(g, end, 3 * kH));
}

TEST(ConsistentExtraction, DegenerateInputs) {
  ConsistentCrackExtractor extractor(kUnit, kH);
  // Nothing at all, one point, two points.
  EXPECT_EQ(extractor.extract({}, {}).new_edges, 0u);
  EXPECT_EQ(extractor.extract({Point(0.5, 0.5)}, {1}).new_edges, 0u);
  EXPECT_EQ(extractor.extract({Point(0.5, 0.5), Point(0.51, 0.5)}, {1, 1}).new_edges, 0u);
  EXPECT_EQ(extractor.extract({Point(0.5, 0.5), Point(0.51, 0.5)}, {1, 0}).new_edges, 0u);
  // All samples on one line with alternating damage: every seed is collinear.
  std::vector<Point> line;
  std::vector<unsigned char> alternating;
  for (int i = 0; i < 100; ++i) {
    line.emplace_back((i + 0.5) * kH, 0.5);
    alternating.push_back(i % 2);
  }
  EXPECT_NO_THROW(extractor.extract(line, alternating));
  // A solid run of damage on that line: seeds at its two ends only.
  std::vector<unsigned char> run(100, 0);
  for (int i = 30; i < 60; ++i) run[i] = 1;
  EXPECT_NO_THROW(extractor.extract(line, run));
  EXPECT_EQ(extractor.graph().num_edges(), 0u);
  // Everything damaged: no boundary, hence no seeds and no crack.
  const auto pts = sample_grid();
  const ExtractionStats all = extractor.extract(pts, std::vector<unsigned char>(pts.size(), 1));
  EXPECT_EQ(all.seeds, 0u);
  EXPECT_EQ(extractor.graph().num_edges(), 0u);
  EXPECT_THROW(extractor.extract(pts, {1, 0}), std::invalid_argument);
  EXPECT_EQ(extractor.total_subset_violations(), 0u);
}

TEST(ConsistentExtraction, DuplicatedSamplesGiveTheSameCrack) {
  const auto pts = sample_grid();
  auto in_band = [](const Point& p) { return std::abs(p.y() - 0.5) < 2 * kH && p.x() < 0.6; };
  std::vector<Point> doubled = pts;
  doubled.insert(doubled.end(), pts.begin(), pts.end());
  ConsistentCrackExtractor single(kUnit, kH), twice(kUnit, kH);
  single.extract(pts, flags(pts, in_band));
  twice.extract(doubled, flags(doubled, in_band));
  EXPECT_EQ(twice.graph().num_edges(), single.graph().num_edges());
  EXPECT_TRUE(twice.graph().contains(single.graph()));
}

TEST(ConsistentExtraction, CrackGrowsAlongPrescribedCut) {
  const auto pts = sample_grid();
  ConsistentCrackExtractor extractor(kUnit, kH);
  extractor.add_prescribed_cut({Point(0.0, 0.5), Point(0.3, 0.5)}, false);
  const CrackGraph before = extractor.graph();
  extractor.extract(pts, flags(pts, [](const Point& p) { return std::abs(p.y() - 0.5) < 2 * kH && p.x() < 0.6; }));
  EXPECT_TRUE(extractor.graph().contains(before));
  EXPECT_EQ(count_components(extractor.graph()), 1);
  EXPECT_NEAR(measure(extractor.graph()).u_max, 0.6, 2 * kH);
}

}  // namespace
}  // namespace shellfrac::crack2d

namespace shellfrac::crack2d {
namespace {

// Non-uniform samples as the shell produces them: 4 x 4 Gauss-Legendre points per cell of a 40-cell patch.
TEST(ConsistentExtraction, GaussSamplesSlantedBandGrowsWithoutGaps) {
  const int cells = 40;
  const double cell = 1.0 / cells, spacing = cell / 4;
  const double gauss[4] = {0.0694318442029737, 0.3300094782075719, 0.6699905217924281, 0.9305681557970263};
  std::vector<Point> pts;
  for (int j = 0; j < cells; ++j)
    for (int i = 0; i < cells; ++i)
      for (int b = 0; b < 4; ++b)
        for (int a = 0; a < 4; ++a) pts.emplace_back((i + gauss[a]) * cell, (j + gauss[b]) * cell);
  const Point start(0.0, 0.4), end(0.7, 0.6);
  const Point axis = (end - start).normalized(), normal(-axis.y(), axis.x());
  ConsistentCrackExtractor extractor(kUnit, spacing);
  for (int k = 1; k <= 6; ++k) {
    SCOPED_TRACE("stage " + std::to_string(k));
    const Point tip = start + (end - start) * (k / 6.0);
    const double half_width = (3.0 + 0.3 * k) * spacing;
    const auto damaged = flags(pts, [&](const Point& p) { return distance_to_segment(p, start, tip) < half_width; });
    const ExtractionStats stats = extractor.extract(pts, damaged);
    EXPECT_EQ(stats.subset_violations, 0u);
    EXPECT_EQ(count_components(extractor.graph()), 1);
    double far_along = 0.0, worst_offset = 0.0;
    for (size_t v = 0; v < extractor.graph().num_vertices(); ++v) {
      const Point d = extractor.graph().vertices()[v] - start;
      far_along = std::max(far_along, d.dot(axis));
      worst_offset = std::max(worst_offset, std::abs(d.dot(normal)));
    }
    // Inside the damaged band. (With these non-uniform samples a short spur can appear at the band's
    // rounded cap, so the centre-line bound of the uniform-grid tests is not asserted here.)
    EXPECT_LE(worst_offset, half_width);
    EXPECT_NEAR(far_along, (tip - start).norm() + half_width, 2.0 * spacing);
  }
  EXPECT_EQ(extractor.total_subset_violations(), 0u);
}

}  // namespace
}  // namespace shellfrac::crack2d
