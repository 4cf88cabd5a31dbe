// `shellfrac validate SCENE [--max-memory SIZE] [--max-steps N] [--max-frames N] [--force]`: checks a
// scene without running it and prints its resource estimate. It refuses (exit 2) exactly what `run`
// would refuse, before anything is allocated: memory over the budget always, the step and frame
// budgets unless --force is given (then they are warnings).
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
  add_budget_options(validate, args->budget, true);
  return [validate, args]() -> std::optional<int> {
    if (!validate->parsed()) return std::nullopt;
    return run_guarded([&] {
      const scene::Scene scene = load_scene_or_default(args->path);
      const scene::ResourceEstimate estimate = scene::estimate_resources(scene);
      // The same check as run's (exit 2 for whatever run would refuse); with --force the step and frame
      // budgets are only warnings, as they are for run --force.
      const scene::ResourceBudget budget = make_budget(args->budget, "");
      scene::check_budget(estimate, budget, scene.source);
      const std::vector<std::string> warnings = scene::budget_warnings(estimate, budget);
      const scene::Model model = scene::build(scene);
      for (const std::string& w : model.warnings) std::cerr << "warning: " << w << "\n";
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
