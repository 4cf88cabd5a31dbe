#pragma once
#include <optional>
#include <string>
#include <vector>


#include "output/summary.hpp"
#include "scene/model.hpp"
#include "sim/world.hpp"

namespace shellfrac::output {

// How well one interface holds together in the current state (thesis sec. 4.8).
struct SeamMeasurement {
  std::string json_path;      // "/interfaces/i"
  // Largest distance [m] between the two edges at the same edge parameter (the leader's mapped affinely
  // onto the follower's, as the coupling does): points that were one point at rest.
  double gap = 0;
  // Largest angle [degrees] between the two patches' unit normals along the seam; a normal whose
  // patch is oriented against the other at rest is flipped first.
  double angle_degrees = 0;
  // Largest mid-surface stress of the quadrature points in the two cell rows next to the seam over the
  // median stress of the same patch, the larger of the two patches. Cells within two cells of a pinned
  // control point are left out of both. Unset when neither patch carries stress (median <= 1e-9 E).
  std::optional<double> stress_ratio;
};

// Every interface of the scene, coupled or declared "none", in the order of the scene file.
std::vector<const scene::model::InterfaceSpec*> scene_seams(const scene::Model& scene);

// Where cracks meet each coupled seam: per entry of scene.interfaces, seam coordinates in [0, 1] of
// the leader's edge parameter (Simulation::seam_cracks). Empty when nothing has cracked.
using SeamCrackPositions = std::vector<std::vector<double>>;

// Measures every interface of `scene_seams(scene)` on the current control points of `patches` (the
// simulation's patches, one per scene shell). The gap and angle skip the seam within two leader cells of
// a crack that crosses it: there the seam is open by design (docs/coupling.md, "Cracks across a seam").
std::vector<SeamMeasurement> measure_seams(const scene::Model& scene, const sim::World& world,
                                           const SeamCrackPositions& cracks = {});

// The limits `shellfrac verify coupling` checks; unset means not checked.
struct SeamThresholds {
  std::optional<double> max_gap, max_angle_degrees, max_stress_ratio;
};

// Bounding-box diagonal of all shells' reference control nets [m].
double model_size(const scene::Model& scene);

// The interface's "verify" limits with the defaults filled in:
//   max_gap            1e-9 x model_size for C0 and C1; unchecked for "none"
//   max_angle_degrees  0.5 for C1; unchecked for C0 (a C0 seam may kink) and "none"
//   max_stress_ratio   kDefaultMaxStressRatio for C0 and C1; unchecked for "none"
SeamThresholds seam_thresholds(const scene::Model& scene, const scene::model::InterfaceSpec& spec);

// Default limit on the seam stress ratio. The largest value of a shipped coupled scene is 2.2e3, at
// the drapes' first contact with the ball (frame 1, where the median stress is a fraction of a pascal);
// settled scenes stay below 50. A seam that drags material along gives orders more (1.3e7 in an
// L-sheet run). Measured values in docs/coupling.md ("Stress ratio", "Shipped scenes").
inline constexpr double kDefaultMaxStressRatio = 1e4;

// Default limit on metrics.peak_edge_stretch (render-edge length over rest length, largest in any
// frame) in `verify coupling`; the scene's top-level "verify": {"max_edge_stretch": ...} changes it.
inline constexpr double kDefaultMaxEdgeStretch = 3.0;

// Collects the per-frame measurements of a run for summary.json (metrics.interfaces).
class SeamRecorder {
 public:
  explicit SeamRecorder(const scene::Model& scene);
  // False when the scene declares no interfaces (nothing is recorded or reported).
  bool active() const { return !series_.empty(); }
  void record(int frame, double time, const sim::World& world,
              const SeamCrackPositions& cracks = {});
  // One report per interface: its edges, continuity, thresholds, the per-frame series, the maxima
  // with the frame where they happened, and whether every checked maximum is within its limit.
  std::vector<InterfaceReport> reports() const;

 private:
  struct Sample {
    int frame;
    double time;
    SeamMeasurement m;
  };
  const scene::Model& scene_;
  std::vector<std::vector<Sample>> series_;  // per interface of scene_seams()
};

}  // namespace shellfrac::output
