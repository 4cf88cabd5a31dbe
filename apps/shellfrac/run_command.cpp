// `shellfrac run [SCENE] [--out DIR] [--threads N]`: runs a scene and writes its frames and summary.json.
#include <iostream>
#include <memory>

#include "apps/shellfrac/command.hpp"
#include "core/version.hpp"
#include "output/progress.hpp"
#include "output/run.hpp"
#include "output/scene_description.hpp"
#include "scene/build.hpp"

namespace shellfrac::app {

namespace {

struct RunArguments {
  std::string scene_path;
  std::string out_dir = "out";
  int threads = 0;
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
  return [run, args]() -> std::optional<int> {
    if (!run->parsed()) return std::nullopt;
    return run_guarded([&] {
      const scene::Model model = scene::build(load_scene_or_default(args->scene_path));
      output::RunOptions options;
      options.out_dir = args->out_dir;
      options.threads = args->threads;
      options.interactive = output::Progress::stderr_is_terminal();
      std::cerr << "shellfrac " << kVersion << ": running " << output::describe_scene(model);
      const output::Summary summary = output::run_scene(model, options, std::cerr);
      std::cerr << "done: " << summary.frames.size() << " frame(s) and summary.json in " << args->out_dir << " ("
                << summary.wall_seconds << " s)\n";
      return 0;
    });
  };
}

}  // namespace shellfrac::app
