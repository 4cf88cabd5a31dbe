#include "output/frame_render.hpp"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>

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

// What a cracked patch's render vertices depend on besides the control points: the crack graph it is
// tessellated along and the crack its bases see (the same crack, by index).
std::vector<double> crack_key(const crack2d::CrackGraph& graph, const shell::ShellPatch& patch) {
  std::vector<double> key;
  key.reserve(4 * graph.num_edges() + 1);
  for (size_t e = 0; e < graph.num_edges(); ++e) {
    const auto& s = graph.segment(e);
    key.insert(key.end(), {s.a.x(), s.a.y(), s.b.x(), s.b.y()});
  }
  key.push_back(patch.crack() ? static_cast<double>(patch.crack()->num_segments()) : -1.0);
  return key;
}

render_mesh::ParameterDomain domain_of(const shell::ShellPatch& patch) {
  const nurbs::NurbsSurface& ref = patch.reference();
  return {ref.knots_u().domain_begin(), ref.knots_u().domain_end(), ref.knots_v().domain_begin(),
          ref.knots_v().domain_end()};
}

// Cracked patch (thesis sec. 4.9, Algorithm 5), the part that depends on the crack only: split the R x S
// grid along the crack, give each side its own shadow vertices, and find the basis that places each
// vertex (MLS near the crack, NURBS elsewhere; the basis chain of docs/mls.md) and its rest position.
void build_cracked_patch(const sim::Simulation& sim, size_t i, const crack2d::CrackGraph& graph,
                         FrameRenderer::CrackedPatch& c) {
  const scene::Model& model = sim.model();
  const shell::ShellPatch& patch = sim.world().shell(i);
  std::vector<render_mesh::CrackSegment2> segments;
  for (size_t e = 0; e < graph.num_edges(); ++e) segments.push_back({graph.segment(e).a, graph.segment(e).b});
  render_mesh::CrackedTessellationSettings settings;
  settings.resolution_u = model.output.resolution_u;
  settings.resolution_v = model.output.resolution_v;
  settings.shadow_offset = model.cracks.shadow_offset;
  c.mesh = render_mesh::separate_crack_vertices(render_mesh::split_parameter_grid(domain_of(patch), segments, settings),
                                                settings.shadow_offset);
  const size_t n = c.mesh.uv.size();
  std::vector<shell::ShellPatch::SurfaceStencil> stencils(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 256), [&](const tbb::blocked_range<size_t>& r) {
    shell::BasisChainWork work;
    for (size_t k = r.begin(); k != r.end(); ++k) patch.surface_stencil(c.mesh.uv[k], work, stencils[k]);
  });
  c.offsets.assign(1, 0);
  c.index.clear();
  c.R.clear();
  c.offset.resize(n);
  c.removed.resize(n);
  for (size_t k = 0; k < n; ++k) {
    const shell::ShellPatch::SurfaceStencil& st = stencils[k];
    c.index.insert(c.index.end(), st.index.begin(), st.index.end());
    c.R.insert(c.R.end(), st.R.begin(), st.R.end());
    c.offsets.push_back(static_cast<int>(c.index.size()));
    c.offset[k] = st.offset;
    // A vertex in a piece too small to carry any basis has no position; the faces touching it are left out
    // (counted in metrics.cracks.basis as removed material).
    c.removed[k] = st.level == shell::BasisLevel::Removed;
  }
  const nurbs::NurbsSurface& ref = patch.reference();
  c.rest.resize(n);
  tbb::parallel_for(size_t{0}, n, [&](size_t k) { c.rest[k] = ref.point(c.mesh.uv[k].x(), c.mesh.uv[k].y()); });
}

// The cracked patch's mesh at the current control points.
render_mesh::PolyMesh cracked_mesh(const sim::Simulation& sim, size_t i, const FrameRenderer::CrackedPatch& c) {
  const shell::ShellPatch& patch = sim.world().shell(i);
  std::vector<Eigen::Vector3d> positions(c.mesh.uv.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, positions.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t k = r.begin(); k != r.end(); ++k) {
      const auto b = static_cast<size_t>(c.offsets[k]), e = static_cast<size_t>(c.offsets[k + 1]);
      positions[k] = patch.stencil_position(c.index.data() + b, c.R.data() + b, e - b, c.offset[k]);
    }
  });
  render_mesh::PolyMesh out =
      render_mesh::assemble_render_mesh(c.mesh, domain_of(patch), std::move(positions), {}, sim.world().shell_name(i));
  if (std::find(c.removed.begin(), c.removed.end(), 1) != c.removed.end()) drop_faces_touching(out, c.removed);
  return out;
}

std::vector<render_mesh::PolyMesh> meshes_of(const sim::Simulation& sim, std::vector<std::vector<Eigen::Vector3d>>* rest,
                                             std::vector<FrameRenderer::CrackedPatch>& cache) {
  const sim::World& world = sim.world();
  const scene::Model& model = sim.model();
  std::vector<render_mesh::PolyMesh> meshes(world.num_shells());
  if (rest) rest->assign(world.num_shells(), {});
  cache.resize(world.num_shells());
  for (size_t i = 0; i < world.num_shells(); ++i) {
    const crack2d::CrackGraph* graph = sim.crack_graph(i);
    const int R = model.output.resolution_u, S = model.output.resolution_v;
    if (graph && !graph->empty()) {
      std::vector<double> key = crack_key(*graph, world.shell(i));
      if (key != cache[i].key || cache[i].offsets.empty()) {
        build_cracked_patch(sim, i, *graph, cache[i]);
        cache[i].key = std::move(key);
      }
      meshes[i] = cracked_mesh(sim, i, cache[i]);
      if (rest) (*rest)[i] = cache[i].rest;
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

std::vector<render_mesh::PolyMesh> render_meshes(const sim::Simulation& sim) {
  std::vector<FrameRenderer::CrackedPatch> cache;
  return meshes_of(sim, nullptr, cache);
}

FrameMeshes render_frame(const sim::Simulation& sim) { return FrameRenderer().render(sim); }

FrameMeshes FrameRenderer::render(const sim::Simulation& sim) {
  FrameMeshes f;
  f.meshes = meshes_of(sim, &f.rest, cache_);
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
