#pragma once
// What the bench commands may use and when they stop: every scene they simulate is checked
// against the resource budget before it is built, as `run` does, and a stop request (a signal caught by
// output::InterruptHandlers) ends them between two time steps with output::Interrupted.
#include <functional>
#include <string>

#include "scene/estimate.hpp"
#include "scene/scene.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::tools {

struct RunLimits {
  // Memory and steps (frames and disk do not apply: bench scenes write no frames). Default: no limit.
  scene::ResourceBudget budget{0, 1e300, 1e300, std::nullopt, true, ""};
  // Asked between steps; true ends the bench with output::Interrupted.
  std::function<bool()> should_stop;
};

// Estimates `scene` run to `end` seconds and throws scene::SceneError (exit code 2, the JSON path of the
// driving value) when it is over the budget.
void check_limits(const scene::Scene& scene, double end, const RunLimits& limits);

// sim.advance_to(end), stopping between steps when limits.should_stop says so: then throws
// output::Interrupted naming `what` and the signal received (output::interrupt_signal()).
void advance(sim::Simulation& sim, double end, const RunLimits& limits, const std::string& what);

// Throws output::Interrupted when limits.should_stop says so.
void check_stop(const RunLimits& limits, const std::string& what);

}  // namespace shellfrac::tools
