#pragma once
// The meshes of one frame: every shell's render mesh at the scene's output resolution (cracked patches by
// thesis Algorithm 5), and the solids as point clouds.
#include <vector>

#include "render_mesh/cracked_tessellation.hpp"
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

// render_frame for one simulation frame after frame: a cracked patch's parameter mesh, the basis of each of
// its vertices (ShellPatch::surface_stencil: an MLS fit beside the crack) and its rest positions depend
// on the crack only, so they are kept until the patch's crack changes; each frame then only sums
// the control points. The meshes are the same, bit for bit, as render_frame's.
class FrameRenderer {
 public:
  FrameMeshes render(const sim::Simulation& sim);

  // A cracked patch's render vertices for one crack (the key).
  struct CrackedPatch {
    std::vector<double> key;  // the crack graph's segments and the patch crack's segments
    render_mesh::ParameterMesh mesh;
    std::vector<int> offsets;  // vertex k: stencil entries [offsets[k], offsets[k+1])
    std::vector<int> index;
    std::vector<double> R;
    std::vector<Eigen::Vector3d> offset, rest;
    std::vector<unsigned char> removed;
  };

 private:
  std::vector<CrackedPatch> cache_;  // per shell
};
// Largest depth by which any vertex of `meshes` is inside any collider now (0 if none).
double collider_penetration(const sim::Simulation& sim, const std::vector<render_mesh::PolyMesh>& meshes);

}  // namespace shellfrac::output
