// `shellfrac bench`: speed-accuracy sweeps and the stability map (docs/benchmarks.md). Every scene is
// checked against the resource budget before it is built (--max-memory, --max-steps, --force), and
// SIGINT, SIGTERM and SIGHUP stop the bench between two steps with exit code 128 + the signal, writing
// no CSV or chart (a partial sweep would look complete).
#include "apps/shellfrac/command.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <iostream>
#include <memory>
#include <string>

#include "apps/shellfrac/bench_verify.hpp"
#include "apps/shellfrac/budget.hpp"
#include "output/interrupt.hpp"
#include "tools/bench_sweep.hpp"
#include "tools/stability_map.hpp"

namespace shellfrac::app {

namespace {

struct BenchOptions {
  std::string config = "tiny";
  std::string out_dir = "out/bench";
  int threads = 0;
  bool no_charts = false;
  BudgetArguments budget;
};

void add_common_options(CLI::App* cmd, BenchOptions& o) {
  cmd->add_option("--config", o.config, "tiny (seconds, as the tests run it) or full (minutes, the documented run)")
      ->check(CLI::IsMember({"tiny", "full"}))
      ->capture_default_str();
  cmd->add_option("--out,-o", o.out_dir, "Output directory for the CSV and PNG files")->capture_default_str();
  cmd->add_option("--threads,-j", o.threads, "Worker threads (0: all cores)")->check(CLI::Range(0, 4096))->capture_default_str();
  cmd->add_flag("--no-charts", o.no_charts, "Write the CSV files only (no gnuplot)");
  add_budget_options(cmd, o.budget, /*with_force=*/true, /*with_frames=*/false);
}

// The budget of every bench scene (no frames are written) and the stop request of the signal handlers.
tools::RunLimits bench_limits(const BudgetArguments& args) {
  tools::RunLimits limits;
  limits.budget = make_budget(args, "");
  limits.budget.max_frames = 1e300;
  limits.should_stop = [] { return output::interrupt_signal() != 0; };
  return limits;
}

}  // namespace

Command add_bench_command(CLI::App& app) {
  auto* bench = app.add_subcommand("bench", "Speed-accuracy sweeps and the stability map (docs/benchmarks.md).");
  bench->require_subcommand(1);
  auto options = std::make_shared<BenchOptions>();
  auto* sweep = bench->add_subcommand(
      "sweep", "Run the accuracy benchmarks over cells, quadrature points/layers, cfl and PIC/APIC; write "
               "sweep.csv, convergence.csv, stages.csv and error-vs-time / error-vs-resolution charts.");
  add_common_options(sweep, *options);
  auto* stability = bench->add_subcommand(
      "stability", "Run each method variant of the tearing and draping scenes and classify the outcome; write "
                   "stability.csv and stability-map.png and print the table.");
  add_common_options(stability, *options);
  auto* verify = bench->add_subcommand(
      "verify", "Run the shell obstacle course (scenes/verification/course.json) over cells and degrees, "
                "serially or on a Dask cluster (--dask); write verify.csv and error-vs-time/-dofs charts. "
                "Every argument goes to `python3 -m shellfrac.verify_course` (see its --help).");
  verify->prefix_command();    // the arguments after `verify` are the course runner's
  verify->set_help_flag("");  // so is --help

  return [bench, sweep, stability, verify, options]() -> std::optional<int> {
    if (!*bench) return std::nullopt;
    if (*verify) return exec_course_runner(verify->remaining());
    const int threads = options->threads > 0 ? options->threads : tbb::info::default_concurrency();
    tbb::global_control limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));
    return run_guarded([&] {
      const output::InterruptHandlers handlers;
      if (*sweep) {
        tools::SweepConfig config;
        config.full = options->config == "full";
        config.out_dir = options->out_dir;
        config.charts = !options->no_charts;
        config.limits = bench_limits(options->budget);
        const auto rows = tools::run_sweep(config, std::cerr);
        std::cout << "sweep (" << options->config << ", " << threads << " thread(s)): " << rows.size()
                  << " runs; sweep.csv, convergence.csv, stages.csv" << (config.charts ? " and charts" : "")
                  << " in " << options->out_dir << "\n";
      } else if (*stability) {
        tools::StabilityConfig config;
        config.full = options->config == "full";
        config.out_dir = options->out_dir;
        config.charts = !options->no_charts;
        config.limits = bench_limits(options->budget);
        const auto results = tools::run_stability_map(config, std::cout, std::cerr);
        std::cout << results.size() << " runs; stability.csv" << (config.charts ? " and stability-map.png" : "")
                  << " in " << options->out_dir << "\n";
      }
      return 0;
    });
  };
}

}  // namespace shellfrac::app
