#include "crack2d/consistent_extraction.hpp"
#include "crack2d/prescribed_cut.hpp"

#include <gtest/gtest.h>

#include <cmath>

namespace shellfrac::crack2d {
namespace {

const Box kUnit{Point(0, 0), Point(1, 1)};

std::string cut_error(const std::vector<Point>& polyline, bool closed) {
  try {
    validate_cut(polyline, closed, kUnit);
  } catch (const CutError& e) {
    return e.what();
  }
  return "";
}

TEST(PrescribedCut, ArchimedeanSpiralEntersGraph) {
  // r = 0.02 + 0.05 * theta / (2 pi), three turns around the patch centre.
  std::vector<Point> spiral;
  const int n = 300;
  for (int i = 0; i < n; ++i) {
    const double theta = 6.0 * M_PI * i / (n - 1);
    const double r = 0.02 + 0.05 * theta / (2.0 * M_PI);
    spiral.emplace_back(0.5 + r * std::cos(theta), 0.5 + r * std::sin(theta));
  }
  ConsistentCrackExtractor extractor(kUnit, 0.01);
  extractor.add_prescribed_cut(spiral, false);
  const CrackGraph& g = extractor.graph();
  EXPECT_EQ(g.num_vertices(), static_cast<size_t>(n));
  EXPECT_EQ(g.num_edges(), static_cast<size_t>(n - 1));
  EXPECT_EQ(g.degree(0), 1);
  EXPECT_EQ(g.degree(n - 1), 1);
  // A ray from the centre along +u crosses the three turns; the index sees it.
  EXPECT_TRUE(extractor.index().crosses(Point(0.5, 0.5), Point(0.99, 0.5)));
  // Between turns (r = 0.02 + 0.05 k + 0.025 at theta = 2 pi k + pi/2... use the gap along +u) nothing is hit.
  EXPECT_FALSE(extractor.index().crosses(Point(0.5 + 0.08, 0.5), Point(0.5 + 0.11, 0.5)));
  EXPECT_NEAR(extractor.index().distance(Point(0.5 + 0.095, 0.5), 1.0), 0.025, 1e-3);
}

TEST(PrescribedCut, ClosedStarIsALoop) {
  std::vector<Point> star;
  for (int i = 0; i < 64; ++i) {
    const double theta = 2.0 * M_PI * i / 64;
    const double r = (i % 2 == 0) ? 0.3 : 0.15;
    star.emplace_back(0.5 + r * std::cos(theta), 0.5 + r * std::sin(theta));
  }
  ConsistentCrackExtractor extractor(kUnit, 0.01);
  extractor.add_prescribed_cut(star, true);
  const CrackGraph& g = extractor.graph();
  EXPECT_EQ(g.num_edges(), 64u);
  for (int v = 0; v < 64; ++v) EXPECT_EQ(g.degree(v), 2);
  int components = 0;
  g.component_labels(&components);
  EXPECT_EQ(components, 1);
  // The loop separates centre from corner.
  EXPECT_TRUE(extractor.index().crosses(Point(0.5, 0.5), Point(0.02, 0.02)));
}

TEST(PrescribedCut, BadCutsNameTheProblemAndIndex) {
  EXPECT_NE(cut_error({Point(0.1, 0.1), Point(0.2, 0.2), Point(0.3, 0.3), Point(1.2, 0.3)}, false).find("vertex 3"), std::string::npos);
  EXPECT_NE(cut_error({Point(0.1, 0.1), Point(0.2, 0.2), Point(0.3, 0.3), Point(1.2, 0.3)}, false).find("outside"), std::string::npos);
  const std::string zero = cut_error({Point(0.1, 0.1), Point(0.2, 0.2), Point(0.3, 0.3), Point(0.3, 0.3)}, false);
  EXPECT_NE(zero.find("segment 2"), std::string::npos) << zero;
  EXPECT_NE(zero.find("zero length"), std::string::npos) << zero;
  // A Z that folds back over its first segment: segments 0 and 2 cross.
  const std::string crossing = cut_error({Point(0.1, 0.1), Point(0.5, 0.5), Point(0.5, 0.1), Point(0.1, 0.5)}, false);
  EXPECT_NE(crossing.find("segment 0 intersects segment 2"), std::string::npos) << crossing;
  // Consecutive segments folding back onto each other.
  const std::string fold = cut_error({Point(0.1, 0.1), Point(0.5, 0.1), Point(0.3, 0.1)}, false);
  EXPECT_NE(fold.find("segment 0 intersects segment 1"), std::string::npos) << fold;
  // Closed figure eight.
  const std::string eight = cut_error({Point(0.1, 0.1), Point(0.5, 0.5), Point(0.5, 0.1), Point(0.1, 0.5)}, true);
  EXPECT_NE(eight.find("intersects"), std::string::npos) << eight;
  EXPECT_NE(cut_error({Point(0.1, 0.1)}, false).find("at least 2"), std::string::npos);
  EXPECT_NE(cut_error({Point(0.1, 0.1), Point(0.2, 0.1)}, true).find("at least 3"), std::string::npos);
  // The extractor throws the same CutError (an std::invalid_argument) and leaves its graph untouched.
  ConsistentCrackExtractor extractor(kUnit, 0.01);
  EXPECT_THROW(extractor.add_prescribed_cut({Point(0.1, 0.1), Point(-0.1, 0.1)}, false), CutError);
  EXPECT_THROW(extractor.add_prescribed_cut({Point(0.1, 0.1), Point(-0.1, 0.1)}, false), std::invalid_argument);
  EXPECT_EQ(extractor.graph().num_edges(), 0u);
  // Valid edge cases: a cut lying on the domain boundary and a closed triangle.
  EXPECT_EQ(cut_error({Point(0, 0), Point(1, 0)}, false), "");
  EXPECT_EQ(cut_error({Point(0.1, 0.1), Point(0.4, 0.1), Point(0.2, 0.3)}, true), "");
}

}  // namespace
}  // namespace shellfrac::crack2d
