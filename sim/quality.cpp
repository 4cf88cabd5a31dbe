#include "sim/quality.hpp"

#include <algorithm>
#include <cmath>

#include "sim/scene_error.hpp"

namespace shellfrac::sim {

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

int scaled(const Json& v, double factor) {
  return std::max(1, static_cast<int>(std::lround(v.get<double>() * factor)));
}

void scale_patch(Json& patch, double factor) {
  if (!patch.is_object()) return;
  const std::string type = patch.contains("type") && patch["type"].is_string() ? patch["type"].get<std::string>() : "";
  const char* key = type == "control_net" ? "refine" : "cells";
  if (type == "control_net" && !patch.contains("refine")) patch["refine"] = {1, 1};
  if (!patch.contains(key) || !patch[key].is_array()) return;  // the reader reports what is missing
  for (auto& n : patch[key])
    if (n.is_number()) n = scaled(n, factor);
}

}  // namespace

void apply_quality(Json& scene, const std::string& source) {
  if (!scene.is_object() || !scene.contains("quality")) return;
  const Json& q = scene["quality"];
  const auto& presets = quality_presets();
  const auto preset = std::find_if(presets.begin(), presets.end(),
                                   [&](const QualityPreset& p) { return q.is_string() && q.get<std::string>() == p.name; });
  if (preset == presets.end())
    throw SceneError(source, "/quality", "expected draft, default or high, got " + q.dump());
  const QualityPreset p = *preset;
  scene.erase("quality");

  if (p.cells_factor != 1.0) {
    if (scene.contains("pins") && scene["pins"].is_array())
      for (size_t i = 0; i < scene["pins"].size(); ++i)
        if (scene["pins"][i].is_object() && scene["pins"][i].contains("control_points"))
          throw SceneError(source, "/quality",
                           "quality \"" + p.name + "\" changes the patch resolution, which renumbers control points, "
                           "but /pins/" + std::to_string(i) + " selects control_points by index: pin a region instead");
    if (scene.contains("shells") && scene["shells"].is_array())
      for (auto& shell : scene["shells"])
        if (shell.is_object() && shell.contains("patch")) scale_patch(shell["patch"], p.cells_factor);
    if (scene.contains("grid") && scene["grid"].is_object() && scene["grid"].contains("dx") &&
        scene["grid"]["dx"].is_number())
      scene["grid"]["dx"] = scene["grid"]["dx"].get<double>() / p.cells_factor;
  }
  if (p.points && scene.contains("shells") && scene["shells"].is_array())
    for (auto& shell : scene["shells"]) {
      if (!shell.is_object()) continue;
      if (!shell.contains("quadrature")) shell["quadrature"] = Json::object();
      if (shell["quadrature"].is_object() && !shell["quadrature"].contains("points"))
        shell["quadrature"]["points"] = *p.points;
    }
  if (p.cfl) {
    if (!scene.contains("time")) scene["time"] = Json::object();
    Json& time = scene["time"];
    if (time.is_object() && !time.contains("cfl") && !time.contains("dt")) time["cfl"] = *p.cfl;
  }
}

}  // namespace shellfrac::sim
