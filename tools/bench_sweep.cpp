#include "tools/bench_sweep.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <ostream>
#include <random>
#include <set>

#include "nurbs/patch_builders.hpp"
#include "render_mesh/cracked_tessellation.hpp"
#include "shell/mls_basis.hpp"
#include "scene/scene_error.hpp"
#include "tools/bench_scenes.hpp"
#include "tools/charts.hpp"
#include "tools/crack_speed.hpp"
#include "tools/run_limits.hpp"
#include "output/progress.hpp"
#include "scene/build.hpp"
#include "output/frame_render.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::tools {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

double hanging_strip_elongation(double E, double density, double gravity, double length) {
  // Composite Simpson over the reference length; the integrand is smooth.
  const double mu = 0.5 * E;
  auto stretch_minus_one = [&](double S) {
    const double q = density * gravity * (length - S) / mu;
    return 0.5 * (q + std::sqrt(q * q + 4.0)) - 1.0;
  };
  const int n = 2000;
  const double h = length / n;
  double sum = stretch_minus_one(0) + stretch_minus_one(length);
  for (int i = 1; i < n; ++i) sum += (i % 2 ? 4.0 : 2.0) * stretch_minus_one(i * h);
  return sum * h / 3.0;
}

namespace {

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// Runs a scene to `end` and measures with `quantity` at the end; the timed part is the stepping only.
// The scene is checked against the limits before it is built, and stepping stops on request.
template <class Quantity>
Measurement simulate(const scene::Scene& scene, double end, const RunLimits& limits, Quantity&& quantity) {
  check_limits(scene, end, limits);
  sim::Simulation sim(scene);
  const auto t0 = Clock::now();
  advance(sim, end, limits, "bench sweep");
  Measurement m;
  m.wall_seconds = seconds_since(t0);
  m.simulated_seconds = sim.time();
  m.cost = m.simulated_seconds > 0 ? m.wall_seconds / m.simulated_seconds : 0;
  m.steps = sim.steps();
  m.quadrature_points = sim.num_quadrature_points();
  m.stage_seconds = sim.timer().seconds();
  m.measured = quantity(sim);
  return m;
}

void set_relative_error(Measurement& m) {
  m.error = std::abs(m.measured - m.reference) / std::abs(m.reference);
}

AccuracyBenchmark membrane_benchmark(bool full, const RunLimits& limits) {
  AccuracyBenchmark b;
  b.name = "membrane";
  b.reference = "hanging strip 0.25 x 0.5 m, nu = 0, under its own weight: elongation from the exact 1D "
                "neo-Hookean solution (hanging_strip_elongation)";
  b.cost_unit = "wall s per simulated s";
  b.length = bench_scenes::kStripLength;
  b.cells = full ? std::vector<int>{5, 10, 20, 40} : std::vector<int>{4, 8};
  if (!full) b.points = {2, 4}, b.cfl = {1.0};
  const double end = full ? 0.3 : 0.03;
  b.run = [end, limits](const Discretisation& d) {
    const scene::Scene scene = bench_scenes::hanging_strip(d);
    Measurement m = simulate(scene, end, limits, [](const sim::Simulation& sim) {
      const auto surf = sim.world().shell(0).current_surface();
      double y = 0;
      for (int k = 0; k <= 4; ++k) y += surf.point(k / 4.0, 1.0).y() / 5.0;
      return -y;  // the bottom edge started at y = 0
    });
    m.reference = hanging_strip_elongation(bench_scenes::kStripE, bench_scenes::kStripDensity, 9.81,
                                           bench_scenes::kStripLength);
    set_relative_error(m);
    return m;
  };
  return b;
}

AccuracyBenchmark cantilever_benchmark(bool full, const RunLimits& limits) {
  AccuracyBenchmark b;
  b.name = "cantilever";
  b.reference = "0.5 x 0.1 x 0.05 m plate clamped at one end under its own weight (nu = 0): Euler-Bernoulli "
                "tip deflection 1.5 rho g L^4 / (E tau^2)";
  b.cost_unit = "wall s per simulated s";
  b.length = 0.5;
  b.cells = full ? std::vector<int>{5, 10, 15, 20} : std::vector<int>{4, 5};
  b.one_layer_ladder = false;  // one layer has no bending stiffness: the plate just hangs
  if (!full) b.points = {4}, b.cfl = {1.0}, b.apic = false;
  const double end = full ? 0.3 : 0.01;
  b.run = [end, limits](const Discretisation& d) {
    Measurement m = simulate(bench_scenes::cantilever(d), end, limits, [](const sim::Simulation& sim) {
      const auto surf = sim.world().shell(0).current_surface();
      double tip = 0;
      for (int k = 0; k <= 4; ++k) tip += surf.point(1.0, k / 4.0).z() / 5.0;
      return tip;
    });
    const double E = 2e8, rho = 1000, g = 9.81, L = 0.5, tau = 0.05;
    m.reference = -1.5 * rho * g * std::pow(L, 4) / (E * tau * tau);
    set_relative_error(m);
    return m;
  };
  return b;
}

AccuracyBenchmark tear_benchmark(bool full, const RunLimits& limits) {
  AccuracyBenchmark b;
  b.name = "tear-area";
  b.reference = "1 m^2 notched sheet torn in mode I and relaxed: render-mesh area against the sheet's 1.0 m^2";
  b.cost_unit = "wall s per simulated s";
  b.length = 1.0;
  b.cells = full ? std::vector<int>{12, 16, 20, 24} : std::vector<int>{12};
  if (!full) b.points = {4}, b.one_layer_ladder = false, b.cfl = {}, b.apic = false;
  const double end = full ? 1.2 : 0.03;
  b.run = [end, limits](const Discretisation& d) {
    Measurement m = simulate(bench_scenes::mode_one_tear(d), end, limits, [](const sim::Simulation& sim) {
      return render_mesh::surface_area(output::render_meshes(sim)[0]);
    });
    m.reference = 1.0;
    set_relative_error(m);
    return m;
  };
  return b;
}

// Largest distance between the two-patch cloth and the one-patch cloth at matching material points.
double drape_difference(const sim::Simulation& two, const sim::Simulation& one) {
  const auto left = two.world().shell(0).current_surface(), right = two.world().shell(1).current_surface();
  const auto whole = one.world().shell(0).current_surface();
  double worst = 0;
  for (int i = 0; i <= 20; ++i)
    for (int j = 0; j <= 20; ++j) {
      const double s = i / 20.0, t = j / 20.0;
      const nurbs::Vec3 a = s <= 0.5 ? left.point(2 * s, t) : right.point(2 * s - 1, t);
      worst = std::max(worst, (a - whole.point(s, t)).norm());
    }
  return worst;
}

AccuracyBenchmark drape_benchmark(bool full, const RunLimits& limits) {
  AccuracyBenchmark b;
  b.name = "drape-two-patch";
  b.reference = "1 x 1 m cloth on a ball as two C1-coupled patches (N/2 x N and N x 2N cells) against the same "
                "cloth as one 2N x 2N patch: largest distance between them / 1 m";
  b.cost_unit = "wall s per simulated s";
  b.length = 1.0;
  b.cells = full ? std::vector<int>{4, 6, 8, 12} : std::vector<int>{2, 4};
  if (!full) b.points = {4}, b.one_layer_ladder = false, b.cfl = {}, b.apic = false;
  const double end = full ? 0.3 : 0.02;
  b.run = [end, limits](const Discretisation& d) {
    const scene::Scene one_patch = bench_scenes::drape(d, false), two_patches = bench_scenes::drape(d, true);
    check_limits(one_patch, end, limits);
    check_limits(two_patches, end, limits);
    sim::Simulation one(one_patch);
    advance(one, end, limits, "bench sweep");
    sim::Simulation two(two_patches);
    const auto t0 = Clock::now();
    advance(two, end, limits, "bench sweep");
    Measurement m;
    m.wall_seconds = seconds_since(t0);
    m.simulated_seconds = two.time();
    m.cost = m.wall_seconds / std::max(m.simulated_seconds, 1e-300);
    m.steps = two.steps();
    m.quadrature_points = two.num_quadrature_points();
    m.stage_seconds = two.timer().seconds();
    m.measured = drape_difference(two, one);
    m.reference = 0;
    m.error = m.measured / 1.0;
    return m;
  };
  return b;
}

// MLS approximation of a smooth field from its values at the control points of an N x N patch: the
// error of sum_k R_k(xi) f(xi_k) against f(xi) at random points, optionally with a slit that cuts the
// supports (thesis sec. 4.6). A quadratic basis gives third-order convergence of values.
AccuracyBenchmark mls_benchmark(bool full, bool slit) {
  AccuracyBenchmark b;
  b.name = slit ? "mls-slit" : "mls";
  b.reference = std::string("f = sin(2u + 0.3) cos(3v) sampled at the control points, interpolated by MLS") +
                (slit ? " with a slit u = 0.5, v < 0.5 blocking visibility" : "") +
                ": largest |error| at random points over max |f| = 1";
  b.cost_unit = "wall s per 1e6 evaluations";
  b.length = 1.0;
  b.cells = full ? std::vector<int>{8, 16, 32, 64, 128} : std::vector<int>{4, 8};
  b.points = {};
  b.one_layer_ladder = false;
  b.cfl = {};
  b.apic = false;
  const int samples = full ? 4000 : 200;
  b.run = [samples, slit](const Discretisation& d) {
    const auto grid = shell::ControlGrid::from_surface(nurbs::flat_patch(1.0, 1.0, d.cells, d.cells));
    auto field = [](const Eigen::Vector2d& x) { return std::sin(2 * x.x() + 0.3) * std::cos(3 * x.y()); };
    auto visible = [slit](const Eigen::Vector2d& a, const Eigen::Vector2d& c) {
      if (!slit) return true;
      const double fa = a.x() - 0.5, fc = c.x() - 0.5;
      if (fa * fc >= 0.0) return true;
      const double v = a.y() + fa / (fa - fc) * (c.y() - a.y());
      return !(v >= 0.0 && v < 0.5);
    };
    std::mt19937 rng(11);
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::vector<Eigen::Vector2d> at(static_cast<size_t>(samples));
    for (auto& x : at) x = Eigen::Vector2d(unit(rng), unit(rng));
    shell::MlsBasis basis;
    double worst = 0;
    const auto t0 = Clock::now();
    for (const auto& x : at) {
      if (!shell::mls_basis(x, grid, visible, shell::MlsSettings{}, basis)) continue;
      double s = 0;
      for (int k = 0; k < basis.size(); ++k)
        s += basis.R[static_cast<size_t>(k)] * field(grid.point(basis.index[static_cast<size_t>(k)]));
      worst = std::max(worst, std::abs(s - field(x)));
    }
    Measurement m;
    m.wall_seconds = seconds_since(t0);
    m.cost = m.wall_seconds * 1e6 / samples;
    m.measured = worst;
    m.reference = 0;
    m.error = worst;
    return m;
  };
  return b;
}

std::string series_label(int points, int layers) {
  return std::to_string(points) + "x" + std::to_string(points) + " pts, " + std::to_string(layers) +
         (layers == 1 ? " layer" : " layers");
}

}  // namespace

