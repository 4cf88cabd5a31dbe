// The run driver's controls (output/run.hpp): the per-step callback sees every step, should_stop ends
// the run between steps with an "interrupted" summary that matches the files on disk, and the steps
// the driver takes are those of sim::Simulation::advance_to (same count, same final time).
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <sstream>

#include "output/interrupt.hpp"
#include "output/run.hpp"
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

TEST(RunControl, SignalNames) {
  EXPECT_STREQ(signal_name(2), "SIGINT");
  EXPECT_STREQ(signal_name(15), "SIGTERM");
  EXPECT_STREQ(signal_name(1), "SIGHUP");
  EXPECT_EQ(interrupt_signal(), 0);
}

}  // namespace
}  // namespace shellfrac::output
