#pragma once
// Stopping a run between steps on SIGINT, SIGTERM or SIGHUP (issue 14, "Signals"). The handler only
// records the signal; the run driver (output/run.cpp) polls interrupt_signal() between steps, keeps
// every complete frame, writes an "interrupted" summary and returns. A second SIGINT while the first is
// pending ends the process at once (the default action), for a run stuck inside a long step.
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

}  // namespace shellfrac::output
