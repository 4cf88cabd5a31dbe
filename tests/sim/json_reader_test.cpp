#include "sim/json_reader.hpp"

#include <gmock/gmock.h>
#include <gtest/gtest.h>

namespace shellfrac::sim {
namespace {

using ::testing::HasSubstr;

TEST(Range, BoundsAndWording) {
  EXPECT_TRUE(Range::positive().contains(1e-300));
  EXPECT_FALSE(Range::positive().contains(0.0));
  EXPECT_TRUE(Range::non_negative().contains(0.0));
  EXPECT_FALSE(Range::open(-1, 0.5).contains(0.5));
  EXPECT_FALSE(Range::open(-1, 0.5).contains(-1));
  EXPECT_TRUE(Range::open(-1, 0.5).contains(0.4999));
  EXPECT_TRUE(Range::left_open(0, 1).contains(1.0));
  EXPECT_FALSE(Range::any().contains(std::numeric_limits<double>::quiet_NaN()));
  EXPECT_FALSE(Range::any().contains(std::numeric_limits<double>::infinity()));
  EXPECT_EQ(Range::positive().describe(), "> 0");
  EXPECT_EQ(Range::open(-1, 0.5).describe(), "in (-1, 0.5)");
  EXPECT_EQ(Range::closed(1, 10).describe(), "in [1, 10]");
}

TEST(ObjectReader, ReadsValuesAndDefaults) {
  const Json j = Json::parse(R"({"a": 2.5, "n": 3, "s": "x", "b": true, "v": [1, 2, 3]})");
  ObjectReader r(j, "/root", "f.json");
  EXPECT_DOUBLE_EQ(r.number("a"), 2.5);
  EXPECT_EQ(r.integer("n"), 3);
  EXPECT_EQ(r.string("s"), "x");
  EXPECT_TRUE(r.boolean_or("b", false));
  EXPECT_EQ(r.numbers("v", 3), (std::vector<double>{1, 2, 3}));
  EXPECT_DOUBLE_EQ(r.number_or("missing", 7.0), 7.0);
  EXPECT_NO_THROW(r.finish());
}

TEST(ObjectReader, UnknownKeyListsAllowedKeys) {
  const Json j = Json::parse(R"({"alpha": 1, "betta": 2})");
  ObjectReader r(j, "/obj", "f.json");
  r.number("alpha");
  r.number_or("beta", 0.0);
  try {
    r.finish();
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/obj/betta");
    EXPECT_THAT(e.message(), HasSubstr("allowed here are alpha, beta"));
  }
}

TEST(ObjectReader, TypeErrorsNameTheFoundType) {
  const Json j = Json::parse(R"({"a": "1", "n": 1.5, "arr": [1, "x"]})");
  ObjectReader r(j, "", "f.json");
  try {
    r.number("a");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/a");
    EXPECT_THAT(e.message(), HasSubstr("expected a number, got string"));
  }
  try {
    r.integer("n");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_THAT(e.message(), HasSubstr("expected an integer, got number 1.5"));
  }
  try {
    r.numbers("arr", 2);
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/arr/1");
  }
}

TEST(ObjectReader, NonObjectIsRejected) {
  const Json j = Json::parse("[1, 2]");
  try {
    ObjectReader r(j, "/x", "f.json");
    FAIL();
  } catch (const SceneError& e) {
    EXPECT_EQ(e.json_path(), "/x");
    EXPECT_THAT(e.message(), HasSubstr("expected an object, got array"));
  }
}

}  // namespace
}  // namespace shellfrac::sim
