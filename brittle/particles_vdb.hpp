#pragma once
#include <filesystem>
#include <string>
#include <vector>

#include "brittle/brittle_solid.hpp"

namespace shellfrac::brittle {

// Writes the particles of a solid as an OpenVDB Points grid named "particles" (readable by Houdini and
// Blender): positions P (world, or material positions with use_rest), and per point the attributes
// v (velocity), damage (c), c_his, tau (damage time, -1 while not fully damaged), id (particle index).
// Returns the bytes of the .vdb file (the same as openvdb::io::File writes): the caller writes them with
// checked I/O (output/brittle_output.cpp uses render_mesh::write_file_atomically), since openvdb's own
// file writer does not check its writes.
std::string particles_vdb_bytes(const BrittleSolid& solid, bool use_rest = false);

// What particles_vdb_bytes stored, in particle order (read back through the id attribute).
struct ParticlePoints {
  std::vector<Vec3> position, velocity;
  std::vector<float> damage, c_his, tau;
};
ParticlePoints read_particles_vdb(const std::filesystem::path& file);

}  // namespace shellfrac::brittle
