#pragma once
// The parts of the Python module `_shellfrac` (docs/python.md); module.cpp calls each bind_* in turn.
#include <pybind11/pybind11.h>

namespace shellfrac::python {

namespace py = pybind11;

void bind_errors(py::module_& m);      // errors.cpp: Error, SceneError, NumericalError and their translation
void bind_scene(py::module_& m);       // scene_bindings.cpp: Scene
void bind_simulation(py::module_& m);  // simulation_bindings.cpp: Simulation
void bind_run(py::module_& m);         // run_bindings.cpp: run()

// Python objects <-> JSON text through Python's own json module, so that key order and number types
// survive exactly (an int stays an int, a float a float).
py::object json_to_python(const std::string& text);
std::string python_to_json(const py::handle& value);

}  // namespace shellfrac::python
