#pragma once
// The run driver: steps a scene frame by frame, writes every frame's meshes and the run's summary.json.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>

#include "output/summary.hpp"
#include "scene/model.hpp"

namespace shellfrac::output {

// Where a run is, passed to RunOptions::on_step after every step.
struct StepReport {
  long step = 0;        // steps taken so far
  double time = 0;      // simulated time reached [s]
  double end = 0;       // time.end [s]
  int frame = 0;        // the frame being stepped towards
  int last_frame = 0;
};

struct RunOptions {
  std::filesystem::path out_dir = "out";
  int threads = 0;            // 0: all cores
  bool interactive = false;   // progress bar (true) or periodic log lines (false)
  // Files of an earlier run in out_dir/frames/ (frame_*) and its summary.json are removed before the
  // first frame unless this is set. Stale staging folders of killed runs are removed either way.
  bool keep_old_frames = false;
  // Polled between steps (with output::interrupt_signal(), set by InterruptHandlers): true stops the run
  // at the step it reached, with every complete frame kept and summary status "interrupted".
  std::function<bool()> should_stop;
  // Called after every step (progress bars of embedding programs; the driver's own progress is drawn
  // from the same place).
  std::function<void(const StepReport&)> on_step;
};

// Runs a scene: writes the frame meshes to out_dir/frames/ and out_dir/summary.json (both atomically).
// Returns the summary that was written (status "completed" or "interrupted"). Throws NumericalError on
// numerical failure (after writing a summary with status "failed"), SceneError for input only the built
// simulation can judge (before any output), core::InputError for an empty out_dir, std::runtime_error
// on I/O failure (naming the path and the OS reason; frames written before stay, a summary with status
// "failed" is written when the disk still takes it).
Summary run_scene(const scene::Model& model, const RunOptions& options, std::ostream& log);

}  // namespace shellfrac::output
