#pragma once
// What a verification run records beside its frames (docs/cli.md): probes sampled every step or frame,
// the kinetic energy per frame, control-point positions per frame (output.control_points), the pins'
// support reactions, the loads' applied totals, and the run-to-rest criterion (time.until_rest).
#include <filesystem>
#include <string>
#include <vector>

#include "output/summary.hpp"
#include "scene/model.hpp"
#include "sim/probes.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::output {

class VerificationRecorder {
 public:
  VerificationRecorder(const sim::Simulation& sim, std::filesystem::path out_dir);

  // After every step: samples the step probes and watches for rest; true once the run is at rest.
  bool after_step(const sim::Simulation& sim);
  // At every written frame (0 included): frame probes, kinetic energy, control-point positions.
  void at_frame(const sim::Simulation& sim, int frame);
  // Writes the probe CSV files and fills the summary's verification sections.
  void finish(const sim::Simulation& sim, Summary& s) const;

 private:
  void sample(const sim::Simulation& sim, bool step);

  const scene::Model& model_;
  std::filesystem::path out_dir_;
  sim::ProbeSampler probes_;
  std::vector<std::vector<sim::ProbeSample>> samples_;
  EnergyHistory energy_;
  // Run to rest: since when both measures have been below their thresholds (negative: not below now).
  double quiet_since_ = -1;
  std::optional<double> rest_time_;
};

}  // namespace shellfrac::output
