// `shellfrac run [SCENE] [--out DIR] [--threads N] [--max-memory SIZE] [--force] [--keep-old-frames]`: runs
// a scene and writes its frames and summary.json. The scene's resources are estimated and checked
// against the budget before anything is built (apps/shellfrac/budget.hpp); SIGINT, SIGTERM and SIGHUP
// stop the run between steps with an "interrupted" summary and exit code 128 + the signal.
#include <iostream>
#include <memory>

#include "apps/shellfrac/budget.hpp"
#include "apps/shellfrac/command.hpp"
#include "core/error.hpp"
#include "core/version.hpp"
#include "output/interrupt.hpp"
#include "output/progress.hpp"
#include "output/run.hpp"
#include "output/scene_description.hpp"
#include "scene/build.hpp"
#include "scene/estimate.hpp"

namespace shellfrac::app {

namespace {

struct RunArguments {
  std::string scene_path;
  std::string out_dir = "out";
  int threads = 0;
  bool keep_old_frames = false;
  BudgetArguments budget;
};

}  // namespace

Command add_run_command(CLI::App& app) {
  auto args = std::make_shared<RunArguments>();
  auto* run = app.add_subcommand("run", "Run a scene (the built-in default when no file is given) and "
                                        "write OUT/summary.json and OUT/frames/.");
  run->add_option("scene", args->scene_path, "Scene file (JSON, see docs/scene-format.md)");
  run->add_option("--out,-o", args->out_dir, "Output directory")->capture_default_str();
  run->add_option("--threads,-j", args->threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();
  run->add_flag("--keep-old-frames", args->keep_old_frames,
                "Keep the files an earlier run left in OUT/frames/ (by default they are removed first)");
  add_budget_options(run, args->budget, true);
  return [run, args]() -> std::optional<int> {
    if (!run->parsed()) return std::nullopt;
    return run_guarded([&] {
      if (args->out_dir.empty()) throw core::InputError("--out: the output folder must not be empty");
      const scene::Scene scene = load_scene_or_default(args->scene_path);
      // Refuse before anything big is allocated (the build samples solids and level sets).
      const scene::ResourceEstimate estimate = scene::estimate_resources(scene);
      scene::check_budget(estimate, make_budget(args->budget, args->out_dir, args->threads), scene.source);
      const scene::Model model = scene::build(scene);
      for (const std::string& w : model.warnings) std::cerr << "warning: " << w << "\n";
      output::RunOptions options;
      options.out_dir = args->out_dir;
      options.threads = args->threads;
      options.interactive = output::Progress::stderr_is_terminal();
      options.keep_old_frames = args->keep_old_frames;
      std::cerr << "shellfrac " << kVersion << ": running " << output::describe_scene(model);
      const output::InterruptHandlers handlers;
      const output::Summary summary = output::run_scene(model, options, std::cerr);
      if (summary.status == "interrupted") {
        const int signal = output::interrupt_signal();
        std::cerr << "interrupted: " << summary.frames.size() << " complete frame(s) and summary.json (status "
                  << "\"interrupted\", t = " << summary.simulated_seconds << " s) in " << args->out_dir << "\n";
        return 128 + (signal ? signal : 2);
      }
      std::cerr << "done: " << summary.frames.size() << " frame(s) and summary.json in " << args->out_dir << " ("
                << summary.wall_seconds << " s)\n";
      return 0;
    });
  };
}

}  // namespace shellfrac::app
