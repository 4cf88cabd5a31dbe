// The short version of the scene-reader fuzz target (tests/robust/fuzz/): every shipped scene mutated
// 150 times by a fixed-seed random generator (byte flips, deletions, duplicated spans and inserted
// hostile tokens such as 1e999, control characters, deep brackets, duplicate keys). Each input must end
// accepted or refused as bad input; any other exception fails the test. Deterministic (fixed seed).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "fuzz/scene_reader_target.hpp"

namespace shellfrac::fuzz {
namespace {

namespace fs = std::filesystem;

const char* const kTokens[] = {"1e999", "-1e999", "1e308", "-0", "0", "1e-320", "null", "true", "[]", "{}", "\"",
                               "\\u0000", "\\n", "\"\\u0007\"", ",", ":", "}", "]", "[[[[[[[[[[[[[[[[", "\"name\": \"x\",",
                               "\"E\": 1, \"E\": 2,", "2147483648", "-2147483649", "1e9", "\"mesh\"", "\"/dev/zero\"",
                               "\"control_net\"", "\"cells\": [10000, 10000],", "\"refine\": [64, 64],", "\xff\xfe"};

std::string mutate(std::string text, std::mt19937& rng) {
  const int edits = 1 + static_cast<int>(rng() % 4);
  for (int k = 0; k < edits && !text.empty(); ++k) {
    const size_t at = rng() % text.size();
    switch (rng() % 5) {
      case 0: text[at] = static_cast<char>(rng() % 256); break;                  // flip a byte
      case 1: text.erase(at, 1 + rng() % 16); break;                            // delete a span
      case 2: text.insert(at, text.substr(rng() % text.size(), 1 + rng() % 64)); break;  // duplicate a span
      default: {                                                                // insert a hostile token
        const size_t n = sizeof kTokens / sizeof kTokens[0];
        text.insert(at, kTokens[rng() % n]);
      }
    }
  }
  return text;
}

TEST(SceneReaderMutation, EveryMutantIsAcceptedOrRefusedAsBadInput) {
  std::mt19937 rng(14);
  int accepted = 0, refused = 0;
  std::vector<fs::path> scenes;
  for (const auto& e : fs::directory_iterator(fs::path(SHELLFRAC_SOURCE_DIR) / "scenes"))
    if (e.path().extension() == ".json") scenes.push_back(e.path());
  std::sort(scenes.begin(), scenes.end());
  ASSERT_GE(scenes.size(), 4u);
  for (const fs::path& p : scenes) {
    std::ifstream in(p);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::string original = ss.str();
    EXPECT_EQ(check_scene_text(original), p.filename() == "cloth-drape-mesh.json" ? 1 : 0) << p;  // its mesh is not found here
    for (int i = 0; i < 150; ++i) {
      const std::string input = mutate(original, rng);
      int outcome = -1;
      EXPECT_NO_THROW(outcome = check_scene_text(input)) << p << " mutant " << i << ":\n" << input;
      (outcome == 0 ? accepted : refused) += outcome >= 0;
    }
  }
  // Both outcomes occur: the mutations neither all break the syntax nor all slip through unchanged.
  EXPECT_GT(accepted, 0);
  EXPECT_GT(refused, accepted);
  EXPECT_EQ(accepted + refused, static_cast<int>(scenes.size()) * 150);
}

}  // namespace
}  // namespace shellfrac::fuzz