std::vector<AccuracyBenchmark> accuracy_benchmarks(bool full, const RunLimits& limits) {
  return {membrane_benchmark(full, limits), cantilever_benchmark(full, limits), tear_benchmark(full, limits),
          drape_benchmark(full, limits), mls_benchmark(full, false), mls_benchmark(full, true)};
}

std::vector<std::pair<std::string, Discretisation>> sweep_plan(const AccuracyBenchmark& b) {
  std::vector<std::pair<std::string, Discretisation>> plan;
  if (b.points.empty())
    for (int n : b.cells) plan.push_back({"ladder", Discretisation{n, 4, 3, 0.5, false}});
  for (int p : b.points)
    for (int n : b.cells) plan.push_back({series_label(p, 3), Discretisation{n, p, 3, 0.5, false}});
  if (b.one_layer_ladder)
    for (int n : b.cells) plan.push_back({series_label(4, 1), Discretisation{n, 4, 1, 0.5, false}});
  const int mid = b.cells[b.cells.size() / 2];
  for (double c : b.cfl) {
    char name[48];
    std::snprintf(name, sizeof name, "cfl %g (4x4 pts, 3 layers)", c);
    plan.push_back({name, Discretisation{mid, 4, 3, c, false}});
  }
  if (b.apic) plan.push_back({"apic (4x4 pts, 3 layers)", Discretisation{mid, 4, 3, 0.5, true}});
  return plan;
}

