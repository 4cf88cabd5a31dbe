#pragma once
// Scene documents: JSON text or a parsed document to a Scene (strict: every error is a SceneError with
// the file and the JSON pointer), and a Scene back to the JSON document it was read from.
#include <nlohmann/json.hpp>
#include <string>

#include "scene/scene.hpp"

namespace shellfrac::scene {

// Parses and checks a scene document (types, ranges, unknown keys, rules between keys). Checks that need
// the built geometry (shell names, pins, interfaces, cuts against the patch) are made by build().
Scene read_scene(const std::string& json_text, const std::string& source);
Scene read_scene(const nlohmann::json& document, const std::string& source);
// Reads a scene file; relative mesh paths in it are resolved against its folder.
Scene load_scene(const std::string& path);

// The document of a scene: every field that is set, nothing else, so read_scene(to_json(s)) == s and
// to_json(read_scene(d)) == d for every valid document d.
nlohmann::json to_json(const Scene& scene);

// The default scene compiled into the binary (scenes/default.json).
const char* default_scene_json();
Scene default_scene();

}  // namespace shellfrac::scene
