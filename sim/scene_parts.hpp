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
// A shell given by name or by index at `key`.
size_t read_shell_reference(ObjectReader& r, const std::string& key, const std::vector<Shell>& shells);
// Patch interfaces (thesis sec. 4.8): validated and built (refinement and coupling operators) here.
std::vector<InterfaceSpec> read_interfaces(ObjectReader& root, const std::vector<Shell>& shells);

}  // namespace shellfrac::sim
