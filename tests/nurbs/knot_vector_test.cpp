// Tests for KnotVector: construction, validation messages, span search, helpers.
#include "nurbs/knot_vector.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "nurbs/nurbs_error.hpp"
#include "tests/nurbs/nurbs_test_helpers.hpp"

namespace shellfrac::nurbs {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

TEST(KnotVector, BasicCountsAndDomain) {
  const KnotVector kv({0, 0, 0, 1, 2, 3, 4, 4, 4}, 2);
  EXPECT_EQ(kv.degree(), 2);
  EXPECT_EQ(kv.size(), 9);
  EXPECT_EQ(kv.num_basis(), 6);
  EXPECT_EQ(kv.domain_begin(), 0.0);
  EXPECT_EQ(kv.domain_end(), 4.0);
  EXPECT_EQ(kv.num_spans(), 4);
  EXPECT_EQ(kv[3], 1.0);
}

TEST(KnotVector, OpenUniformKnots) {
  const KnotVector kv = KnotVector::open_uniform(3, 4, -2.0, 6.0);
  const std::vector<double> expected = {-2, -2, -2, -2, 0, 2, 4, 6, 6, 6, 6};
  EXPECT_EQ(kv.knots(), expected);  // all values are exactly representable
  EXPECT_EQ(kv.num_basis(), 7);
  EXPECT_EQ(kv.num_spans(), 4);

  const KnotVector unit = KnotVector::open_uniform(2, 10);
  ASSERT_EQ(unit.size(), 2 * 3 + 9);
  for (int k = 0; k <= 10; ++k) EXPECT_NEAR(unit[2 + k], k / 10.0, 1e-16);
}

TEST(KnotVector, FindSpanInteriorAndAtKnots) {
  const KnotVector kv({0, 0, 0, 1, 2, 3, 4, 4, 4}, 2);
  EXPECT_EQ(kv.find_span(0.0), 2);
  EXPECT_EQ(kv.find_span(0.5), 2);
  EXPECT_EQ(kv.find_span(1.0), 3);  // a knot starts its span: knots[3] = 1 <= u < knots[4]
  EXPECT_EQ(kv.find_span(2.5), 4);
  EXPECT_EQ(kv.find_span(3.999), 5);
}

TEST(KnotVector, FindSpanAtDomainEndReturnsLastNonEmptySpan) {
  const KnotVector kv({0, 0, 0, 1, 2, 3, 4, 4, 4}, 2);
  const int span = kv.find_span(4.0);
  EXPECT_EQ(span, 5);
  EXPECT_LT(kv[span], kv[span + 1]);

  // Repeated knot at the end of an unclamped vector: n = 5, domain [knots[2], knots[5]] = [1, 3],
  // knots[4] = knots[5] = 3, so the last non-empty span is 3 ([2, 3)).
  const KnotVector unclamped({0, 0.5, 1, 2, 3, 3, 5, 6}, 2);
  EXPECT_EQ(unclamped.domain_end(), 3.0);
  EXPECT_EQ(unclamped.find_span(3.0), 3);
}

TEST(KnotVector, FindSpanAtRepeatedInteriorKnots) {
  // Double knot at 1 and triple knot (C0 for cubic) at 2.
  const KnotVector kv({0, 0, 0, 0, 1, 1, 2, 2, 2, 3, 3, 3, 3}, 3);
  EXPECT_EQ(kv.find_span(0.999), 3);
  EXPECT_EQ(kv.find_span(1.0), 5);  // skips the empty span [knots[4], knots[5]) = [1, 1)
  EXPECT_EQ(kv.find_span(1.5), 5);
  EXPECT_EQ(kv.find_span(2.0), 8);
  EXPECT_EQ(kv.find_span(3.0), 8);
  for (double u : {0.0, 0.3, 1.0, 1.7, 2.0, 2.9, 3.0}) {
    const int s = kv.find_span(u);
    EXPECT_LE(kv[s], u);
    EXPECT_LT(kv[s], kv[s + 1]);
    if (u < 3.0) {
      EXPECT_LT(u, kv[s + 1]);
    }
  }
}

TEST(KnotVector, FindSpanFarFromUnitInterval) {
  const double b = 1e6;
  const KnotVector far({b, b, b, b + 1, b + 2, b + 3, b + 3, b + 3}, 2);
  EXPECT_EQ(far.find_span(b), 2);
  EXPECT_EQ(far.find_span(b + 0.5), 2);
  EXPECT_EQ(far.find_span(b + 1), 3);
  EXPECT_EQ(far.find_span(b + 2.5), 4);
  EXPECT_EQ(far.find_span(b + 3), 4);
  // One ulp beyond the end (about 1.2e-10 here) is round-off and gets clamped.
  EXPECT_EQ(far.find_span(std::nextafter(b + 3, 2 * b)), 4);
  EXPECT_EQ(far.find_span(std::nextafter(b, 0.0)), 2);
  EXPECT_THROW(far.find_span(b + 3.001), NurbsError);

  const KnotVector negative({-50, -50, -50, -10, 0, 30, 30, 30}, 2);
  EXPECT_EQ(negative.find_span(-50), 2);
  EXPECT_EQ(negative.find_span(-10), 3);
  EXPECT_EQ(negative.find_span(-0.001), 3);
  EXPECT_EQ(negative.find_span(0), 4);
  EXPECT_EQ(negative.find_span(30), 4);
}

TEST(KnotVector, FindSpanClampsRoundOffAndRejectsOutside) {
  const KnotVector kv({-50, -50, -50, -10, 0, 30, 30, 30}, 2);  // domain length 80
  // Within relative 1e-12 of the domain length (8e-11): clamped.
  EXPECT_EQ(kv.find_span(30 + 5e-11), 4);
  EXPECT_EQ(kv.find_span(-50 - 5e-11), 2);
  // Beyond: rejected with the value and the domain in the message.
  const std::string msg = error_message([&] { kv.find_span(30.5); });
  EXPECT_THAT(msg, AllOf(HasSubstr("parameter 30.5"), HasSubstr("outside"), HasSubstr("[-50, 30]")));
  EXPECT_THAT(error_message([&] { kv.find_span(-50 - 1e-9); }), HasSubstr("outside the knot domain"));
  EXPECT_THAT(error_message([&] { kv.find_span(std::nan("")); }), HasSubstr("parameter nan"));
}

TEST(KnotVector, MultiplicityBreakpointsGreville) {
  const KnotVector kv({0, 0, 0, 0, 1, 1, 2, 2, 2, 3, 3, 3, 3}, 3);
  EXPECT_EQ(kv.multiplicity(0.0), 4);
  EXPECT_EQ(kv.multiplicity(1.0), 2);
  EXPECT_EQ(kv.multiplicity(2.0), 3);
  EXPECT_EQ(kv.multiplicity(1.5), 0);
  EXPECT_EQ(kv.interior_breakpoints(), (std::vector<double>{1.0, 2.0}));
  EXPECT_EQ(kv.num_spans(), 3);
  // Greville: averages of knots i+1 .. i+3.
  EXPECT_DOUBLE_EQ(kv.greville(0), 0.0);
  EXPECT_DOUBLE_EQ(kv.greville(1), 1.0 / 3.0);
  EXPECT_DOUBLE_EQ(kv.greville(2), 2.0 / 3.0);
  EXPECT_DOUBLE_EQ(kv.greville(3), 4.0 / 3.0);
  EXPECT_DOUBLE_EQ(kv.greville(8), 3.0);

  const KnotVector open = KnotVector::open_uniform(2, 4);
  EXPECT_EQ(open.greville(0), 0.0);
  EXPECT_EQ(open.greville(1), 0.125);
  EXPECT_EQ(open.greville(2), 0.375);
  EXPECT_EQ(open.greville(5), 1.0);
  EXPECT_TRUE(open.interior_breakpoints().size() == 3u);
}

TEST(KnotVectorValidation, DegreeBelowOne) {
  EXPECT_THAT(error_message([] { KnotVector({0, 0, 1, 1}, 0); }),
              AllOf(HasSubstr("degree must be at least 1"), HasSubstr("got 0")));
}

TEST(KnotVectorValidation, TooFewKnots) {
  EXPECT_THAT(error_message([] { KnotVector({0, 0, 0, 1, 1}, 2); }),
              AllOf(HasSubstr("5 knots"), HasSubstr("at least 2(p+1) = 6")));
}

TEST(KnotVectorValidation, NonFiniteKnot) {
  const double inf = std::numeric_limits<double>::infinity();
  EXPECT_THAT(error_message([&] { KnotVector({0, 0, 0, inf, 1, 1, 1}, 2); }),
              AllOf(HasSubstr("knot[3]"), HasSubstr("not finite")));
  EXPECT_THAT(error_message([] { KnotVector({0, 0, std::nan(""), 1, 1, 1}, 2); }), HasSubstr("knot[2] = nan"));
}

TEST(KnotVectorValidation, Decreasing) {
  EXPECT_THAT(error_message([] { KnotVector({0, 0, 0, 0.5, 0.3, 1, 1, 1}, 2); }),
              HasSubstr("knot vector is not non-decreasing: knot[4] = 0.3 < knot[3] = 0.5"));
}

TEST(KnotVectorValidation, EmptyDomain) {
  EXPECT_THAT(error_message([] { KnotVector({0, 1, 1, 1, 1, 2}, 2); }),
              AllOf(HasSubstr("empty domain"), HasSubstr("positive length")));
}

TEST(KnotVectorValidation, InteriorMultiplicityAboveDegree) {
  EXPECT_THAT(error_message([] { KnotVector({0, 0, 0, 0.5, 0.5, 0.5, 1, 1, 1}, 2); }),
              AllOf(HasSubstr("interior knot 0.5"), HasSubstr("3 times"), HasSubstr("at most the degree 2")));
}

TEST(KnotVectorValidation, EndMultiplicityAbovePPlusOne) {
  EXPECT_THAT(error_message([] { KnotVector({0, 0, 0, 0, 1, 1, 1}, 2); }),
              AllOf(HasSubstr("knot 0 is repeated 4 times"), HasSubstr("p+1 = 3")));
}

TEST(KnotVectorValidation, OpenUniformArguments) {
  EXPECT_THAT(error_message([] { KnotVector::open_uniform(2, 0); }), HasSubstr("spans must be at least 1, got 0"));
  EXPECT_THAT(error_message([] { KnotVector::open_uniform(0, 3); }), HasSubstr("degree must be at least 1"));
  EXPECT_THAT(error_message([] { KnotVector::open_uniform(2, 3, 1.0, 1.0); }),
              AllOf(HasSubstr("[1, 1]"), HasSubstr("begin < end")));
}

TEST(KnotVectorValidation, GrevilleIndexOutOfRange) {
  const KnotVector kv = KnotVector::open_uniform(2, 3);  // 5 basis functions
  EXPECT_THAT(error_message([&] { kv.greville(5); }), AllOf(HasSubstr("index 5"), HasSubstr("0 .. 4")));
  EXPECT_THAT(error_message([&] { kv.greville(-1); }), HasSubstr("out of range"));
}

}  // namespace
}  // namespace shellfrac::nurbs
