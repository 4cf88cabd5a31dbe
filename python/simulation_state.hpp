#pragma once
// What the Python Simulation object holds: the C++ simulation, the TBB arena its parallel loops run in
// (its own thread count, so two simulations in two Python threads do not share one global limit), and
// the progress a watching thread may read while a step runs without the GIL.
#include <tbb/task_arena.h>

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>

#include "python/bindings.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::python {

struct SimulationState {
  SimulationState(const scene::Scene& scene, int threads);

  // Runs f inside the arena with the GIL released and the simulation locked (one caller at a time).
  template <class F>
  auto locked(F&& f) {
    py::gil_scoped_release nogil;
    std::lock_guard<std::mutex> lock(busy);
    return arena->execute(std::forward<F>(f));
  }
  // Copies time and step count where another thread can read them during a step.
  void publish() {
    time.store(sim->time());
    steps.store(sim->steps());
  }

  int threads = 0;
  std::unique_ptr<tbb::task_arena> arena;
  std::unique_ptr<sim::Simulation> sim;
  std::mutex busy;
  std::atomic<double> time{0};
  std::atomic<long> steps{0};
  std::optional<std::string> error;  // the message of the NumericalError a step raised, if any
};

inline SimulationState& state_of(py::handle self) { return self.cast<SimulationState&>(); }

}  // namespace shellfrac::python
