#include "output/progress.hpp"

#include "core/format.hpp"

#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <ostream>

namespace shellfrac::output {

bool Progress::stderr_is_terminal() {
  const char* term = std::getenv("TERM");
  return ::isatty(STDERR_FILENO) && !(term && std::strcmp(term, "dumb") == 0);
}

Progress::Progress(std::ostream& out, bool interactive, double total, std::string unit,
                   double log_interval_seconds)
    : out_(out),
      interactive_(interactive),
      total_(total > 0 ? total : 1.0),
      unit_(std::move(unit)),
      log_interval_(log_interval_seconds),
      start_(std::chrono::steady_clock::now()),
      last_draw_(start_) {}

bool Progress::due(double ahead_seconds) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return due_locked(ahead_seconds);
}

bool Progress::due_locked(double ahead_seconds) const {
  const double since =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - last_draw_).count() + ahead_seconds;
  // Short runs log nothing mid-way; the bar is redrawn at most ten times a second.
  return since >= (interactive_ ? 0.1 : log_interval_);
}

void Progress::update(double done, const std::string& detail) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!finished_ && due_locked()) draw(done, detail, false);
}

void Progress::update_early(double done, const std::string& detail, double ahead_seconds) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (!finished_ && due_locked(ahead_seconds)) draw(done, detail, false);
}

void Progress::finish(const std::string& detail) {
  const std::lock_guard<std::mutex> lock(mutex_);
  draw(total_, detail, true);
  finished_ = true;  // a watchdog still running draws nothing after the last line
}

void Progress::draw(double done, const std::string& detail, bool final) {
  const auto now = std::chrono::steady_clock::now();
  last_draw_ = now;
  drawn_ = true;
  const double elapsed = std::chrono::duration<double>(now - start_).count();
  const double frac = std::clamp(done / total_, 0.0, 1.0);
  const double eta = frac > 0 ? elapsed * (1.0 - frac) / frac : -1.0;
  char pct[16];
  std::snprintf(pct, sizeof pct, "%5.1f%%", 100.0 * frac);
  if (interactive_) {
    constexpr int kWidth = 30;
    const int filled = static_cast<int>(frac * kWidth);
    std::string bar(static_cast<size_t>(filled), '#');
    bar.resize(kWidth, '.');
    out_ << "\r[" << bar << "] " << pct << "  " << detail << "  elapsed "
         << core::format_duration(elapsed);
    if (!final) out_ << "  ETA " << core::format_duration(eta);
    out_ << "\033[K";  // clear the rest of the line
    if (final) out_ << '\n';
  } else {
    out_ << "progress " << pct << " " << detail << " elapsed " << core::format_duration(elapsed);
    if (!final) out_ << " ETA " << core::format_duration(eta);
    out_ << '\n';
  }
  out_.flush();
}

}  // namespace shellfrac::output
