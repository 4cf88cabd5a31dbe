#pragma once
// Quality presets: a scene may say "quality": "draft" | "default" | "high" at the top level. The preset
// is a rewrite of the scene's JSON before it is read, mapped to measured points of the speed-accuracy
// sweep (docs/benchmarks.md); "default" changes nothing. Settings the scene gives explicitly win.
#include <optional>
#include <string>
#include <vector>

#include "sim/json_reader.hpp"

namespace shellfrac::sim {

struct QualityPreset {
  std::string name;
  double cells_factor = 1;     // every patch's cells (or control_net refine) times this, rounded, >= 1
  std::optional<int> points;   // quadrature.points of shells that do not set it
  std::optional<double> cfl;   // time.cfl when the scene sets neither cfl nor dt
};

// draft, default, high (in that order).
const std::vector<QualityPreset>& quality_presets();

// Applies and removes the top-level "quality" key of a scene document. Unknown values and presets that
// cannot apply (a resolution change with pins that name control points by index) throw SceneError at
// /quality naming `source`.
void apply_quality(Json& scene, const std::string& source);

}  // namespace shellfrac::sim
