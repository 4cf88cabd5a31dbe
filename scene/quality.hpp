#pragma once
// Quality presets: a scene may say "quality": "draft" | "default" | "high". The preset changes the
// discretisation the scene leaves open, mapped to measured points of the speed-accuracy sweep
// (docs/benchmarks.md); "default" changes nothing. Settings the scene gives explicitly win.
#include <optional>
#include <string>
#include <vector>

#include "scene/scene.hpp"

namespace shellfrac::scene {

struct QualityPreset {
  std::string name;
  double cells_factor = 1;     // every patch's cells (or control_net refine) times this, rounded, >= 1
  std::optional<int> points;   // quadrature.points of shells that do not set it
  std::optional<double> cfl;   // time.cfl when the scene sets neither cfl nor dt
};

// draft, default, high (in that order).
const std::vector<QualityPreset>& quality_presets();

// Applies the scene's preset (if any) to its fields and clears `quality`. A resolution change with pins
// that name control points by index is refused (SceneError at /quality).
void apply_quality(Scene& scene);

}  // namespace shellfrac::scene
