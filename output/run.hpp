#pragma once
// The run driver: steps a scene frame by frame, writes every frame's meshes and the run's summary.json.
#include <filesystem>
#include <iosfwd>
#include <string>

#include "output/summary.hpp"
#include "scene/model.hpp"

namespace shellfrac::output {

struct RunOptions {
  std::filesystem::path out_dir = "out";
  int threads = 0;            // 0: all cores
  bool interactive = false;   // progress bar (true) or periodic log lines (false)
};

// Runs a scene: writes the frame meshes to out_dir/frames/ and out_dir/summary.json (both atomically).
// Returns the summary that was written. Throws NumericalError on numerical failure (after writing a
// summary with status "failed"), SceneError for input only the built simulation can judge (before any
// output), std::runtime_error on I/O failure.
Summary run_scene(const scene::Model& model, const RunOptions& options, std::ostream& log);

}  // namespace shellfrac::output
