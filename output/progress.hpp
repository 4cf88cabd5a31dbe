#pragma once
#include <chrono>
#include <iosfwd>
#include <mutex>
#include <string>

namespace shellfrac::output {

// Reports progress of a long run on stderr: a redrawn bar with ETA when stderr is a terminal, plain
// log lines (one every `log_interval` seconds, plus the last) otherwise, so CI logs stay short. The run
// driver calls update() after every step, so a line comes on time even when no frame is due; a
// StepWatchdog (output/step_watchdog.hpp) calls it from its own thread while a step runs long, so every
// member locks.
class Progress {
 public:
  Progress(std::ostream& out, bool interactive, double total, std::string unit,
           double log_interval_seconds = 5.0);
  // done is in [0, total]; detail is appended to the line (e.g. "frame 12/48"). Drawn only when due.
  void update(double done, const std::string& detail = "");
  // update() that also draws when a line will be due within ahead_seconds (the watchdog's).
  void update_early(double done, const std::string& detail, double ahead_seconds);
  // Whether update() would draw now, or (ahead_seconds > 0) will within that time: callers that report
  // every step build their detail text only then; a watchdog that wakes every `ahead_seconds` draws
  // early rather than late, so lines are never further apart than the interval.
  bool due(double ahead_seconds = 0) const;
  void finish(const std::string& detail = "");

  // True when stderr is a terminal (and TERM is not "dumb").
  static bool stderr_is_terminal();

 private:
  bool due_locked(double ahead_seconds = 0) const;
  void draw(double done, const std::string& detail, bool final);

  std::ostream& out_;
  bool interactive_;
  double total_;
  std::string unit_;
  double log_interval_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false, finished_ = false;
  mutable std::mutex mutex_;
};


}  // namespace shellfrac::output
