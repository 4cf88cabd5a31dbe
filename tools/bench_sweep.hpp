#pragma once
// Speed-accuracy sweeps (`shellfrac bench sweep`): every accuracy benchmark with a reference answer is run
// over a range of discretisations, and its error is recorded against the wall time it cost. See
// docs/benchmarks.md for the benchmarks, the references and the measured results.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include "tools/run_limits.hpp"

namespace shellfrac::tools {

// One discretisation of a benchmark.
struct Discretisation {
  int cells = 8;      // cells per side (along the benchmark's main direction)
  int points = 4;     // quadrature.points: Gauss points per cell direction
  int layers = 3;     // quadrature.layers
  double cfl = 0.5;   // time.cfl: the step as a fraction of the stability bound
  bool apic = false;  // grid.transfer
};

// What one run measured.
struct Measurement {
  double measured = 0;      // the benchmark's quantity (tip deflection, area, ...)
  double reference = 0;     // its reference value
  double error = 0;         // relative error |measured - reference| / |reference| (or as the benchmark defines)
  double cost = 0;          // wall seconds per simulated second (per million evaluations for MLS)
  double wall_seconds = 0;  // wall time of the timed part
  double simulated_seconds = 0;
  long steps = 0;
  size_t quadrature_points = 0;
  std::vector<std::pair<std::string, double>> stage_seconds;  // Simulation::timer() of the run
};

// One accuracy benchmark: a name, its reference, and a function that runs one discretisation.
struct AccuracyBenchmark {
  std::string name;
  std::string reference;  // what the error is measured against
  std::string cost_unit;  // "wall s per simulated s" or "wall s per 1e6 evaluations"
  double length = 1;      // the length divided into `cells` (h = length / cells)
  std::vector<int> cells;                // resolution ladder
  std::vector<int> points{2, 3, 4};      // quadrature stencils run on the ladder (empty: not applicable)
  bool one_layer_ladder = true;          // also run the ladder with 1 layer (4 points)
  std::vector<double> cfl{0.25, 1.0};    // extra cfl values at the middle resolution (empty: not dynamic)
  bool apic = true;                      // also run APIC at the middle resolution
  std::function<Measurement(const Discretisation&)> run;
};

// One row of the sweep.
struct SweepRow {
  std::string benchmark;
  std::string series;  // e.g. "4x4 pts, 3 layers", "cfl 0.25", "apic"
  Discretisation d;
  double h = 0;
  Measurement m;
  bool pareto = false;
};

struct SweepConfig {
  bool full = false;  // tiny: seconds, for tests; full: the documented sweep (minutes)
  std::filesystem::path out_dir = "out/bench";
  bool charts = true;  // draw PNGs with gnuplot (the CSVs are always written)
  RunLimits limits;    // budget per scene, stop requests between steps (output::Interrupted, nothing written)
};

// The benchmarks of a configuration (tiny: small and short versions of the same cases); their runs check
// each scene against `limits` before building it and stop on its requests.
std::vector<AccuracyBenchmark> accuracy_benchmarks(bool full, const RunLimits& limits = {});

// The discretisations run for a benchmark, with their series names.
std::vector<std::pair<std::string, Discretisation>> sweep_plan(const AccuracyBenchmark& b);

// Runs every benchmark over its plan, the tearing stage breakdown and the crack-speed study of the brittle
// solids (tools/crack_speed.hpp), and writes into out_dir: sweep.csv, convergence.csv, stages.csv,
// crack_speed.csv, crack_speed_summary.csv and (charts on) <benchmark>-error-vs-time.png,
// <benchmark>-error-vs-resolution.png, tear-stage-breakdown.png and crack-tip-<specimen>.png. Progress
// lines go to `log`.
// Returns the rows (with their Pareto flags set per benchmark).
std::vector<SweepRow> run_sweep(const SweepConfig& config, std::ostream& log);

// Reference elongation of a hanging strip of length L under its own weight, for nu = 0 neo-Hookean
// (lambda = 0, mu = E / 2): each cross-section carries the weight below it, mu (s - 1/s) = rho g (L - S).
double hanging_strip_elongation(double E, double density, double gravity, double length);

}  // namespace shellfrac::tools
