#pragma once
#include <string>

#include "scene/model.hpp"

namespace shellfrac::output {

// Short human-readable description of a built scene, for `shellfrac validate` and the start of a run.
std::string describe_scene(const scene::Model& model);

}  // namespace shellfrac::output
