#include "tools/run_limits.hpp"

#include <cmath>

#include "output/interrupt.hpp"

namespace shellfrac::tools {

void check_limits(const scene::Scene& scene, double end, const RunLimits& limits) {
  scene::Scene run = scene;
  run.time.end = end;
  run.time.frame_rate = 1.0 / end;  // bench runs write no frames: one interval, no frame-driven steps
  scene::check_budget(scene::estimate_resources(run), limits.budget, run.source);
}

void check_stop(const RunLimits& limits, const std::string& what) {
  if (!limits.should_stop || !limits.should_stop()) return;
  const int signal = output::interrupt_signal();
  throw output::Interrupted(what + " stopped " + (signal ? std::string("by ") + output::signal_name(signal) : "on request"),
                            signal);
}

void advance(sim::Simulation& sim, double end, const RunLimits& limits, const std::string& what) {
  sim.advance_to(end, limits.should_stop);
  if (sim.time() < end - 1e-12 * std::max(1.0, std::abs(end))) check_stop(limits, what + " at t = " + std::to_string(sim.time()) + " s");
}

}  // namespace shellfrac::tools
