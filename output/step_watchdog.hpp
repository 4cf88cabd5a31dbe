#pragma once
// Progress reported on time, not per frame, even inside one long step. The run driver
// records where it is before every step and every frame export; a thread of this watchdog wakes every
// `period` and, once the current activity has run for a period and a progress line falls due before the
// next wake-up (5 s after the last line, 0.1 s for the terminal bar), prints the last recorded state and
// how long the current activity has been running, so lines are never more than 5 s apart. The watchdog only
// reads what the driver recorded and prints: the simulation (sim/, free of I/O) and its results do not
// depend on it.
#include <chrono>
#include <condition_variable>
#include <mutex>
#include <string>
#include <thread>

#include "output/progress.hpp"

namespace shellfrac::output {

class StepWatchdog {
 public:
  enum class Activity { setting_up, stepping, writing_frame };

  StepWatchdog(Progress& progress, double period_seconds = 1.0);
  ~StepWatchdog();  // stops the thread and waits for it
  StepWatchdog(const StepWatchdog&) = delete;
  StepWatchdog& operator=(const StepWatchdog&) = delete;

  // Where the run is: simulated time, the frame being stepped towards, steps taken, and what it does
  // next (building the simulation, a step towards `frame`, or writing `frame`). Cheap: a lock and a few
  // stores.
  void record(double time, int frame, int last_frame, long steps, Activity next);
  // What the current step is doing inside (a fracture event's MPM run); shown after the step's line until
  // the next record(). Does not restart the step's clock.
  void record_detail(std::string detail);

  // The line the watchdog prints for the recorded state, `busy_seconds` into the current activity
  // ("frame 3/10, step 57; step 58 running for 12 s", then the detail in parentheses).
  std::string describe(double busy_seconds) const;

 private:
  void watch();

  Progress& progress_;
  std::chrono::duration<double> period_;
  mutable std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  double time_ = 0;
  int frame_ = 0, last_frame_ = 0;
  long steps_ = 0;
  Activity next_ = Activity::setting_up;
  std::string detail_;
  std::chrono::steady_clock::time_point since_;
  std::thread thread_;  // last: started once everything above is set
};

}  // namespace shellfrac::output