namespace {

// Runs every benchmark's plan; a diverging setting is reported and left out.
std::vector<SweepRow> run_plans(const std::vector<AccuracyBenchmark>& benchmarks, const SweepConfig& config,
                                std::ostream& log) {
  size_t total = 0;
  for (const auto& b : benchmarks) total += sweep_plan(b).size();
  output::Progress progress(log, output::Progress::stderr_is_terminal(), static_cast<double>(total), "runs");
  std::vector<SweepRow> rows;
  size_t done = 0;
  for (const auto& b : benchmarks) {
    for (const auto& [series, d] : sweep_plan(b)) {
      const std::string label = b.name + " " + series + " cells " + std::to_string(d.cells);
      check_stop(config.limits, "bench sweep (" + std::to_string(done) + " of " + std::to_string(total) + " runs done)");
      try {
        SweepRow row{b.name, series, d, b.length / d.cells, b.run(d), false};
        rows.push_back(row);
        progress.update(static_cast<double>(++done), label + ": error " + charts::number(row.m.error) + ", " +
                                                         charts::number(row.m.wall_seconds) + " s");
      } catch (const core::NumericalError& e) {  // a diverging setting has no error to chart: say so, go on
        log << "\n" << label << " diverged, left out of the charts: " << e.what() << "\n";
        progress.update(static_cast<double>(++done), label + ": diverged");
      }
    }
  }
  progress.finish(std::to_string(rows.size()) + " runs");
  return rows;
}

// Resolution dependence of the brittle solids' local and non-local damage (tools/crack_speed.hpp): the
// notched bar and beam at three spacings (full), the coarse bar for 4 ms (tiny).
void run_crack_speed(const SweepConfig& config, std::ostream& log) {
  std::vector<CrackSpeedRun> crack_speed;
  for (const std::string specimen : {"bar", "beam"}) {
    if (!config.full && specimen == "beam") continue;
    CrackSpeedOptions o;
    o.specimen = specimen;
    if (!config.full) o.spacings = {0.005}, o.end = 0.004;
    for (CrackSpeedRun& r : run_crack_speed_study(o, log, config.limits)) crack_speed.push_back(std::move(r));
  }
  write_crack_speed(config.out_dir, crack_speed, config.charts);
}

// Pareto flags per benchmark (error against cost).
void mark_pareto(const std::vector<AccuracyBenchmark>& benchmarks, std::vector<SweepRow>& rows) {
  for (const auto& b : benchmarks) {
    std::vector<size_t> idx;
    std::vector<double> cost, error;
    for (size_t i = 0; i < rows.size(); ++i)
      if (rows[i].benchmark == b.name) {
        idx.push_back(i);
        cost.push_back(rows[i].m.cost);
        error.push_back(rows[i].m.error);
      }
    const auto front = charts::pareto_front(cost, error);
    for (size_t k = 0; k < idx.size(); ++k) rows[idx[k]].pareto = front[k];
  }
}

void write_sweep_csv(const fs::path& out_dir, const std::vector<AccuracyBenchmark>& benchmarks,
                     const std::vector<SweepRow>& rows) {
  charts::CsvTable sweep{{"benchmark", "series", "cells", "h", "points", "layers", "cfl", "transfer", "steps",
                          "quadrature_points", "simulated_seconds", "wall_seconds", "cost", "cost_unit", "measured",
                          "reference", "error", "pareto"},
                         {}};
  for (const auto& r : rows) {
    const auto& b = *std::find_if(benchmarks.begin(), benchmarks.end(), [&](const auto& x) { return x.name == r.benchmark; });
    sweep.add({r.benchmark, r.series, std::to_string(r.d.cells), charts::number(r.h), std::to_string(r.d.points),
               std::to_string(r.d.layers), charts::number(r.d.cfl), r.d.apic ? "apic" : "pic", std::to_string(r.m.steps),
               std::to_string(r.m.quadrature_points), charts::number(r.m.simulated_seconds),
               charts::number(r.m.wall_seconds), charts::number(r.m.cost), b.cost_unit, charts::number(r.m.measured),
               charts::number(r.m.reference), charts::number(r.m.error), r.pareto ? "1" : "0"});
  }
  charts::write_csv(out_dir / "sweep.csv", sweep);
}

// Per benchmark, the series to chart against cost and, for series over two or more resolutions, against
// cell size with their convergence fits.
struct BenchmarkCharts {
  std::vector<charts::Series> by_cost, by_resolution;
  std::vector<charts::ConvergenceFit> fits;
};

// Convergence orders (one least-squares fit per series that spans at least two resolutions), written to
// convergence.csv, and the chart series per benchmark.
std::map<std::string, BenchmarkCharts> fit_convergence(const fs::path& out_dir,
                                                       const std::vector<AccuracyBenchmark>& benchmarks,
                                                       const std::vector<SweepRow>& rows) {
  charts::CsvTable convergence{{"benchmark", "series", "points_used", "order", "log_constant"}, {}};
  std::map<std::string, BenchmarkCharts> out;
  for (const auto& b : benchmarks) {
    BenchmarkCharts& c = out[b.name];
    std::vector<std::string> names;
    for (const auto& r : rows)
      if (r.benchmark == b.name && std::find(names.begin(), names.end(), r.series) == names.end())
        names.push_back(r.series);
    for (const auto& name : names) {
      charts::Series by_h{name, {}, {}}, by_cost{name, {}, {}};
      std::set<int> cells;
      for (const auto& r : rows)
        if (r.benchmark == b.name && r.series == name) {
          by_h.x.push_back(r.h);
          by_h.y.push_back(r.m.error);
          by_cost.x.push_back(r.m.cost);
          by_cost.y.push_back(r.m.error);
          cells.insert(r.d.cells);
        }
      c.by_cost.push_back(by_cost);
      if (cells.size() < 2) continue;
      const auto fit = charts::fit_convergence_order(by_h.x, by_h.y);
      convergence.add({b.name, name, std::to_string(fit.points), charts::number(fit.order),
                       charts::number(fit.log_constant)});
      c.by_resolution.push_back(by_h);
      c.fits.push_back(fit);
    }
  }
  charts::write_csv(out_dir / "convergence.csv", convergence);
  return out;
}

// The most resolved default tearing run, whose stage breakdown is charted (thesis Fig. 4.28); null if none.
const SweepRow* stage_breakdown_run(const std::vector<SweepRow>& rows) {
  const SweepRow* tear = nullptr;
  for (const auto& r : rows)
    if (r.benchmark == "tear-area" && r.d.points == 4 && r.d.layers == 3 && r.d.cfl == 0.5 && !r.d.apic &&
        (!tear || r.d.cells > tear->d.cells))
      tear = &r;
  return tear;
}

void write_stages_csv(const fs::path& out_dir, const SweepRow* tear) {
  charts::CsvTable stages{{"stage", "seconds", "share"}, {}};
  if (tear) {
    double total_seconds = 0;
    for (const auto& s : tear->m.stage_seconds) total_seconds += s.second;
    for (const auto& s : tear->m.stage_seconds)
      stages.add({s.first, charts::number(s.second), charts::number(total_seconds > 0 ? s.second / total_seconds : 0)});
  }
  charts::write_csv(out_dir / "stages.csv", stages);
}

void draw_sweep_charts(const fs::path& out_dir, const std::vector<AccuracyBenchmark>& benchmarks,
                       std::map<std::string, BenchmarkCharts>& chart, const SweepRow* tear) {
  for (const auto& b : benchmarks) {
    const BenchmarkCharts& c = chart[b.name];
    charts::error_vs_cost_chart(out_dir / (b.name + "-error-vs-time.png"),
                                b.name + ": error against cost (circles: Pareto front)", b.cost_unit, c.by_cost);
    if (!c.by_resolution.empty())
      charts::error_vs_resolution_chart(out_dir / (b.name + "-error-vs-resolution.png"),
                                        b.name + ": error against cell size", c.by_resolution, c.fits);
  }
  if (tear)
    charts::stage_breakdown_chart(out_dir / "tear-stage-breakdown.png",
                                  "tear-area, " + std::to_string(tear->d.cells) + " x " + std::to_string(tear->d.cells) +
                                      " cells, " + std::to_string(tear->m.steps) + " steps: wall seconds per stage",
                                  tear->m.stage_seconds);
}

}  // namespace

std::vector<SweepRow> run_sweep(const SweepConfig& config, std::ostream& log) {
  fs::create_directories(config.out_dir);
  const auto benchmarks = accuracy_benchmarks(config.full, config.limits);
  std::vector<SweepRow> rows = run_plans(benchmarks, config, log);
  run_crack_speed(config, log);
  mark_pareto(benchmarks, rows);
  write_sweep_csv(config.out_dir, benchmarks, rows);
  std::map<std::string, BenchmarkCharts> chart = fit_convergence(config.out_dir, benchmarks, rows);
  const SweepRow* tear = stage_breakdown_run(rows);
  write_stages_csv(config.out_dir, tear);
  if (config.charts) draw_sweep_charts(config.out_dir, benchmarks, chart, tear);
  return rows;
}

}  // namespace shellfrac::tools
