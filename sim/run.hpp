#pragma once
#include <filesystem>
#include <iosfwd>
#include <nlohmann/json.hpp>
#include <string>

#include "sim/scene.hpp"

namespace shellfrac::sim {

struct RunOptions {
  std::filesystem::path out_dir = "out";
  int threads = 0;            // 0: all cores
  bool interactive = false;   // progress bar (true) or periodic log lines (false)
};

// Runs a scene: writes the frame meshes to out_dir/frames/ and out_dir/summary.json (both atomically).
// Returns the summary that was written. Throws NumericalError on numerical failure (after writing a
// summary with status "failed"), std::runtime_error on I/O failure.
nlohmann::json run_scene(const Scene& scene, const RunOptions& options, std::ostream& log);

// Short human-readable description of a validated scene, for `shellfrac validate`.
std::string describe_scene(const Scene& scene);

}  // namespace shellfrac::sim
