#include "scene/quality.hpp"

#include <algorithm>
#include <cmath>

#include "scene/scene_error.hpp"

namespace shellfrac::scene {

const std::vector<QualityPreset>& quality_presets() {
  // Chosen from the full sweep of 2026-11-22 (docs/benchmarks.md, "Quality presets"): the 2x2 stencil
  // matched the 4x4 error to 3-4 digits in every simulated benchmark at a quarter of the quadrature
  // points; cfl 1 is not used (it blew the 20-cell tear up); doubling the cells (10 -> 20) cut the
  // membrane error 3.1x and the cantilever's 4.2x.
  static const std::vector<QualityPreset> presets = {
      {"draft", 1.0, 2, std::nullopt},
      {"default", 1.0, std::nullopt, std::nullopt},
      {"high", 2.0, std::nullopt, std::nullopt},
  };
  return presets;
}

namespace {

int scaled(int n, double factor) { return std::max(1, static_cast<int>(std::lround(n * factor))); }

}  // namespace

void apply_quality(Scene& scene) {
  if (!scene.quality) return;
  const auto& presets = quality_presets();
  const auto preset = std::find_if(presets.begin(), presets.end(),
                                   [&](const QualityPreset& p) { return p.name == *scene.quality; });
  if (preset == presets.end())
    throw SceneError(scene.source, "/quality", "expected draft, default or high, got \"" + *scene.quality + "\"");
  const QualityPreset p = *preset;
  scene.quality.reset();

  if (p.cells_factor != 1.0) {
    for (size_t i = 0; i < scene.pins.size(); ++i)
      if (scene.pins[i].control_points)
        throw SceneError(scene.source, "/quality",
                         "quality \"" + p.name + "\" changes the patch resolution, which renumbers control points, "
                         "but /pins/" + std::to_string(i) + " selects control_points by index: pin a region instead");
    for (Shell& shell : scene.shells) {
      if (!shell.patch) continue;
      Patch& patch = *shell.patch;
      Opt<Int2>& counts = patch.type == "control_net" ? patch.refine : patch.cells;
      if (patch.type == "control_net" && !counts) counts = Int2{1, 1};
      if (counts) *counts = {scaled((*counts)[0], p.cells_factor), scaled((*counts)[1], p.cells_factor)};
    }
    if (scene.grid.dx) *scene.grid.dx /= p.cells_factor;
  }
  if (p.points)
    for (Shell& shell : scene.shells)
      if (!shell.quadrature.points) shell.quadrature.points = *p.points;
  if (p.cfl && !scene.time.cfl && !scene.time.dt) scene.time.cfl = *p.cfl;
}

}  // namespace shellfrac::scene
