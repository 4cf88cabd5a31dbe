// shellfrac's exceptions in Python: the C++ SceneError and NumericalError become Python exceptions that
// carry their fields as attributes (the message stays the C++ one, word for word).
#include <Python.h>

#include "core/error.hpp"
#include "python/bindings.hpp"
#include "scene/scene_error.hpp"

namespace shellfrac::python {

namespace {

// The exception classes, created once at import and kept for the life of the interpreter.
PyObject* g_error = nullptr;
PyObject* g_scene_error = nullptr;
PyObject* g_numerical_error = nullptr;

PyObject* new_class(py::module_& m, const char* name, PyObject* bases, const char* doc) {
  const std::string qualified = std::string("shellfrac.") + name;
  PyObject* cls = PyErr_NewExceptionWithDoc(qualified.c_str(), doc, bases, nullptr);
  if (!cls) throw py::error_already_set();
  m.add_object(name, py::handle(cls));  // add_object steals nothing: the module holds its own reference
  return cls;
}

// Raises an instance of cls with the message and the attributes set.
void raise_with(PyObject* cls, const std::string& message, const py::dict& attributes) {
  py::object instance = py::reinterpret_steal<py::object>(PyObject_CallFunction(cls, "s", message.c_str()));
  if (!instance) throw py::error_already_set();
  for (auto item : attributes) instance.attr(item.first) = item.second;
  PyErr_SetObject(cls, instance.ptr());
}

py::object none_if(long value) { return value < 0 ? py::object(py::none()) : py::object(py::int_(value)); }
py::object none_if(const std::string& value) { return value.empty() ? py::object(py::none()) : py::object(py::str(value)); }

}  // namespace

void bind_errors(py::module_& m) {
  g_error = new_class(m, "Error", PyExc_RuntimeError, "Base of the errors shellfrac raises on purpose.");
  {
    py::tuple bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_ValueError));
    g_scene_error = new_class(m, "SceneError", bases.ptr(),
                              "A scene that cannot be read or accepted: the same checks and messages as `shellfrac "
                              "validate`.\n\nAttributes:\n  json_path: JSON pointer of the offending value, e.g. "
                              "'/shells/0/material/nu' ('' for the whole document)\n  file: the scene's source (a "
                              "path, or '<python>')\n  reason: what is wrong and what is allowed (the message "
                              "without file and pointer)");
  }
  {
    py::tuple bases = py::make_tuple(py::handle(g_error), py::handle(PyExc_ArithmeticError));
    g_numerical_error = new_class(m, "NumericalError", bases.ptr(),
                                  "A numerical failure while stepping (NaN, inversion, blow-up). The simulation stays "
                                  "readable (metrics, arrays) at the state the failing step left.\n\nAttributes:\n"
                                  "  shell / solid: name of the body where it started (the other is None)\n"
                                  "  particle: index of the particle within its body and kind (or None)\n"
                                  "  particle_kind: 'control point', 'shear particle', 'quadrature point' or "
                                  "'solid particle'\n  step: steps completed before the failing one\n"
                                  "  time: simulated time at the start of the failing step [s]");
  }

  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const scene::SceneError& e) {
      py::dict a;
      a["json_path"] = e.json_path();
      a["file"] = e.file();
      a["reason"] = e.message();
      raise_with(g_scene_error, e.what(), a);
    } catch (const core::NumericalError& e) {
      const core::NumericalLocation& w = e.where();
      py::dict a;
      a["shell"] = w.body_kind == "shell" ? none_if(w.body) : py::object(py::none());
      a["solid"] = w.body_kind == "solid" ? none_if(w.body) : py::object(py::none());
      a["particle"] = none_if(w.particle);
      a["particle_kind"] = none_if(w.particle_kind);
      a["step"] = none_if(w.step);
      a["time"] = w.step < 0 ? py::object(py::none()) : py::object(py::float_(w.time));
      raise_with(g_numerical_error, e.what(), a);
    } catch (const core::InputError& e) {  // bad input that is not a scene (an option, a file)
      raise_with(g_error, e.what(), py::dict());
    }
  });
}

py::object json_to_python(const std::string& text) { return py::module_::import("json").attr("loads")(text); }

std::string python_to_json(const py::handle& value) {
  // allow_nan=False: a NaN or infinity is no JSON number; the reader then reports it like a bad file.
  return py::module_::import("json").attr("dumps")(value, py::arg("allow_nan") = false).cast<std::string>();
}

}  // namespace shellfrac::python
