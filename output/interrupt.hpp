#pragma once
// Stopping a run between steps on SIGINT, SIGTERM or SIGHUP. The handler only
// records the signal; the run driver (output/run.cpp) polls interrupt_signal() between steps, keeps
// every complete frame, writes an "interrupted" summary and returns. A second SIGINT while the first is
// pending ends the process at once (the default action), for a run stuck inside a long step.
#include <string>

#include "core/error.hpp"

namespace shellfrac::output {

// Installs the handlers for as long as it lives and restores the previous ones afterwards.
class InterruptHandlers {
 public:
  InterruptHandlers();
  ~InterruptHandlers();
  InterruptHandlers(const InterruptHandlers&) = delete;
  InterruptHandlers& operator=(const InterruptHandlers&) = delete;
};

// The signal received since the handlers were installed, or 0.
int interrupt_signal();
// Forgets a received signal (tests, and callers that run several scenes).
void clear_interrupt();
// "SIGINT", "SIGTERM", "SIGHUP" or "signal N".
const char* signal_name(int signal);

// A command stopped before it finished (bench, preview; `run` returns an "interrupted" summary instead).
// Its exit code is 128 + the signal, 130 (as for SIGINT) when the stop was requested without one.
class Interrupted : public core::Error {
 public:
  Interrupted(const std::string& what, int signal)
      : core::Error(what, static_cast<core::ExitCode>(128 + (signal ? signal : 2))), signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

}  // namespace shellfrac::output
