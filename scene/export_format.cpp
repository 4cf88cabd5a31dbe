// The output formats a scene may ask for: every format the linked assimp exports.
#include "render_mesh/exporter.hpp"
#include "scene/describe.hpp"

namespace shellfrac::scene {

std::string export_format_problem(const std::string& format) {
  if (render_mesh::is_export_format(format)) return "";
  std::string list;
  for (const auto& f : render_mesh::export_formats()) list += (list.empty() ? "" : ", ") + f.id;
  return "unknown mesh format \"" + format + "\": allowed are " + list;
}

}  // namespace shellfrac::scene
