#include "apps/shellfrac/command.hpp"

#include <iostream>

#include "core/error.hpp"
#include "output/interrupt.hpp"
#include "scene/json_io.hpp"

namespace shellfrac::app {

int run_guarded(const std::function<int()>& body) {
  try {
    return body();
  } catch (const output::Interrupted& e) {
    std::cerr << "interrupted: " << e.what() << "\n";
    return core::to_int(e.exit_code());
  } catch (const std::exception& e) {
    const core::ExitCode code = core::exit_code_for(e);
    std::cerr << (code == core::ExitCode::numerical ? "numerical failure: " : "error: ") << e.what() << "\n";
    return core::to_int(code);
  }
}

scene::Scene load_scene_or_default(const std::string& path) {
  return path.empty() ? scene::default_scene() : scene::load_scene(path);
}

}  // namespace shellfrac::app
