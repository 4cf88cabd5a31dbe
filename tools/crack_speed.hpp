#pragma once
// Resolution dependence of local and non-local damage (docs/phase-field.md, "Where the local and the
// non-local model differ"): a notched specimen is broken at several grid spacings with the thesis's Rankine
// damage and with CD-MPM's phase field at a fixed physical length scale, and its crack tip is followed over
// time. Run by `shellfrac_crack_speed_study` and by `shellfrac bench sweep`. The specimens and their
// loading are bench_scenes::notched_specimen's (the stability map's bar and beam).
//  - bar: 12 x 2 x 2 cm, notch 4 mm wide and 8 mm deep from z = 0, pulled apart by two sticky grips at
//    0.1 m/s each (mode I in tension);
//  - beam: 20 x 2 x 4 cm, notch 6 mm wide and 12 mm deep, on two slip supports, pressed at its centre from
//    above by a box at 0.3 m/s (three-point bending).
// Both: E 10 MPa, nu 0.2, 1000 kg/m^3, G 8 J/m^2, two particles per cell and axis, one velocity field.
// The tip is the top of the broken column that grows from the notch root: the highest particle layer up
// to which every layer holds a broken particle within 1 cm of the notch plane, so that material broken
// elsewhere (under the beam's loading box) is not read as the crack.
#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include "tools/run_limits.hpp"

namespace shellfrac::tools {

struct CrackSpeedOptions {
  std::string specimen = "bar";  // "bar" or "beam"
  std::vector<double> spacings{0.005, 0.0033333333333333335, 0.0025};  // grid spacings dx [m]
  double end = 0.012;            // simulated seconds per run
  double length_scale = 0.0025;  // the phase field's l0 [m], the same at every spacing
  double sample_interval = 2e-5; // seconds between tip samples
};

struct CrackSpeedRun {
  std::string specimen, model;  // model: "rankine" or "phase_field"
  double dx = 0;
  size_t particles = 0;
  long steps = 0;
  std::vector<double> time, tip;  // the tip's height z over time [s, m]
  double notch_depth = 0, height = 0;  // of the specimen [m]
  double start_time = -1;    // when the tip first rose above the notch root (-1: never)
  double through_time = -1;  // when it came within one grid cell of the top face (-1: never)
  double speed = 0;          // mean speed from 1/6 to 2/3 of the ligament above the root [m/s] (0: not crossed)
  double spread = 0;         // largest |x| of a broken particle at the end [m]
  double wall_seconds = 0;
};

// Runs both models at every spacing; one progress line per run to `log`. Stops between steps on the
// limits' request (output::Interrupted).
std::vector<CrackSpeedRun> run_crack_speed_study(const CrackSpeedOptions& options, std::ostream& log,
                                                 const RunLimits& limits = {});

// Writes crack_speed.csv (specimen, model, dx, time, tip; replaced whole or not at all) and
// crack_speed_summary.csv (one row per run) into `dir`, and with `chart` crack-tip-<specimen>.png (gnuplot).
void write_crack_speed(const std::filesystem::path& dir, const std::vector<CrackSpeedRun>& runs, bool chart);

}  // namespace shellfrac::tools
