// The run driver's controls (output/run.hpp): the per-step callback sees every step, should_stop ends
// the run between steps with an "interrupted" summary that matches the files on disk, and the steps
// the driver takes are those of sim::Simulation::advance_to (same count, same final time).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <filesystem>
#include <mutex>
#include <sstream>
#include <thread>

#include "output/interrupt.hpp"
#include "output/progress.hpp"
#include "output/run.hpp"
#include "output/step_watchdog.hpp"
#include "scene/build.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::output {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

scene::Model cloth(double end) {
  return scene::build_model(R"({"time": {"end": )" + std::to_string(end) + R"(, "frame_rate": 20},
      "output": {"resolution": [4, 4]},
      "shells": [{"name": "cloth", "patch": {"type": "flat", "size": [1, 1], "cells": [4, 4]},
                  "thickness": 0.0005, "material": {"E": 1e5, "nu": 0.3, "density": 300}}]})",
                            "cloth.json");
}

fs::path scratch(const std::string& name) {
  const fs::path d = fs::temp_directory_path() / ("shellfrac-runctl-" + name + "-" + std::to_string(::getpid()));
  fs::remove_all(d);
  return d;
}

TEST(RunControl, OnStepSeesEveryStepOfAdvanceTo) {
  const scene::Model model = cloth(0.2);
  RunOptions options;
  options.out_dir = scratch("steps");
  options.threads = 1;
  long calls = 0, last_step = 0;
  double last_time = 0;
  bool increasing = true;
  options.on_step = [&](const StepReport& r) {
    ++calls;
    increasing = increasing && r.step == last_step + 1 && r.time > last_time;
    last_step = r.step;
    last_time = r.time;
    EXPECT_EQ(r.last_frame, 4);
    EXPECT_EQ(r.end, 0.2);
  };
  std::ostringstream log;
  const Summary s = run_scene(model, options, log);
  EXPECT_EQ(s.status, "completed");
  EXPECT_TRUE(increasing);
  EXPECT_EQ(calls, s.steps);
  // The same scene stepped by advance_to frame by frame: the same steps and end time.
  sim::Simulation reference(model);
  for (int f = 1; f <= 4; ++f) reference.advance_to(f / 20.0);
  EXPECT_EQ(reference.steps(), s.steps);
  EXPECT_EQ(reference.time(), s.simulated_seconds);
  fs::remove_all(options.out_dir);
}

// An end between two frames gets a last, shorter frame at the end: the run reaches `end` (it stopped at
// the last whole frame, and a scene ending before its first frame took no step at all).
TEST(RunControl, EndBetweenFramesGetsALastFrameAtTheEnd) {
  for (const double end : {0.13, 0.02}) {  // frames every 0.05 s
    const scene::Model model = cloth(end);
    RunOptions options;
    options.out_dir = scratch("tail");
    options.threads = 1;
    std::ostringstream log;
    const Summary s = run_scene(model, options, log);
    EXPECT_EQ(s.status, "completed");
    EXPECT_DOUBLE_EQ(s.simulated_seconds, end);
    EXPECT_EQ(s.frames.size(), end > 0.1 ? 4u : 2u) << end;  // 0, 0.05, 0.1, 0.13 / 0, 0.02
    EXPECT_GT(s.steps, 0);
    sim::Simulation reference(model);
    for (double t : {0.05, 0.1, 0.13})
      if (t <= end + 1e-12) reference.advance_to(t);
    reference.advance_to(end);
    EXPECT_EQ(reference.steps(), s.steps);
    fs::remove_all(options.out_dir);
  }
}

TEST(RunControl, ShouldStopEndsTheRunBetweenSteps) {
  const scene::Model model = cloth(1.0);
  RunOptions options;
  options.out_dir = scratch("stop");
  options.threads = 1;
  long steps = 0;
  options.on_step = [&](const StepReport&) { ++steps; };
  options.should_stop = [&] { return steps >= 25; };
  std::ostringstream log;
  const Summary s = run_scene(model, options, log);
  EXPECT_EQ(s.status, "interrupted");
  EXPECT_EQ(s.steps, 25);
  ASSERT_TRUE(s.error);
  EXPECT_THAT(*s.error, HasSubstr("interrupted on request"));
  // Every listed frame exists, and frames before the time reached were all written.
  EXPECT_GE(s.frames.size(), 1u);
  EXPECT_LE((s.frames.size() - 1) / 20.0, s.simulated_seconds + 1e-12);
  EXPECT_GT(s.frames.size() / 20.0, s.simulated_seconds - 1e-12);
  for (const std::string& f : s.frames) EXPECT_TRUE(fs::exists(options.out_dir / f)) << f;
  const Summary on_disk = read_summary((options.out_dir / "summary.json").string());
  EXPECT_EQ(on_disk.status, "interrupted");
  EXPECT_EQ(on_disk.frames, s.frames);
  fs::remove_all(options.out_dir);
}

