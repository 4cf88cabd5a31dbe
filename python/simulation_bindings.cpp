// shellfrac.Simulation: a running scene (sim/simulation.hpp) stepped from Python with the GIL released,
// its particles as read-only NumPy views, its render meshes and metrics.
#include <pybind11/stl.h>
#include <tbb/info.h>

#include <chrono>

#include "python/arrays.hpp"
#include "python/simulation_metrics.hpp"
#include "python/simulation_state.hpp"

namespace shellfrac::python {

SimulationState::SimulationState(const scene::Scene& scene, int n) {
  if (n < 0) throw py::value_error("threads must be >= 0 (0: all cores), got " + std::to_string(n));
  threads = n > 0 ? n : tbb::info::default_concurrency();
  arena = std::make_unique<tbb::task_arena>(threads);
  py::gil_scoped_release nogil;
  arena->execute([&] { sim = std::make_unique<sim::Simulation>(scene); });
  publish();
}

namespace {

using State = SimulationState;

// Steps through f (which calls advance_to or step) and turns what happened into Python: Ctrl-C between
// steps becomes KeyboardInterrupt, a NumericalError is remembered for `error` and re-raised.
template <class F>
long stepping(State& s, F&& f) {
  bool interrupted = false;
  // Asked after every step. Every 10 ms of stepping it takes the GIL back for the signal check
  // (PyErr_CheckSignals runs the Python signal handlers; in a thread other than the main one it does
  // nothing): not after every step, since a busy Python thread can hold the GIL for its whole switch
  // interval (5 ms), longer than a small scene's step.
  auto last_check = std::chrono::steady_clock::now();
  const std::function<bool()> should_stop = [&] {
    s.publish();
    const auto now = std::chrono::steady_clock::now();
    if (now - last_check < std::chrono::milliseconds(10)) return false;
    last_check = now;
    py::gil_scoped_acquire gil;
    if (PyErr_CheckSignals() != 0) interrupted = true;  // the KeyboardInterrupt is now set on this thread
    return interrupted;
  };
  long taken = 0;
  try {
    taken = s.locked([&] { return f(should_stop); });
  } catch (const core::NumericalError& e) {
    s.publish();
    s.error = e.what();
    throw;
  }
  s.publish();
  if (interrupted) throw py::error_already_set();
  return taken;
}

}  // namespace

size_t shell_index(const sim::Simulation& sim, const py::handle& shell) {
  const sim::World& w = sim.world();
  if (py::isinstance<py::str>(shell)) {
    const auto name = shell.cast<std::string>();
    for (size_t i = 0; i < w.num_shells(); ++i)
      if (w.shell_name(i) == name) return i;
    throw py::key_error("no shell named \"" + name + "\"");
  }
  const long i = shell.cast<long>();
  if (i < 0 || static_cast<size_t>(i) >= w.num_shells())
    throw py::index_error("shell " + std::to_string(i) + " out of range (the scene has " +
                          std::to_string(w.num_shells()) + " shell(s))");
  return static_cast<size_t>(i);
}

size_t solid_index(const sim::Simulation& sim, const py::handle& solid) {
  const sim::World& w = sim.world();
  if (py::isinstance<py::str>(solid)) {
    const auto name = solid.cast<std::string>();
    for (size_t k = 0; k < w.num_solids(); ++k)
      if (w.solid_name(k) == name) return k;
    throw py::key_error("no solid named \"" + name + "\"");
  }
  const long k = solid.cast<long>();
  if (k < 0 || static_cast<size_t>(k) >= w.num_solids())
    throw py::index_error("solid " + std::to_string(k) + " out of range (the scene has " +
                          std::to_string(w.num_solids()) + " solid(s))");
  return static_cast<size_t>(k);
}

namespace {

// Stepping, time, names and energy.
void bind_stepping(py::class_<State>& c) {
  c.def(
      "step",
      [](py::object self, std::optional<double> dt) {
        State& s = state_of(self);
        const double h = dt ? *dt : s.locked([&] { return s.sim->stable_dt(); });
        if (!(h > 0)) throw py::value_error("dt must be > 0");
        stepping(s, [&](const std::function<bool()>&) {
          s.sim->step(h);
          return 1L;
        });
        return h;
      },
      py::arg("dt") = py::none(),
      "One step of size dt (default: the largest stable step now, stable_dt()). Returns the dt used. Raises "
      "NumericalError naming the particle, shell and step.");
  c.def(
      "advance_to",
      [](py::object self, double t) {
        State& s = state_of(self);
        return stepping(s, [&](const std::function<bool()>& stop) { return s.sim->advance_to(t, stop); });
      },
      py::arg("t"),
      "Steps until simulated time t in equal steps no larger than the stable step (as `shellfrac run` does "
      "between frames). Returns the steps taken. Ctrl-C raises KeyboardInterrupt after the current step; the "
      "simulation stays usable (time < t then).");
  c.def("stable_dt", [](py::object self) { State& s = state_of(self); return s.locked([&] { return s.sim->stable_dt(); }); },
        "Largest stable step now: cfl x the elastic-wave bound, limited by the current particle speeds.");
  c.def_property_readonly("time", [](py::object self) { return state_of(self).time.load(); },
                          "Simulated time [s]. Safe to read from another thread while a step runs.");
  c.def_property_readonly("steps", [](py::object self) { return state_of(self).steps.load(); },
                          "Steps taken. Safe to read from another thread while a step runs.");
  c.def_property_readonly("threads", [](py::object self) { return state_of(self).threads; }, "Thread count of this simulation.");
  c.def_property_readonly("dx", [](py::object self) { return state_of(self).sim->dx(); }, "Grid spacing h [m].");
  c.def_property_readonly("error", [](py::object self) { return state_of(self).error; },
                          "Message of the NumericalError the last failing step raised, or None.");
  c.def_property_readonly(
      "shell_names",
      [](py::object self) {
        std::vector<std::string> names;
        const sim::World& w = state_of(self).sim->world();
        for (size_t i = 0; i < w.num_shells(); ++i) names.push_back(w.shell_name(i));
        return names;
      },
      "Names of the shells, in scene order.");
  c.def_property_readonly(
      "solid_names",
      [](py::object self) {
        std::vector<std::string> names;
        const sim::World& w = state_of(self).sim->world();
        for (size_t k = 0; k < w.num_solids(); ++k) names.push_back(w.solid_name(k));
        return names;
      },
      "Names of the solids, in scene order.");
  c.def_property_readonly("kinetic_energy",
                          [](py::object self) {
                            State& s = state_of(self);
                            return s.locked([&] { return s.sim->kinetic_energy(); });
                          },
                          "Kinetic energy of all particles [J] (sum 1/2 m |v|^2).");
}

// Type II: control points x_i, v_i, m_i (thesis sec. 4.3.1).
void bind_control_points(py::class_<State>& c) {
  c.def(
      "positions", [](py::object self, py::object shell) {
        const sim::Simulation& sim = *state_of(self).sim;
        return view_vec3(sim.world().shell(shell_index(sim, shell)).x, self);
      },
      py::arg("shell") = 0, "Control-point positions x_i of a shell, (n, 3) read-only view, row k = control point k "
                            "(k = i + num_u * j on the control net).");
  c.def(
      "velocities", [](py::object self, py::object shell) {
        const sim::Simulation& sim = *state_of(self).sim;
        return view_vec3(sim.world().shell(shell_index(sim, shell)).v, self);
      },
      py::arg("shell") = 0, "Control-point velocities v_i, (n, 3) read-only view.");
  c.def(
      "masses", [](py::object self, py::object shell) {
        const sim::Simulation& sim = *state_of(self).sim;
        return view_scalars(sim.world().shell(shell_index(sim, shell)).mass, self);
      },
      py::arg("shell") = 0,
      "Lumped control-point masses m_i of the material [kg], (n,) read-only view (without the added mass of "
      "cracks.mass_scaling, which kinetic_energy and the momentum include).");
  c.def(
      "set_velocities",
      [](py::object self, py::object shell, const py::array_t<double, py::array::c_style | py::array::forcecast>& v) {
        State& s = state_of(self);
        const size_t i = shell_index(*s.sim, shell);
        const size_t n = s.sim->world().shell(i).v.size();
        if (v.ndim() != 2 || v.shape(1) != 3 || static_cast<size_t>(v.shape(0)) != n)
          throw py::value_error("velocities must have shape (" + std::to_string(n) + ", 3)");
        std::vector<Eigen::Vector3d> in(n);
        for (size_t k = 0; k < n; ++k) in[k] = Eigen::Vector3d(v.at(k, 0), v.at(k, 1), v.at(k, 2));
        s.locked([&] {
          sim::Span<Eigen::Vector3d> out = s.sim->velocities(i);
          for (size_t k = 0; k < n; ++k) out[k] = in[k];
        });
      },
      py::arg("shell"), py::arg("v"),
      "Overwrites a shell's control-point velocities (an (n, 3) array copied in), e.g. to set up an initial state.");
}

// Type III shear particles and Type IV quadrature points (thesis sec. 4.3.2, 4.3.3, 4.4.1).
void bind_shell_points(py::class_<State>& c) {
  // Type III: shear particles, one per cell (thesis sec. 4.3.2).
  c.def(
      "shear_particles", [](py::object self, py::object shell) {
        const sim::Simulation& sim = *state_of(self).sim;
        const shell::ShearParticles& p = sim.world().shell(shell_index(sim, shell)).shear;
        py::dict d;
        d["x"] = view_vec3(p.x, self);
        d["v"] = view_vec3(p.v, self);
        d["mass"] = view_scalars(p.mass, self);
        d["director"] = view_vec3(p.director, self);
        d["volume"] = view_scalars(p.volume, self);
        d["stress"] = view_mat3(p.stress, self);
        return d;
      },
      py::arg("shell") = 0,
      "Type III particles of a shell as read-only views: x (n, 3), v (n, 3), mass (n,), director (the elastic "
      "d_3, n x 3), volume (n,), stress (the grid stress term, n x 3 x 3).");

  // Type IV: quadrature points (thesis sec. 4.3.3, 4.4.1).
  c.def(
      "quadrature_parameters", [](py::object self, py::object shell) {
        const sim::Simulation& sim = *state_of(self).sim;
        return view_vec2(sim.world().shell(shell_index(sim, shell)).inplane_parameters(), self);
      },
      py::arg("shell") = 0, "Parameter coordinates (xi_1, xi_2) of the in-plane quadrature points, (n, 2) read-only view.");
  c.def(
      "damage", [](py::object self, py::object shell) -> py::object {
        const sim::Simulation& sim = *state_of(self).sim;
        const shell::ShellPatch& p = sim.world().shell(shell_index(sim, shell));
        if (!p.fractures()) return py::none();
        return view_scalars(p.damage_values(), self, p.num_layers());
      },
      py::arg("shell") = 0,
      "Damage c per quadrature point and layer, (n, layers) read-only view; None when the shell does not fracture.");
  c.def(
      "damage_history", [](py::object self, py::object shell) -> py::object {
        const sim::Simulation& sim = *state_of(self).sim;
        const shell::ShellPatch& p = sim.world().shell(shell_index(sim, shell));
        if (!p.fractures()) return py::none();
        return view_scalars(p.damage_history_values(), self, p.num_layers());
      },
      py::arg("shell") = 0, "Damage history c_his (largest c so far), (n, layers) read-only view, or None.");
  c.def(
      "deformation_gradients",
      [](py::object self, py::object shell) {
        State& s = state_of(self);
        const shell::ShellPatch& p = s.sim->world().shell(shell_index(*s.sim, shell));
        const std::vector<Eigen::Matrix3d> F = s.locked([&] { return p.deformation_gradients(); });
        return copy_mat3(F, p.num_layers());
      },
      py::arg("shell") = 0,
      "Kirchhoff-Love deformation gradient F^KL = sum_i g_i (x) Gbar^i (thesis Eq. 4.5) of every quadrature "
      "point and layer, (n, layers, 3, 3). A COPY, recomputed from the current control points (the solver keeps "
      "no F per point). NaN where a point carries no stress (a rigid or removed sliver).");
}

// Type I: solid particles.
void bind_solid_particles(py::class_<State>& c) {
  c.def(
      "solid_particles", [](py::object self, py::object solid) {
        const sim::Simulation& sim = *state_of(self).sim;
        const mpm::SolidParticles& p = sim.world().solid(solid_index(sim, solid));
        py::dict d;
        d["x"] = view_vec3(p.x, self);
        d["v"] = view_vec3(p.v, self);
        d["mass"] = view_scalars(p.mass, self);
        d["volume"] = view_scalars(p.volume, self);
        d["F"] = view_mat3(p.F, self);
        return d;
      },
      py::arg("solid") = 0,
      "Type I particles of a solid as read-only views: x, v (n, 3), mass, volume (n,), F (n, 3, 3).");
}

}  // namespace

void bind_simulation(py::module_& m) {
  py::class_<State> c(m, "Simulation",
                      "A running scene: Kirchhoff-Love shell patches (control points, shear particles, quadrature "
                      "points) and solids on a sparse MPM grid (thesis sec. 4.3), advanced by explicit symplectic "
                      "Euler steps.\n\nArrays returned by positions(), velocities(), masses(), damage(), ... are "
                      "read-only NumPy views of the solver's memory: they show the state after every later step "
                      "and are valid as long as the Simulation (they keep it alive). Stepping releases the GIL; "
                      "Ctrl-C stops it between steps with KeyboardInterrupt. Shells and solids are chosen by index "
                      "or name.");
  c.def(py::init<const scene::Scene&, int>(), py::arg("scene"), py::arg("threads") = 0,
        "Builds the scene (validation, defaults, geometry) and its particles. threads: TBB threads of this "
        "simulation's parallel loops (0: all cores); results are deterministic for a thread count. Raises "
        "SceneError.");
  bind_stepping(c);
  bind_control_points(c);
  bind_shell_points(c);
  bind_solid_particles(c);
  bind_simulation_outputs(c);
}

}  // namespace shellfrac::python
