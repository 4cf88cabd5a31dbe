#pragma once
// The outputs of shellfrac.Simulation that are computed on request: metrics(), render_mesh(), crack_graph().
#include "python/simulation_state.hpp"

namespace shellfrac::python {

// Index of a shell or solid given by index or name (IndexError / KeyError otherwise).
size_t shell_index(const sim::Simulation& sim, const py::handle& shell);
size_t solid_index(const sim::Simulation& sim, const py::handle& solid);

void bind_simulation_outputs(py::class_<SimulationState>& c);

}  // namespace shellfrac::python
