#pragma once
// The meshes of one frame: every shell's render mesh at the scene's output resolution (cracked patches by
// thesis Algorithm 5), and the solids as point clouds.
#include <vector>

#include "render_mesh/poly_mesh.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::output {

struct FrameMeshes {
  std::vector<render_mesh::PolyMesh> meshes;  // one per shell, then one point cloud per solid
  // Per shell: its render vertices placed on the reference (rest) surface, same order (quality metrics).
  std::vector<std::vector<Eigen::Vector3d>> rest;
};

std::vector<render_mesh::PolyMesh> render_meshes(const sim::Simulation& sim);
// As render_meshes, with the rest positions of the shells' vertices.
FrameMeshes render_frame(const sim::Simulation& sim);
// Largest depth by which any vertex of `meshes` is inside any collider now (0 if none).
double collider_penetration(const sim::Simulation& sim, const std::vector<render_mesh::PolyMesh>& meshes);

}  // namespace shellfrac::output
