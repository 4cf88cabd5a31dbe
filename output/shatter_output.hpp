#pragma once
// What the run writes for the shatter loop (docs/brittle.md, "The shatter loop"): per frame one mesh file,
// rigid/frame_NNNNN.<ext>, with every body and fragment in world space as one named object each, and the
// "shatter" section of summary.json (fracture events, fragments per class, totals as in thesis Table 3.3).
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "scene/model.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::output {

class ShatterWriter {
 public:
  ShatterWriter(const scene::Model& model, std::filesystem::path out_dir);
  // Writes frame `frame` atomically (complete or absent); nothing without a shatter loop. Throws
  // std::runtime_error naming the file when a write fails.
  void write_frame(const sim::Simulation& sim, int frame);
  const std::vector<std::string>& frames() const { return frames_; }  // relative to the run folder
  // rigid/shatter.gltf (+ .bin): every piece's mesh once, in its body frame, and its motion over the
  // frames written so far as glTF animation (scale 0 while it does not exist). Returns the file relative
  // to the run folder; "" without a shatter loop.
  std::string write_animation(const sim::Simulation& sim);

 private:
  const scene::Model& model_;
  std::filesystem::path out_dir_;
  std::vector<std::string> frames_;
  std::vector<float> times_;                          // of the frames written
  std::vector<std::vector<std::optional<rigid::Pose>>> poses_;  // [frame][piece]: body to world while alive
};

nlohmann::json shatter_json(const shatter::ShatterLoop& loop, const std::vector<std::string>& frames,
                            const std::string& animation);

}  // namespace shellfrac::output
