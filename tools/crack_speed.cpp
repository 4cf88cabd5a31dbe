#include "tools/crack_speed.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <ostream>
#include <sstream>

#include "brittle/solver.hpp"
#include "tools/bench_scenes.hpp"
#include "tools/charts.hpp"

namespace shellfrac::tools {

namespace {

using brittle::Vec3;

using bench_scenes::NotchedSpecimen;

brittle::BrittleSolid sample(const NotchedSpecimen& s, double spacing, brittle::DamageModel model) {
  brittle::BrittleSolid solid;
  solid.material.youngs_modulus = bench_scenes::kSpecimenE;
  solid.material.poisson_ratio = bench_scenes::kSpecimenNu;
  solid.material.density = bench_scenes::kSpecimenDensity;
  solid.material.fracture_energy = bench_scenes::kSpecimenFractureEnergy;
  solid.material.failure_stress = s.failure_stress;  // read by Rankine only
  solid.material.model = model;
  solid.spacing = spacing;
  std::vector<Vec3> points;
  const Vec3 half(s.half_extents[0], s.half_extents[1], s.half_extents[2]), size = 2 * half;
  const int nx = static_cast<int>(std::lround(size.x() / spacing)), ny = static_cast<int>(std::lround(size.y() / spacing)),
            nz = static_cast<int>(std::lround(size.z() / spacing));
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec3 p(-half.x() + spacing * (i + 0.5), spacing * (j + 0.5), spacing * (k + 0.5));
        if (std::abs(p.x()) < s.notch_half_width && p.z() < s.notch_depth) continue;
        points.push_back(p);
      }
  solid.add_particles(points, spacing * spacing * spacing, Vec3::Zero());
  return solid;
}

void add_loading(brittle::BrittleSolver& solver, const NotchedSpecimen& s) {
  auto vec = [](const scene::Vec3& v) { return Vec3(v[0], v[1], v[2]); };
  for (const bench_scenes::LoadingBox& box : s.loading) {
    mpm::Collider c;
    c.shape = std::make_shared<mpm::Box>(vec(box.center), vec(box.half_extents));
    c.motion.linear_velocity = vec(box.velocity);
    c.boundary = box.boundary == "sticky" ? mpm::Boundary::Sticky : mpm::Boundary::Slip;
    solver.add_collider(c);
  }
}

// The top of the broken column growing from the notch root: particle layers (rows of equal z) are walked
// up from the root while each holds a broken particle within 1 cm of the notch plane.
double crack_tip(const brittle::BrittleSolid& solid, const NotchedSpecimen& s) {
  std::vector<double> broken_z;
  for (size_t p = 0; p < solid.size(); ++p)
    if (solid.damage[p].c_his >= 1.0 && std::abs(solid.rest[p].x()) < 0.01 && solid.rest[p].z() > s.notch_depth)
      broken_z.push_back(solid.rest[p].z());
  std::sort(broken_z.begin(), broken_z.end());
  double tip = s.notch_depth;
  for (double z : broken_z) {
    if (z > tip + 1.01 * solid.spacing) break;  // a layer without a broken particle: the column ends
    tip = std::max(tip, z);
  }
  return tip;
}

// First time the tip series reaches `z` (-1: never).
double first_reach(const CrackSpeedRun& r, double z) {
  for (size_t k = 0; k < r.time.size(); ++k)
    if (r.tip[k] >= z) return r.time[k];
  return -1;
}

CrackSpeedRun run_one(const std::string& name, double dx, brittle::DamageModel model, const CrackSpeedOptions& o,
                      const RunLimits& limits) {
  const auto start = std::chrono::steady_clock::now();
  const NotchedSpecimen& s = bench_scenes::notched_specimen(name);
  brittle::BrittleSolid solid = sample(s, 0.5 * dx, model);
  solid.set_strength({}, brittle::WeibullStrength{}, dx);
  brittle::SolverOptions so;
  so.dx = dx;
  so.two_fields = false;
  so.phase_field.mobility = 2000;
  so.phase_field.length_scale = o.length_scale;
  brittle::BrittleSolver solver(solid, so);
  add_loading(solver, s);
  CrackSpeedRun r;
  r.specimen = name;
  r.model = model == brittle::DamageModel::PhaseField ? "phase_field" : "rankine";
  r.dx = dx;
  r.particles = solid.size();
  r.notch_depth = s.notch_depth;
  r.height = 2 * s.half_extents[2];
  double next_sample = 0;
  while (solver.time() < o.end) {
    check_stop(limits, "crack speed study (" + name + ", " + r.model + ", dx " + charts::number(dx) + ")");
    solver.step();
    if (solver.time() < next_sample) continue;
    next_sample += o.sample_interval;
    r.time.push_back(solver.time());
    r.tip.push_back(crack_tip(solid, s));
  }
  for (size_t k = 0; k < r.time.size() && r.start_time < 0; ++k)
    if (r.tip[k] > s.notch_depth) r.start_time = r.time[k];
  // Through: within one grid cell of the top face (the beam's top layers under the loading box are in
  // compression and need not break).
  r.through_time = first_reach(r, r.height - dx);
  // Speed over the ligament from 1/6 to 2/3 of its height above the root (the bar: 10 -> 16 mm), away from
  // the notch's start and the free top face.
  const double ligament = r.height - s.notch_depth;
  const double lo = s.notch_depth + ligament / 6, hi = s.notch_depth + 2 * ligament / 3;
  const double t_lo = first_reach(r, lo), t_hi = first_reach(r, hi);
  if (t_lo >= 0 && t_hi > t_lo) r.speed = (hi - lo) / (t_hi - t_lo);
  for (size_t p = 0; p < solid.size(); ++p)
    if (solid.damage[p].c_his >= 1.0) r.spread = std::max(r.spread, std::abs(solid.rest[p].x()));
  r.steps = static_cast<long>(solver.steps());
  r.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return r;
}

}  // namespace

