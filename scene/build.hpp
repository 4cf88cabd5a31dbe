#pragma once
#include "scene/model.hpp"
#include "scene/scene.hpp"

namespace shellfrac::scene {

// Turns a scene into solver inputs: validates it (scene/validate.hpp), applies its quality preset, fills in
// every default and derives the geometry (NURBS patches, pinned control points, coupling operators,
// collider and solid shapes, mesh level sets). Everything that needs that geometry is checked here: shell
// references, pins against the control net, interface edges, prescribed cuts against the patch domain,
// mesh files. Throws SceneError naming scene.source and the JSON pointer of the offending field.
Model build(const Scene& scene);

// Convenience: read_scene + build.
Model build_model(const std::string& json_text, const std::string& source);
Model load_model(const std::string& path);

}  // namespace shellfrac::scene
