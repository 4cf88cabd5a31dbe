#include "output/frame_render.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

#include "render_mesh/cracked_tessellation.hpp"
#include "render_mesh/surface_tessellation.hpp"

namespace shellfrac::output {

namespace {

// Leaves out the faces with a vertex marked in `drop`; vertices stay (the vertex count of a frame depends on
// the crack graph only).
void drop_faces_touching(render_mesh::PolyMesh& mesh, const std::vector<unsigned char>& drop) {
  std::vector<int> offsets{0}, vertices;
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int b = mesh.face_offsets[static_cast<size_t>(f)], e = mesh.face_offsets[static_cast<size_t>(f) + 1];
    bool keep = true;
    for (int k = b; k < e; ++k) keep = keep && !drop[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(k)])];
    if (!keep) continue;
    vertices.insert(vertices.end(), mesh.face_vertices.begin() + b, mesh.face_vertices.begin() + e);
    offsets.push_back(static_cast<int>(vertices.size()));
  }
  mesh.face_offsets = std::move(offsets);
  mesh.face_vertices = std::move(vertices);
}

// Cracked patch (thesis sec. 4.9, Algorithm 5): split the R x S grid along the crack, give each side its
// own shadow vertices, and place them with MLS near the crack and NURBS elsewhere.
render_mesh::PolyMesh cracked_mesh(const sim::Simulation& sim, size_t i, const crack2d::CrackGraph& graph,
                                   std::vector<Eigen::Vector3d>* rest) {
  const scene::Model& model = sim.model();
  const shell::ShellPatch& patch = sim.world().shell(i);
  const nurbs::NurbsSurface& ref = patch.reference();
  const render_mesh::ParameterDomain domain{ref.knots_u().domain_begin(), ref.knots_u().domain_end(),
                                            ref.knots_v().domain_begin(), ref.knots_v().domain_end()};
  std::vector<render_mesh::CrackSegment2> segments;
  for (size_t e = 0; e < graph.num_edges(); ++e) segments.push_back({graph.segment(e).a, graph.segment(e).b});
  render_mesh::CrackedTessellationSettings settings;
  settings.resolution_u = model.output.resolution_u;
  settings.resolution_v = model.output.resolution_v;
  settings.shadow_offset = model.cracks.shadow_offset;
  const render_mesh::ParameterMesh mesh = render_mesh::separate_crack_vertices(
      render_mesh::split_parameter_grid(domain, segments, settings), settings.shadow_offset);
  // Every vertex on its own side of the crack (the basis chain of docs/mls.md); a vertex in a piece too
  // small to carry any basis has no position, and the faces touching it are left out (counted in
  // metrics.cracks.basis as removed material).
  std::vector<Eigen::Vector3d> positions(mesh.uv.size());
  std::vector<unsigned char> removed(mesh.uv.size(), 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mesh.uv.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    shell::BasisChainWork work;
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const shell::ShellPatch::SurfacePoint p = patch.surface_point(mesh.uv[k], work);
      positions[k] = p.position;
      removed[k] = p.level == shell::BasisLevel::Removed;
    }
  });
  if (rest) {
    rest->resize(mesh.uv.size());
    tbb::parallel_for(size_t{0}, mesh.uv.size(), [&](size_t k) { (*rest)[k] = ref.point(mesh.uv[k].x(), mesh.uv[k].y()); });
  }
  render_mesh::PolyMesh out = render_mesh::assemble_render_mesh(mesh, domain, std::move(positions), {}, sim.world().shell_name(i));
  if (std::find(removed.begin(), removed.end(), 1) != removed.end()) drop_faces_touching(out, removed);
  return out;
}

std::vector<render_mesh::PolyMesh> meshes_of(const sim::Simulation& sim, std::vector<std::vector<Eigen::Vector3d>>* rest) {
  const sim::World& world = sim.world();
  const scene::Model& model = sim.model();
  std::vector<render_mesh::PolyMesh> meshes(world.num_shells());
  if (rest) rest->assign(world.num_shells(), {});
  for (size_t i = 0; i < world.num_shells(); ++i) {
    const crack2d::CrackGraph* graph = sim.crack_graph(i);
    const int R = model.output.resolution_u, S = model.output.resolution_v;
    if (graph && !graph->empty()) {
      meshes[i] = cracked_mesh(sim, i, *graph, rest ? &(*rest)[i] : nullptr);
      continue;
    }
    meshes[i] = render_mesh::tessellate(world.shell(i).current_surface(), R, S, world.shell_name(i));
    if (rest) (*rest)[i] = render_mesh::tessellate(world.shell(i).reference(), R, S, world.shell_name(i)).positions;
  }
  // Solids as point clouds (one point primitive per particle).
  for (size_t k = 0; k < world.num_solids(); ++k) {
    render_mesh::PolyMesh cloud;
    cloud.name = world.solid_name(k);
    cloud.positions = world.solid(k).x;
    for (int p = 0; p < static_cast<int>(world.solid(k).size()); ++p) cloud.add_face({p});
    meshes.push_back(std::move(cloud));
  }
  return meshes;
}

}  // namespace

std::vector<render_mesh::PolyMesh> render_meshes(const sim::Simulation& sim) { return meshes_of(sim, nullptr); }

FrameMeshes render_frame(const sim::Simulation& sim) {
  FrameMeshes f;
  f.meshes = meshes_of(sim, &f.rest);
  return f;
}

double collider_penetration(const sim::Simulation& sim, const std::vector<render_mesh::PolyMesh>& meshes) {
  double depth = 0;
  for (const auto& c : sim.colliders())
    for (const auto& m : meshes)
      for (const auto& x : m.positions) depth = std::max(depth, -c.signed_distance(x, sim.time()));
  return depth;
}

}  // namespace shellfrac::output
