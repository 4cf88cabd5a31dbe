#pragma once
#include <chrono>
#include <string>
#include <utility>
#include <vector>

namespace shellfrac::sim {

// Accumulates wall seconds per named time-step stage (p2g, forces, ..., output; see DESIGN.md),
// keeping the order in which stages first ran so summary.json lists them as the pipeline runs them.
class StageTimer {
 public:
  class Scope {
   public:
    Scope(StageTimer& t, size_t slot) : timer_(t), slot_(slot), start_(Clock::now()) {}
    ~Scope() { timer_.seconds_[slot_].second += Seconds(Clock::now() - start_).count(); }
    Scope(const Scope&) = delete;
    Scope& operator=(const Scope&) = delete;

   private:
    StageTimer& timer_;
    size_t slot_;
    std::chrono::steady_clock::time_point start_;
  };

  // Times the enclosing block as stage `name`.
  Scope time(const std::string& name) { return Scope(*this, slot(name)); }
  const std::vector<std::pair<std::string, double>>& seconds() const { return seconds_; }

 private:
  using Clock = std::chrono::steady_clock;
  using Seconds = std::chrono::duration<double>;
  size_t slot(const std::string& name) {
    for (size_t i = 0; i < seconds_.size(); ++i)
      if (seconds_[i].first == name) return i;
    seconds_.emplace_back(name, 0.0);
    return seconds_.size() - 1;
  }
  std::vector<std::pair<std::string, double>> seconds_;
};

}  // namespace shellfrac::sim
