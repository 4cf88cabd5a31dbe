#include "fuzz/scene_reader_target.hpp"

#include <stdexcept>

#include "core/error.hpp"
#include "scene/estimate.hpp"
#include "scene/json_io.hpp"

namespace shellfrac::fuzz {

int check_scene_text(const std::string& text) {
  const std::string source = "/nonexistent-fuzz-folder/scene.json";
  try {
    const scene::Scene s = scene::read_scene(text, source);
    const scene::ResourceEstimate e = scene::estimate_resources(s);
    scene::ResourceBudget budget;
    budget.memory_bytes = 256.0 * (1 << 20);
    scene::check_budget(e, budget, source);
    const nlohmann::json doc = scene::to_json(s);
    if (scene::to_json(scene::read_scene(doc, source)) != doc)
      throw std::logic_error("scene document changed on a round trip: " + doc.dump());
    return 0;
  } catch (const core::InputError&) {
    return 1;
  }
}

}  // namespace shellfrac::fuzz
