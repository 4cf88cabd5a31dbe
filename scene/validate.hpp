#pragma once
#include "scene/scene.hpp"

namespace shellfrac::scene {

// Checks a scene's values the way the JSON reader checks a document: required fields, ranges, allowed
// words and the rules between fields. Throws SceneError naming scene.source and the JSON pointer of the
// first problem. (build() calls it; references between parts are checked there.)
void validate(const Scene& scene);

}  // namespace shellfrac::scene
