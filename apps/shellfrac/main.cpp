// shellfrac command-line tool: run, validate, verify coupling, and benchmark scene files.
// Exit codes: 0 success, 2 bad input, 3 numerical failure, 4 a verify check failed, 1 anything else.
#include <CLI/CLI.hpp>

#include <exception>
#include <iostream>
#include <string>

#include "apps/shellfrac/bench_command.hpp"
#include "apps/shellfrac/preview_command.hpp"
#include "apps/shellfrac/verify_command.hpp"
#include "sim/run.hpp"
#include "sim/simulation.hpp"
#include "sim/scene.hpp"
#include "sim/scene_error.hpp"
#include "sim/progress.hpp"
#include "sim/version.hpp"

namespace {

constexpr int kExitOk = 0;
constexpr int kExitOther = 1;
constexpr int kExitBadInput = 2;
constexpr int kExitNumerical = 3;

shellfrac::sim::Scene load(const std::string& path) {
  return path.empty() ? shellfrac::sim::default_scene() : shellfrac::sim::load_scene_file(path);
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"shellfrac: tears and fractures thin shells (Kirchhoff-Love NURBS shells simulated with "
               "MPM) and writes render meshes with the cracks in them."};
  app.set_version_flag("--version", std::string("shellfrac ") + shellfrac::kVersion);
  app.require_subcommand(1);

  std::string run_scene_path;
  shellfrac::sim::RunOptions run_options;
  std::string out_dir = "out";
  auto* run = app.add_subcommand("run", "Run a scene (the built-in default when no file is given) and "
                                        "write OUT/summary.json and OUT/frames/.");
  run->add_option("scene", run_scene_path, "Scene file (JSON, see docs/scene-format.md)");
  run->add_option("--out,-o", out_dir, "Output directory")->capture_default_str();
  run->add_option("--threads,-j", run_options.threads, "Worker threads (0: all cores)")
      ->check(CLI::Range(0, 4096))
      ->capture_default_str();

  std::string validate_path;
  auto* validate = app.add_subcommand("validate", "Check a scene file without running it; prints a "
                                                  "summary, or the first problem with its JSON path.");
  validate->add_option("scene", validate_path, "Scene file (JSON)")->required();

  const auto run_verify = shellfrac::app::add_verify_command(app);  // verify coupling
  const auto run_bench = shellfrac::app::add_bench_command(app);    // bench sweep / stability
  const auto run_preview = shellfrac::app::add_preview_command(app);  // preview (Blender renders)

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? kExitOk : kExitBadInput;
  }

  if (const auto code = run_verify()) return *code;
  if (const auto code = run_bench()) return *code;
  if (const auto code = run_preview()) return *code;
  try {
    if (*validate) {
      const auto scene = load(validate_path);
      // Build the simulation too: some checks need the grid (the stability bound of a given dt, the
      // fracture energy against the characteristic length), and solids must sample particles.
      const shellfrac::sim::Simulation sim(scene);
      std::cout << validate_path << ": OK\n" << shellfrac::sim::describe_scene(scene);
      return kExitOk;
    }
    const auto scene = load(run_scene_path);
    run_options.out_dir = out_dir;
    run_options.interactive = shellfrac::sim::Progress::stderr_is_terminal();
    std::cerr << "shellfrac " << shellfrac::kVersion << ": running " << shellfrac::sim::describe_scene(scene);
    const auto summary = shellfrac::sim::run_scene(scene, run_options, std::cerr);
    std::cerr << "done: " << summary["frames"].size() << " frame(s) and summary.json in " << out_dir
              << " (" << summary["wall_seconds"].get<double>() << " s)\n";
    return kExitOk;
  } catch (const shellfrac::sim::SceneError& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitBadInput;
  } catch (const shellfrac::sim::NumericalError& e) {
    std::cerr << "numerical failure: " << e.what() << "\n";
    return kExitNumerical;
  } catch (const std::exception& e) {
    std::cerr << "error: " << e.what() << "\n";
    return kExitOther;
  }
}
