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
  // Whether update() would draw now: callers that report every step build their detail text only then.
  bool due() const;
  void finish(const std::string& detail = "");

  // True when stderr is a terminal (and TERM is not "dumb").
  static bool stderr_is_terminal();

 private:
  bool due_locked() const;
  void draw(double done, const std::string& detail, bool final);

  std::ostream& out_;
  bool interactive_;
  double total_;
  std::string unit_;
  double log_interval_;
  std::chrono::steady_clock::time_point start_, last_draw_;
  bool drawn_ = false;
  mutable std::mutex mutex_;
};


}  // namespace shellfrac::output
