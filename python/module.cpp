// The compiled part of the `shellfrac` package (python/shellfrac/__init__.py re-exports it).
#include "core/version.hpp"
#include "python/bindings.hpp"

PYBIND11_MODULE(_shellfrac, m) {
  using namespace shellfrac::python;
  m.doc() = "shellfrac: thin-shell tearing with the material point method (Kirchhoff-Love shells on NURBS patches). "
            "See docs/python.md.";
  m.attr("__version__") = shellfrac::kVersion;
  bind_errors(m);
  bind_scene(m);
  bind_simulation(m);
  bind_run(m);
}