std::vector<CrackSpeedRun> run_crack_speed_study(const CrackSpeedOptions& options, std::ostream& log,
                                                 const RunLimits& limits) {
  bench_scenes::notched_specimen(options.specimen);  // refuse an unknown name before any run
  std::vector<CrackSpeedRun> runs;
  for (brittle::DamageModel model : {brittle::DamageModel::Rankine, brittle::DamageModel::PhaseField})
    for (double dx : options.spacings) {
      runs.push_back(run_one(options.specimen, dx, model, options, limits));
      const CrackSpeedRun& r = runs.back();
      log << options.specimen << " " << r.model << " dx " << charts::number(dx) << ": " << r.particles << " particles, "
          << r.steps << " steps, crack " << (r.start_time < 0 ? "never started" : "started at " + charts::number(1e3 * r.start_time) + " ms")
          << ", through " << (r.through_time < 0 ? "never" : "at " + charts::number(1e3 * r.through_time) + " ms")
          << ", speed " << charts::number(r.speed) << " m/s, broken out to |x| = " << charts::number(r.spread) << " m ("
          << charts::number(r.wall_seconds) << " s)\n";
      log.flush();
    }
  return runs;
}

void write_crack_speed(const std::filesystem::path& dir, const std::vector<CrackSpeedRun>& runs, bool chart) {
  std::filesystem::create_directories(dir);
  charts::CsvTable series{{"specimen", "model", "dx", "time", "tip"}, {}};
  charts::CsvTable summary{{"specimen", "model", "dx", "particles", "steps", "start_time", "through_time", "speed",
                            "spread", "wall_seconds"},
                           {}};
  for (const CrackSpeedRun& r : runs) {
    for (size_t k = 0; k < r.time.size(); ++k)
      series.add({r.specimen, r.model, charts::number(r.dx), charts::number(r.time[k]), charts::number(r.tip[k])});
    summary.add({r.specimen, r.model, charts::number(r.dx), std::to_string(r.particles), std::to_string(r.steps),
                 charts::number(r.start_time), charts::number(r.through_time), charts::number(r.speed),
                 charts::number(r.spread), charts::number(r.wall_seconds)});
  }
  charts::write_csv(dir / "crack_speed.csv", series);
  charts::write_csv(dir / "crack_speed_summary.csv", summary);
  if (!chart) return;
  std::vector<std::string> specimens;
  for (const CrackSpeedRun& r : runs)
    if (std::find(specimens.begin(), specimens.end(), r.specimen) == specimens.end()) specimens.push_back(r.specimen);
  for (const std::string& name : specimens) {
    std::ostringstream script;
    script << "set title 'Crack tip in the notched " << name << " (height of the broken column above the notch root)'\n"
           << "set xlabel 'time [ms]'\nset ylabel 'tip z [mm]'\nset key left top\nset datafile separator ','\nplot ";
    bool first = true;
    for (const CrackSpeedRun& r : runs) {
      if (r.specimen != name) continue;
      script << (first ? "" : ", ") << "'-' using 1:2 with lines lw 2 dt " << (r.model == "rankine" ? 1 : 2) << " title '"
             << r.model << " dx " << 1e3 * r.dx << " mm'";
      first = false;
    }
    script << "\n";
    for (const CrackSpeedRun& r : runs) {
      if (r.specimen != name) continue;
      for (size_t k = 0; k < r.time.size(); ++k) script << 1e3 * r.time[k] << ',' << 1e3 * r.tip[k] << '\n';
      script << "e\n";
    }
    charts::render_png(dir / ("crack-tip-" + name + ".png"), script.str());
  }
}

}  // namespace shellfrac::tools
