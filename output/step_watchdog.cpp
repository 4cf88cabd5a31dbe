#include "output/step_watchdog.hpp"

#include <cmath>
#include <utility>

#include "core/format.hpp"

namespace shellfrac::output {

StepWatchdog::StepWatchdog(Progress& progress, double period_seconds)
    : progress_(progress), period_(period_seconds), since_(std::chrono::steady_clock::now()), thread_([this] { watch(); }) {}

StepWatchdog::~StepWatchdog() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
}

void StepWatchdog::record(double time, int frame, int last_frame, long steps, Activity next) {
  const std::lock_guard<std::mutex> lock(mutex_);
  time_ = time;
  frame_ = frame;
  last_frame_ = last_frame;
  steps_ = steps;
  next_ = next;
  detail_.clear();
  since_ = std::chrono::steady_clock::now();
}

void StepWatchdog::record_detail(std::string detail) {
  const std::lock_guard<std::mutex> lock(mutex_);
  detail_ = std::move(detail);
}

std::string StepWatchdog::describe(double busy_seconds) const {
  if (next_ == Activity::setting_up) return "setting up the simulation, running for " + core::format_duration(busy_seconds);
  std::string s = "frame " + std::to_string(frame_) + "/" + std::to_string(last_frame_) + ", step " + std::to_string(steps_) + "; ";
  s += next_ == Activity::stepping ? "step " + std::to_string(steps_ + 1) : "writing frame " + std::to_string(frame_);
  s += " running for " + core::format_duration(busy_seconds);
  return detail_.empty() ? s : s + " (" + detail_ + ")";
}

void StepWatchdog::watch() {
  std::unique_lock<std::mutex> lock(mutex_);
  while (!wake_.wait_for(lock, period_, [this] { return stop_; })) {
    const double busy = std::chrono::duration<double>(std::chrono::steady_clock::now() - since_).count();
    // The driver draws a line itself after each step that finds the progress due; the watchdog speaks
    // only when the current activity has outlasted a period (so short steps never print twice).
    // Due within the next period counts as due: the line comes at most one interval after the last.
    if (busy < period_.count() || !progress_.due(period_.count())) continue;
    const double time = time_;
    const std::string line = describe(busy);
    lock.unlock();  // never hold our lock while waiting for the progress's (the driver may hold it)
    progress_.update_early(time, line, period_.count());
    lock.lock();
  }
}

}  // namespace shellfrac::output