TEST(RunControl, EmptyOutputFolderIsBadInput) {
  RunOptions options;
  options.out_dir = "";
  std::ostringstream log;
  EXPECT_THROW(run_scene(cloth(0.1), options, log), core::InputError);
}

// A stream buffer two threads may write to and the test may read while they do.
class SharedLog : public std::streambuf {
 public:
  std::string text() const {
    const std::lock_guard<std::mutex> lock(mutex_);
    return text_;
  }

 protected:
  int overflow(int c) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (c != EOF) text_ += static_cast<char>(c);
    return c;
  }
  std::streamsize xsputn(const char* s, std::streamsize n) override {
    const std::lock_guard<std::mutex> lock(mutex_);
    text_.append(s, static_cast<size_t>(n));
    return n;
  }

 private:
  mutable std::mutex mutex_;
  std::string text_;
};

size_t count(const std::string& text, const std::string& what) {
  size_t n = 0;
  for (size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1)) ++n;
  return n;
}

// A step that never returns on its own (the main thread blocks, as inside a very long step): the
// watchdog keeps printing the last recorded state. The intervals are scaled down (log every 20 ms,
// wake every 10 ms) so that the test waits for lines, not for seconds; it asserts that lines come and
// what they say, not when.
TEST(RunControl, WatchdogPrintsTheLastStateWhileAStepRuns) {
  SharedLog buffer;
  std::ostream log(&buffer);
  Progress progress(log, /*interactive=*/false, 1.0, "s", 0.02);
  {
    StepWatchdog watchdog(progress, 0.01);
    watchdog.record(0.25, 3, 10, 57, StepWatchdog::Activity::stepping);
    for (int i = 0; i < 20000 && count(buffer.text(), "\n") < 3; ++i) std::this_thread::sleep_for(std::chrono::milliseconds(1));
    watchdog.record_detail("fracture event of cube: MPM step 12");  // inside the same step
    for (int i = 0; i < 20000 && count(buffer.text(), "(fracture event of cube: MPM step 12)") < 2; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    watchdog.record(0.3, 3, 10, 58, StepWatchdog::Activity::writing_frame);
    for (int i = 0; i < 20000 && count(buffer.text(), "writing frame 3") < 1; ++i)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  const std::string text = buffer.text();
  EXPECT_GE(count(text, "frame 3/10, step 57; step 58 running for"), 3u) << text;
  EXPECT_GE(count(text, "frame 3/10, step 58; writing frame 3 running for"), 1u) << text;
  // The detail follows the step's own line; the next record() ends it, so the frame's lines lack it.
  std::istringstream lines_in(text);
  size_t with_detail = 0;
  for (std::string line; std::getline(lines_in, line);) {
    if (line.find("(fracture event of cube: MPM step 12)") == std::string::npos) continue;
    ++with_detail;
    EXPECT_NE(line.find("step 58 running for"), std::string::npos) << line;
    EXPECT_EQ(line.find("writing frame"), std::string::npos) << line;
  }
  EXPECT_GE(with_detail, 2u) << text;
  EXPECT_THAT(text, HasSubstr("progress  25.0% frame 3/10")) << text;  // the recorded simulated time
  // Stopped with the watchdog: nothing more is printed.
  const size_t lines = count(text, "\n");
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(count(buffer.text(), "\n"), lines);
}

TEST(RunControl, WatchdogStaysQuietWhileStepsAreShort) {
  // Each activity is recorded anew before it outlasts the period: the watchdog never speaks.
  SharedLog buffer;
  std::ostream log(&buffer);
  Progress progress(log, false, 1.0, "s", 0.0);  // a line would always be due
  {
    StepWatchdog watchdog(progress, 3600.0);
    for (long step = 0; step < 1000; ++step) watchdog.record(step * 1e-3, 1, 1, step, StepWatchdog::Activity::stepping);
  }
  EXPECT_EQ(buffer.text(), "");
}

TEST(RunControl, SignalNames) {
  EXPECT_STREQ(signal_name(2), "SIGINT");
  EXPECT_STREQ(signal_name(15), "SIGTERM");
  EXPECT_STREQ(signal_name(1), "SIGHUP");
  EXPECT_EQ(interrupt_signal(), 0);
}

}  // namespace
}  // namespace shellfrac::output
