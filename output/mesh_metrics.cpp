#include "output/mesh_metrics.hpp"

#include <algorithm>
#include <cmath>

#include "coupling/seam_release.hpp"
#include "render_mesh/seam_joins.hpp"

namespace shellfrac::output {

namespace {

render_mesh::UvSide uv_side(coupling::Side s) {
  switch (s) {
    case coupling::Side::U0: return render_mesh::UvSide::u_min;
    case coupling::Side::U1: return render_mesh::UvSide::u_max;
    case coupling::Side::V0: return render_mesh::UvSide::v_min;
    case coupling::Side::V1: return render_mesh::UvSide::v_max;
  }
  return render_mesh::UvSide::u_min;
}

// The render vertices of one patch on a seam edge, with their seam coordinate (the leader's edge parameter).
std::vector<render_mesh::SeamVertex> seam_side(const sim::Simulation& sim, const render_mesh::PolyMesh& mesh,
                                               size_t patch, coupling::Side side, bool flip) {
  const nurbs::NurbsSurface& surface = sim.world().shell(patch).reference();
  const double u0 = surface.knots_u().domain_begin(), u1 = surface.knots_u().domain_end();
  const double v0 = surface.knots_v().domain_begin(), v1 = surface.knots_v().domain_end();
  // A few shadow offsets in normalised UV take in the shadow vertices of a crack ending on the seam.
  const double tolerance = 3.0 * sim.model().cracks.shadow_offset / std::min(u1 - u0, v1 - v0);
  std::vector<render_mesh::SeamVertex> vs = render_mesh::side_vertices(mesh, uv_side(side), tolerance);
  for (render_mesh::SeamVertex& s : vs) {
    const Eigen::Vector2d& t = mesh.uvs[static_cast<size_t>(s.vertex)];
    const Eigen::Vector2d uv(u0 + t.x() * (u1 - u0), v0 + t.y() * (v1 - v0));
    s.along = coupling::seam_coordinate(surface, side, flip, uv).along;
  }
  return vs;
}


// Typical render-edge length of a mesh at rest: sqrt(rest area / faces).
double typical_edge(const render_mesh::PolyMesh& mesh, const std::vector<Eigen::Vector3d>& rest) {
  render_mesh::PolyMesh at_rest = mesh;
  at_rest.positions = rest;
  double area = 0;
  int faces = 0;
  for (int f = 0; f < at_rest.num_faces(); ++f)
    if (at_rest.face_offsets[static_cast<size_t>(f) + 1] - at_rest.face_offsets[static_cast<size_t>(f)] >= 3) {
      area += render_mesh::face_area(at_rest, f);
      ++faces;
    }
  return faces > 0 ? std::sqrt(area / faces) : 0.0;
}

}  // namespace

std::vector<render_mesh::VertexJoin> seam_vertex_joins(const sim::Simulation& sim, const FrameMeshes& frame) {
  const std::vector<render_mesh::PolyMesh>& meshes = frame.meshes;
  std::vector<render_mesh::VertexJoin> joins;
  const scene::Model& model = sim.model();
  // Render vertices closer than the coarser render grid along the seam are the same seam point.
  const double max_gap = 1.5 / std::min(model.output.resolution_u, model.output.resolution_v);
  for (size_t i = 0; i < model.interfaces.size(); ++i) {
    const coupling::Interface& c = model.interfaces[i].coupling;
    const auto l = static_cast<size_t>(c.leader_patch), f = static_cast<size_t>(c.follower_patch);
    const auto lv = seam_side(sim, meshes[l], l, c.leader_side, false);
    const auto fv = seam_side(sim, meshes[f], f, c.follower_side, c.reversed);
    const double apart = 0.25 * std::min(typical_edge(meshes[l], frame.rest[l]), typical_edge(meshes[f], frame.rest[f]));
    for (const render_mesh::VertexJoin& j :
         render_mesh::seam_joins(static_cast<int>(l), lv, static_cast<int>(f), fv, sim.seam_cracks(i), max_gap)) {
      const Eigen::Vector3d& a = meshes[static_cast<size_t>(j.mesh_a)].positions[static_cast<size_t>(j.vertex_a)];
      const Eigen::Vector3d& b = meshes[static_cast<size_t>(j.mesh_b)].positions[static_cast<size_t>(j.vertex_b)];
      if ((a - b).norm() <= apart) joins.push_back(j);
    }
  }
  return joins;
}

MeshQuality measure_mesh_quality(const sim::Simulation& sim, const FrameMeshes& frame) {
  const size_t shells = sim.world().num_shells();
  const std::vector<render_mesh::PolyMesh> meshes(frame.meshes.begin(), frame.meshes.begin() + static_cast<long>(shells));
  MeshQuality q;
  const render_mesh::PieceStats pieces = render_mesh::piece_stats(meshes, seam_vertex_joins(sim, frame), sim.dx() * sim.dx());
  q.pieces = pieces.pieces;
  q.slivers = pieces.slivers;
  q.sliver_area = pieces.sliver_area;
  for (size_t k = 0; k < pieces.component_area.size(); ++k)
    if (!pieces.component_is_sliver[k]) q.piece_areas.push_back(pieces.component_area[k]);
  for (size_t i = 0; i < shells; ++i) {
    q.max_edge_stretch = std::max(q.max_edge_stretch, render_mesh::max_edge_stretch(meshes[i], frame.rest[i]).ratio);
    const render_mesh::StrandStats s =
        render_mesh::strand_area(meshes[i], frame.rest[i], sim.model().shells[i].material.strand_stretch);
    q.strand_area += s.area;
    q.strand_faces += s.faces;
    q.max_principal_stretch = std::max(q.max_principal_stretch, s.max_principal_stretch);
  }
  return q;
}

}  // namespace shellfrac::output
