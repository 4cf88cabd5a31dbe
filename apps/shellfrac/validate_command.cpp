// `shellfrac validate SCENE`: checks a scene without running it.
#include <iostream>
#include <memory>

#include "apps/shellfrac/command.hpp"
#include "output/scene_description.hpp"
#include "scene/build.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::app {

Command add_validate_command(CLI::App& app) {
  auto path = std::make_shared<std::string>();
  auto* validate = app.add_subcommand("validate", "Check a scene file without running it; prints a "
                                                  "summary, or the first problem with its JSON path.");
  validate->add_option("scene", *path, "Scene file (JSON)")->required();
  return [validate, path]() -> std::optional<int> {
    if (!validate->parsed()) return std::nullopt;
    return run_guarded([&] {
      const scene::Model model = scene::build(load_scene_or_default(*path));
      // Build the simulation too: some checks need the grid (the stability bound of a given dt, the
      // fracture energy against the characteristic length), and solids must sample particles.
      const sim::Simulation sim(model);
      std::cout << *path << ": OK\n" << output::describe_scene(model);
      return 0;
    });
  };
}

}  // namespace shellfrac::app
