#pragma once
// Readers for the parts of a scene beyond the shells themselves; used by scene.cpp.
#include <vector>

#include "sim/json_reader.hpp"
#include "sim/scene.hpp"

namespace shellfrac::sim {

mpm::RigidMotion read_motion(ObjectReader r);
std::vector<ColliderSpec> read_colliders(ObjectReader& root);
std::vector<SolidBody> read_solids(ObjectReader& root);
std::vector<Pin> read_pins(ObjectReader& root, const std::vector<Shell>& shells);

}  // namespace shellfrac::sim
