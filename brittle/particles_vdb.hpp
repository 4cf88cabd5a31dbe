#pragma once
#include <filesystem>
#include <vector>

#include "brittle/brittle_solid.hpp"

namespace shellfrac::brittle {

// Writes the particles of a solid as an OpenVDB Points grid named "particles" (readable by Houdini and
// Blender): positions P (world, or material positions with use_rest), and per point the attributes
// v (velocity), damage (c), c_his, tau (damage time, -1 while not fully damaged), id (particle index).
// The file is written next to its destination and renamed into place, so an existing file is never left
// half-written. Throws std::runtime_error naming the file on failure.
void write_particles_vdb(const BrittleSolid& solid, const std::filesystem::path& file, bool use_rest = false);

// What write_particles_vdb stored, in particle order (read back through the id attribute).
struct ParticlePoints {
  std::vector<Vec3> position, velocity;
  std::vector<float> damage, c_his, tau;
};
ParticlePoints read_particles_vdb(const std::filesystem::path& file);

}  // namespace shellfrac::brittle
