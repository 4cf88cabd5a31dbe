// Simulation.metrics(), render_mesh() and crack_graph(): values computed from the current state on request.
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "output/frame_render.hpp"
#include "output/mesh_metrics.hpp"
#include "python/simulation_metrics.hpp"
#include "render_mesh/mesh_quality.hpp"
#include "render_mesh/triangulation.hpp"

namespace shellfrac::python {

namespace {

using State = SimulationState;

// Everything metrics() reports, gathered without the GIL.
struct MetricValues {
  double time = 0, stable_dt = 0, kinetic = 0, elastic = 0, max_damage = 0, max_plastic = 0;
  long steps = 0;
  double dt_min = 0, dt_max = 0;
  Eigen::Vector3d momentum = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> pin_reactions;
  sim::CrackStats cracks;
  std::vector<std::pair<std::string, double>> stage_seconds;
  std::optional<output::MeshQuality> mesh;
};

MetricValues gather(const sim::Simulation& sim, bool mesh) {
  MetricValues v;
  const sim::World& w = sim.world();
  v.time = sim.time();
  v.steps = sim.steps();
  v.dt_min = sim.min_dt();
  v.dt_max = sim.max_dt();
  v.stable_dt = sim.stable_dt();
  v.kinetic = sim.kinetic_energy();
  v.momentum = sim.linear_momentum();
  for (size_t i = 0; i < w.num_shells(); ++i) {
    const shell::ShellPatch& p = w.shell(i);
    v.elastic += p.elastic_energy();
    v.max_plastic = std::max(v.max_plastic, p.max_plastic_strain());
    if (p.fractures()) v.max_damage = std::max(v.max_damage, p.max_damage());
    v.pin_reactions.push_back(sim.pin_reaction(i));
  }
  v.cracks = sim.crack_stats();
  v.stage_seconds = sim.timer().seconds();
  if (mesh) v.mesh = output::measure_mesh_quality(sim, output::render_frame(sim));
  return v;
}

py::list vec3(const Eigen::Vector3d& x) { return py::cast(std::vector<double>{x.x(), x.y(), x.z()}); }

py::dict to_dict(const MetricValues& v, const sim::Simulation& sim) {
  py::dict d;
  d["time"] = v.time;
  d["steps"] = v.steps;
  d["dt_min"] = v.steps ? py::object(py::float_(v.dt_min)) : py::object(py::none());
  d["dt_max"] = v.steps ? py::object(py::float_(v.dt_max)) : py::object(py::none());
  d["stable_dt"] = v.stable_dt;
  d["kinetic_energy"] = v.kinetic;
  d["elastic_energy"] = v.elastic;
  d["linear_momentum"] = vec3(v.momentum);
  d["max_damage"] = v.max_damage;
  d["max_plastic_strain"] = v.max_plastic;
  py::dict pins;
  for (size_t i = 0; i < v.pin_reactions.size(); ++i) pins[py::str(sim.world().shell_name(i))] = vec3(v.pin_reactions[i]);
  d["pin_reactions"] = pins;
  d["particle_counts"] = py::dict(py::arg("solid_particles") = sim.num_solid_particles(),
                                  py::arg("control_points") = sim.num_control_points(),
                                  py::arg("shear_particles") = sim.num_shear_particles(),
                                  py::arg("quadrature_points") = sim.num_quadrature_points());
  const sim::CrackStats& c = v.cracks;
  py::dict cracks;
  sim::CrackCounters::visit([&](const char* name, auto counter) { cracks[name] = c.*counter; });
  cracks["first_mls_failure"] = c.first_mls_failure.empty() ? py::object(py::none()) : py::object(py::str(c.first_mls_failure));
  cracks["first_sliver"] = c.first_sliver.empty() ? py::object(py::none()) : py::object(py::str(c.first_sliver));
  d["cracks"] = cracks;
  py::dict stages;
  for (const auto& [name, seconds] : v.stage_seconds) stages[py::str(name)] = seconds;
  d["stage_seconds"] = stages;
  if (v.mesh) {
    const output::MeshQuality& q = *v.mesh;
    d["pieces"] = q.pieces;
    d["slivers"] = py::dict(py::arg("count") = q.slivers, py::arg("area") = q.sliver_area);
    d["piece_areas"] = q.piece_areas;
    d["max_edge_stretch"] = q.max_edge_stretch;
    d["strand_area"] = q.strand_area;
    d["strand_faces"] = q.strand_faces;
    d["max_principal_stretch"] = q.max_principal_stretch;
  }
  return d;
}

// One shell's render mesh with its faces' piece labels and a triangulation for plotting.
struct ShellMesh {
  render_mesh::PolyMesh mesh;
  std::vector<int> labels;
  render_mesh::Triangulation triangles;
};

ShellMesh shell_mesh(const sim::Simulation& sim, size_t shell) {
  const output::FrameMeshes frame = output::render_frame(sim);
  const size_t shells = sim.world().num_shells();
  const std::vector<render_mesh::PolyMesh> meshes(frame.meshes.begin(), frame.meshes.begin() + static_cast<long>(shells));
  // The pieces as metrics.pieces counts them: across patches and coupled seams, slivers below dx^2 included.
  const render_mesh::PieceStats pieces =
      render_mesh::piece_stats(meshes, output::seam_vertex_joins(sim, frame), sim.dx() * sim.dx());
  ShellMesh out{meshes[shell], pieces.face_label[shell], {}};
  out.triangles = render_mesh::triangulate(out.mesh);
  return out;
}

template <class T>
py::array_t<T> rows(const std::vector<T>& flat, py::ssize_t cols) {
  py::array_t<T> a({static_cast<py::ssize_t>(flat.size()) / cols, cols});
  std::copy(flat.begin(), flat.end(), a.mutable_data());
  return a;
}

py::dict mesh_dict(const ShellMesh& m) {
  std::vector<double> xyz, uv;
  for (const auto& p : m.mesh.positions) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  for (const auto& t : m.mesh.uvs) uv.insert(uv.end(), {t.x(), t.y()});
  std::vector<int> tri;
  const render_mesh::PolyMesh& t = m.triangles.mesh;
  std::vector<int> tri_face;
  for (int f = 0; f < t.num_faces(); ++f) {
    const int b = t.face_offsets[static_cast<size_t>(f)], e = t.face_offsets[static_cast<size_t>(f) + 1];
    if (e - b != 3) continue;  // points and lines carry no area
    tri.insert(tri.end(), t.face_vertices.begin() + b, t.face_vertices.begin() + e);
    tri_face.push_back(m.triangles.source_face[static_cast<size_t>(f)]);
  }
  py::dict d;
  d["name"] = m.mesh.name;
  d["vertices"] = rows(xyz, 3);
  d["uvs"] = rows(uv, 2);
  d["face_offsets"] = py::array_t<int>(static_cast<py::ssize_t>(m.mesh.face_offsets.size()), m.mesh.face_offsets.data());
  d["face_vertices"] = py::array_t<int>(static_cast<py::ssize_t>(m.mesh.face_vertices.size()), m.mesh.face_vertices.data());
  py::list faces;
  for (int f = 0; f < m.mesh.num_faces(); ++f) {
    const int b = m.mesh.face_offsets[static_cast<size_t>(f)], e = m.mesh.face_offsets[static_cast<size_t>(f) + 1];
    faces.append(py::array_t<int>(e - b, m.mesh.face_vertices.data() + b));
  }
  d["faces"] = faces;
  d["labels"] = py::array_t<int>(static_cast<py::ssize_t>(m.labels.size()), m.labels.data());
  d["triangles"] = rows(tri, 3);
  d["triangle_faces"] = py::array_t<int>(static_cast<py::ssize_t>(tri_face.size()), tri_face.data());
  return d;
}

}  // namespace

void bind_simulation_outputs(py::class_<SimulationState>& c) {
  c.def(
      "metrics",
      [](py::object self, bool mesh) {
        State& s = state_of(self);
        const MetricValues v = s.locked([&] { return gather(*s.sim, mesh); });
        return to_dict(v, *s.sim);
      },
      py::arg("mesh") = false,
      "The state's numbers as a dict: time, steps, dt_min/dt_max, stable_dt, kinetic_energy, elastic_energy, "
      "linear_momentum, max_damage, max_plastic_strain, pin_reactions (per shell), particle_counts, cracks (the "
      "crack machinery's counters, named as in summary.json), stage_seconds. With mesh=True also the render "
      "mesh's pieces, slivers, piece_areas, max_edge_stretch, strand_area, strand_faces, max_principal_stretch "
      "(as metrics in summary.json; docs/cli.md). Works after a NumericalError (values may be NaN).");
  c.def(
      "render_mesh",
      [](py::object self, py::object shell) {
        State& s = state_of(self);
        const size_t i = shell_index(*s.sim, shell);
        const ShellMesh m = s.locked([&] { return shell_mesh(*s.sim, i); });
        return mesh_dict(m);
      },
      py::arg("shell") = 0,
      "The shell's render mesh now, as written to the frame files (cracked by thesis Algorithm 5), as a dict of "
      "copies: vertices (n, 3), uvs (n, 2) in the parameter plane, faces (list of index arrays; also as CSR "
      "face_offsets/face_vertices), labels (per face: its piece, numbered across all shells and coupled seams as "
      "metrics()['pieces'] counts them; -1 for faces without area), triangles (t, 3) with triangle_faces (t,) "
      "for plotting.");
  c.def(
      "crack_graph",
      [](py::object self, py::object shell) -> py::object {
        State& s = state_of(self);
        const size_t i = shell_index(*s.sim, shell);
        const crack2d::CrackGraph* g = s.sim->crack_graph(i);
        if (!g) return py::none();
        std::vector<double> uv;
        std::vector<int> edges;
        s.locked([&] {
          for (const auto& v : g->vertices()) uv.insert(uv.end(), {v.x(), v.y()});
          for (const auto& e : g->edges()) edges.insert(edges.end(), {e[0], e[1]});
        });
        return py::make_tuple(rows(uv, 2), rows(edges, 2));
      },
      py::arg("shell") = 0,
      "The shell's crack graph in its parameter plane as (vertices (n, 2), edges (m, 2) vertex indices), copies "
      "(the graph grows while cracks run); None when the shell cannot crack.");
}

}  // namespace shellfrac::python
