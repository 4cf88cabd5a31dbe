// Every scene shipped in scenes/ is accepted, and the embedded default equals scenes/default.json.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/scene_error.hpp"

namespace shellfrac::scene {

namespace {

namespace fs = std::filesystem;

TEST(SceneFiles, EveryShippedSceneValidates) {
  int count = 0;
  for (const auto& entry : fs::directory_iterator(fs::path(SHELLFRAC_SOURCE_DIR) / "scenes")) {
    if (entry.path().extension() != ".json") continue;
    ++count;
    try {
      const Model s = load_model(entry.path().string());
      EXPECT_GE(s.shells.size(), 1u) << entry.path();
    } catch (const SceneError& e) {
      ADD_FAILURE() << e.what();
    }
  }
  EXPECT_GE(count, 4);
}

TEST(SceneFiles, EmbeddedDefaultMatchesTheFile) {
  std::ifstream in(fs::path(SHELLFRAC_SOURCE_DIR) / "scenes" / "default.json");
  std::stringstream ss;
  ss << in.rdbuf();
  EXPECT_EQ(ss.str(), default_scene_json());
  const Model s = build(default_scene());
  EXPECT_EQ(s.source, "<built-in default>");
  ASSERT_EQ(s.shells.size(), 1u);  // a short cloth scene
  EXPECT_EQ(s.shells[0].surface.num_u(), 18);
  EXPECT_EQ(s.colliders.size(), 1u);
}

}  // namespace
}  // namespace shellfrac::scene
