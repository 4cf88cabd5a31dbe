// `shellfrac validate SCENE [--max-memory SIZE]`: checks a scene without running it and prints its
// resource estimate. A scene over the memory budget is refused before anything is allocated; step,
// frame and disk budgets are warnings here (run refuses them without --force).
#include <iostream>
#include <memory>

#include "apps/shellfrac/budget.hpp"
#include "apps/shellfrac/command.hpp"
#include "output/scene_description.hpp"
#include "scene/build.hpp"
#include "scene/estimate.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::app {

namespace {

struct ValidateArguments {
  std::string path;
  BudgetArguments budget;
};

}  // namespace

Command add_validate_command(CLI::App& app) {
  auto args = std::make_shared<ValidateArguments>();
  auto* validate = app.add_subcommand("validate", "Check a scene file without running it; prints a "
                                                  "summary and the resource estimate, or the first problem "
                                                  "with its JSON path.");
  validate->add_option("scene", args->path, "Scene file (JSON)")->required();
  add_budget_options(validate, args->budget, false);
  return [validate, args]() -> std::optional<int> {
    if (!validate->parsed()) return std::nullopt;
    return run_guarded([&] {
      const scene::Scene scene = load_scene_or_default(args->path);
      const scene::ResourceEstimate estimate = scene::estimate_resources(scene);
      scene::ResourceBudget budget = make_budget(args->budget, "");
      const std::vector<std::string> warnings = scene::budget_warnings(estimate, budget);
      budget.force = true;  // memory only: the rest are warnings below
      scene::check_budget(estimate, budget, scene.source);
      const scene::Model model = scene::build(scene);
      // Build the simulation too: some checks need the grid (the stability bound of a given dt, the
      // fracture energy against the characteristic length), and solids must sample particles.
      const sim::Simulation sim(model);
      std::cout << args->path << ": OK\n" << output::describe_scene(model) << scene::describe_estimate(estimate);
      for (const std::string& w : warnings) std::cout << "warning: " << w << " (run needs --force)\n";
      return 0;
    });
  };
}

}  // namespace shellfrac::app
