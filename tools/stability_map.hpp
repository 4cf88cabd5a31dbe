#pragma once
// Stability map (`shellfrac bench stability`): each method variant of a scene runs to a fixed simulated
// time and is classified by the first failure it shows, with the measured quantity that tripped it.
// Criteria and thresholds: docs/benchmarks.md.
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <vector>

#include "scene/scene.hpp"
#include "tools/run_limits.hpp"

namespace shellfrac::tools {

enum class Outcome {
  completed,
  refused,        // SceneError at construction (e.g. dt above the stability bound)
  nan,            // NumericalError during the run (NaN/inf, inverted element, runaway particle)
  energy_blowup,  // kinetic energy above 10x the reference peak
  penetration,    // a render vertex deeper than half a grid cell inside a collider
  area_loss,      // render-mesh area below 95% of the reference area
  area_gain,      // render-mesh area above 105% (over-stretched, e.g. by monotone damage)
  glued,          // fragments expected to separate did not (or a solid did not break)
  shattered,      // more pieces than expected (a solid: fragments that are not slivers)
  crease,         // coupled patches: the surface normals jump across the seam by more than 10 degrees
};
const char* outcome_name(Outcome o);

// Thresholds of the classification.
struct StabilityThresholds {
  double energy_factor = 10;          // blow-up: KE > factor x reference peak
  double initial_fraction = 0.1;      // the "initial peak" is taken over this fraction of the run
  double penetration_cells = 0.5;     // penetration beyond half a cell
  double area_tolerance = 0.05;       // area change beyond 5%
  double separation_cells = 0.5;      // the two largest fragments closer than half a cell: glued
  double crease_degrees = 10;         // normal jump across a coupling seam
};

// One variant of a scene.
struct StabilityCase {
  std::string scene;    // "tear", "drape" (shells), "bar" or "beam" (brittle solids)
  std::string variant;  // row name, e.g. "stress 2d_f"
  scene::Scene definition;  // the whole scene
  double end = 1;       // simulated seconds
  // Pieces a correct run ends with: render-mesh components of the shells (tear: 2), or the fragments
  // (slivers not counted) of the brittle solids' fracture events (bar, beam: 2).
  int expected_fragments = 1;
  double reference_area = 1;   // area the render mesh should keep [m^2]; 0: no area check (solids)
  bool seam = false;           // measure the crease across patches 0 (u = 1) and 1 (u = 0)
  double dt_factor = 0;        // dt as a multiple of the elastic-wave bound (0: the scene's own step)
};

struct StabilityResult {
  std::string scene, variant;
  Outcome outcome = Outcome::completed;
  std::string tripped_by;  // the quantity that decided the outcome ("" when completed)
  double measured = 0, threshold = 0;
  std::string detail;      // error message for refused/nan
  // Every measurement made (NaN when the run stopped before it).
  double peak_kinetic = 0, reference_kinetic = 0, penetration_cells = 0, area_ratio = 0, separation_cells = 0,
         seam_angle_degrees = 0;
  int fragments = 0, slivers = 0;
  long steps = 0;
  double dt = 0, bound = 0, simulated_seconds = 0, wall_seconds = 0;
};

// Runs one case. `baseline_peak_kinetic` is the peak kinetic energy of the scene's default variant
// (0 for the default itself): the reference peak is the larger of it and the variant's own peak over the
// first 10% of the run.
// The scene is checked against `limits` before it is built (scene::SceneError over budget; the refused
// dt variant is not, it never runs) and stepping stops on its requests (output::Interrupted).
StabilityResult run_stability_case(const StabilityCase& c, double baseline_peak_kinetic,
                                   const StabilityThresholds& t = {}, const RunLimits& limits = {});

struct StabilityConfig {
  bool full = false;
  std::filesystem::path out_dir = "out/bench";
  bool charts = true;
  RunLimits limits;  // budget per scene, stop requests between steps (output::Interrupted, nothing written)
};

// The cases of a configuration: per scene the default first, then the variants. Building the dt variants
// builds each scene once (for its stability bound): checked against `limits` first.
std::vector<StabilityCase> stability_cases(bool full, const RunLimits& limits = {});

// Runs every case, writes stability.csv and (charts on) stability-map.png into out_dir, prints the
// table to `table` and progress to `log`.
std::vector<StabilityResult> run_stability_map(const StabilityConfig& config, std::ostream& table, std::ostream& log);

}  // namespace shellfrac::tools
