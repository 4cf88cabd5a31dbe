// shellfrac.Scene: a scene as plain data (scene/scene.hpp), read with the CLI's strict reader and written
// back exactly (scene/json_io.hpp), so Scene.from_dict(d).to_dict() == d for every valid document d.
#include <pybind11/stl.h>

#include "output/scene_description.hpp"
#include "python/bindings.hpp"
#include "scene/build.hpp"
#include "scene/json_io.hpp"
#include "scene/validate.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::python {

namespace {

std::string validate_scene(const scene::Scene& s) {
  py::gil_scoped_release nogil;  // building can take a while (mesh level sets, solid sampling)
  const scene::Model model = scene::build(s);
  // As `shellfrac validate`: some checks need the built simulation (the stability bound of a given dt,
  // the fracture energy against the grid's characteristic length).
  const sim::Simulation sim(model);
  return output::describe_scene(model);
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<scene::Scene>(m, "Scene",
                           "A scene: shells, solids, colliders, pins, time and output settings, as plain data "
                           "(docs/scene-format.md).\n\nMake one with Scene.load(path), Scene.from_dict(d) or "
                           "Scene.default(); change it through to_dict() and from_dict(). Reading checks types, "
                           "ranges, unknown keys and rules between keys; validate() adds the checks that need the "
                           "built geometry. Both raise SceneError with the JSON pointer.")
      .def_static(
          "load", [](const std::string& path) { return scene::load_scene(path); }, py::arg("path"),
          "Reads a scene file (JSON). Relative mesh paths in it are resolved against its folder. Raises SceneError.")
      .def_static(
          "from_dict",
          [](const py::dict& d, const std::string& source) { return scene::read_scene(python_to_json(d), source); },
          py::arg("d"), py::arg("source") = "<python>",
          "A scene from a dict shaped like a scene file (json.load of one). `source` names it in errors, and "
          "relative mesh paths are resolved against its folder. Raises SceneError with the JSON pointer.")
      .def_static(
          "from_json", [](const std::string& text, const std::string& source) { return scene::read_scene(text, source); },
          py::arg("text"), py::arg("source") = "<python>", "A scene from JSON text. Raises SceneError.")
      .def_static(
          "default", [] { return scene::default_scene(); }, "The built-in default scene (scenes/default.json).")
      .def(
          "to_dict", [](const scene::Scene& s) { return json_to_python(scene::to_json(s).dump()); },
          "The scene's document: every field that is set and nothing else (from_dict(d).to_dict() == d).")
      .def(
          "to_json", [](const scene::Scene& s, int indent) { return scene::to_json(s).dump(indent); },
          py::arg("indent") = 2, "The scene's document as JSON text.")
      .def("validate", &validate_scene,
           "Checks the scene the way `shellfrac validate` does (build the geometry and the simulation) and returns "
           "the same description. Raises SceneError naming the JSON pointer of the first problem.")
      .def(
          "copy", [](const scene::Scene& s) { return scene::Scene(s); }, "An independent copy.")
      .def_property(
          "name", [](const scene::Scene& s) { return s.name; },
          [](scene::Scene& s, std::optional<std::string> name) { s.name = std::move(name); }, "The scene's name (or None).")
      .def_readwrite("source", &scene::Scene::source,
                     "Where the scene came from: errors name it and relative mesh paths are resolved against its "
                     "folder. Not part of the document.")
      .def_property_readonly(
          "shell_names",
          [](const scene::Scene& s) {
            std::vector<std::optional<std::string>> names;
            for (const auto& sh : s.shells) names.push_back(sh.name);
            return names;
          },
          "The shells' names in scene order (None where the document gives none).")
      .def("__eq__", [](const scene::Scene& a, const scene::Scene& b) { return scene::to_json(a) == scene::to_json(b); })
      .def("__repr__", [](const scene::Scene& s) {
        return "<shellfrac.Scene " + (s.name ? "'" + *s.name + "'" : std::string("(unnamed)")) + " from " + s.source +
               ": " + std::to_string(s.shells.size()) + " shell(s), " + std::to_string(s.solids.size()) + " solid(s)>";
      });
}

}  // namespace shellfrac::python
