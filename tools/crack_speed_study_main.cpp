// shellfrac_crack_speed_study: resolution dependence of local and non-local damage. A notched
// bar (12 x 2 x 2 cm, notch 8 mm deep from z = 0) is pulled apart by two sticky grips at 0.1 m/s each,
// at several grid spacings, with the thesis's Rankine damage and with CD-MPM's phase field at a fixed
// physical length scale. The crack grows from the notch up through z; its tip is the highest broken
// particle within 1 cm of the notch plane. Writes crack_speed.csv (model, dx, time, tip) and the chart
// crack-tip.png (gnuplot), and prints per run when the tip reached the top face and the final path's
// spread in x.
//   shellfrac_crack_speed_study [--out DIR] [--dx 0.005,0.0033333,0.0025] [--end 0.012] [--l0 0.0025]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "brittle/solver.hpp"
#include "tools/charts.hpp"

namespace {

using namespace shellfrac;
using namespace shellfrac::brittle;

constexpr double kHalfLength = 0.06, kSide = 0.02, kNotchDepth = 0.008, kNotchHalfWidth = 0.002, kSpeed = 0.1;

std::vector<double> numbers(const std::string& s) {
  std::vector<double> out;
  std::stringstream ss(s);
  for (std::string item; std::getline(ss, item, ',');) out.push_back(std::stod(item));
  return out;
}

BrittleSolid notched_bar(double spacing, DamageModel model) {
  BrittleSolid solid;
  solid.material.youngs_modulus = 1e7;
  solid.material.poisson_ratio = 0.2;
  solid.material.density = 1000;
  solid.material.fracture_energy = 8;
  solid.material.failure_stress = 5e4;  // Rankine only
  solid.material.model = model;
  solid.spacing = spacing;
  std::vector<Vec3> pts;
  const int nx = static_cast<int>(std::lround(2 * kHalfLength / spacing)), ns = static_cast<int>(std::lround(kSide / spacing));
  for (int k = 0; k < ns; ++k)
    for (int j = 0; j < ns; ++j)
      for (int i = 0; i < nx; ++i) {
        const Vec3 p(-kHalfLength + spacing * (i + 0.5), spacing * (j + 0.5), spacing * (k + 0.5));
        if (std::abs(p.x()) < kNotchHalfWidth && p.z() < kNotchDepth) continue;
        pts.push_back(p);
      }
  solid.add_particles(pts, spacing * spacing * spacing, Vec3::Zero());
  return solid;
}

struct Run {
  std::string model;
  double dx = 0;
  std::vector<double> time, tip;
  double through_time = -1;  // when the tip reached the top layer of particles
  double spread = 0;         // largest |x| of a broken particle at the end
  size_t particles = 0;
  long steps = 0;
};

Run run(double dx, DamageModel model, double l0, double end) {
  BrittleSolid solid = notched_bar(0.5 * dx, model);
  solid.set_strength({}, WeibullStrength{}, dx);
  SolverOptions o;
  o.dx = dx;
  o.two_fields = false;
  o.phase_field.mobility = 2000;
  o.phase_field.length_scale = l0;
  BrittleSolver solver(solid, o);
  for (int side = -1; side <= 1; side += 2) {
    mpm::Collider grip;
    grip.shape = std::make_shared<mpm::Box>(Vec3(side * (kHalfLength - 0.005), 0.5 * kSide, 0.5 * kSide), Vec3(0.006, kSide, kSide));
    grip.motion.linear_velocity = Vec3(side * kSpeed, 0, 0);
    grip.boundary = mpm::Boundary::Sticky;
    solver.add_collider(grip);
  }
  Run r;
  r.model = model == DamageModel::PhaseField ? "phase_field" : "rankine";
  r.dx = dx;
  r.particles = solid.size();
  const double top = kSide - 0.5 * solid.spacing;
  double next_sample = 0;
  while (solver.time() < end) {
    solver.step();
    if (solver.time() < next_sample) continue;
    next_sample += 2e-5;
    double tip = kNotchDepth;
    for (size_t p = 0; p < solid.size(); ++p)
      if (solid.damage[p].c_his >= 1.0 && std::abs(solid.rest[p].x()) < 0.01) tip = std::max(tip, solid.rest[p].z());
    r.time.push_back(solver.time());
    r.tip.push_back(tip);
    if (r.through_time < 0 && tip >= top - 1e-9) r.through_time = solver.time();
  }
  for (size_t p = 0; p < solid.size(); ++p)
    if (solid.damage[p].c_his >= 1.0) r.spread = std::max(r.spread, std::abs(solid.rest[p].x()));
  r.steps = static_cast<long>(solver.steps());
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  std::filesystem::path out = "out/crack-speed";
  std::vector<double> spacings = {0.005, 0.0033333333333333335, 0.0025};
  double end = 0.012, l0 = 0.0025;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string key = argv[i], value = argv[i + 1];
    if (key == "--out") out = value;
    else if (key == "--dx") spacings = numbers(value);
    else if (key == "--end") end = std::stod(value);
    else if (key == "--l0") l0 = std::stod(value);
    else {
      std::fprintf(stderr, "unknown option %s\n", key.c_str());
      return 2;
    }
  }
  std::filesystem::create_directories(out);
  std::vector<Run> runs;
  for (DamageModel model : {DamageModel::Rankine, DamageModel::PhaseField})
    for (double dx : spacings) {
      runs.push_back(run(dx, model, l0, end));
      const Run& r = runs.back();
      std::printf("%-12s dx %.4f m  %7zu particles %6ld steps  through at %s  broken out to |x| = %.4f m\n", r.model.c_str(), dx,
                  r.particles, r.steps, r.through_time < 0 ? "never" : (std::to_string(1e3 * r.through_time) + " ms").c_str(),
                  r.spread);
      std::fflush(stdout);
    }
  const std::filesystem::path csv = out / "crack_speed.csv", tmp = out / "crack_speed.csv.tmp";
  {
    std::ofstream f(tmp);
    f << "model,dx,time,tip\n";
    for (const Run& r : runs)
      for (size_t k = 0; k < r.time.size(); ++k) f << r.model << ',' << r.dx << ',' << r.time[k] << ',' << r.tip[k] << '\n';
    if (!f) {
      std::fprintf(stderr, "could not write %s\n", tmp.c_str());
      return 1;
    }
  }
  std::filesystem::rename(tmp, csv);
  std::ostringstream script;
  script << "set title 'Crack tip in a pulled notched bar (tip height z above the notch root)'\n"
         << "set xlabel 'time [ms]'\nset ylabel 'tip z [mm]'\nset key left top\nset datafile separator ','\n"
         << "plot ";
  for (size_t i = 0; i < runs.size(); ++i) {
    const Run& r = runs[i];
    script << (i ? ", " : "") << "'-' using 1:2 with lines lw 2 dt " << (r.model == "rankine" ? 1 : 2) << " title '" << r.model
           << " dx " << 1e3 * r.dx << " mm'";
  }
  script << "\n";
  for (const Run& r : runs) {
    for (size_t k = 0; k < r.time.size(); ++k) script << 1e3 * r.time[k] << ',' << 1e3 * r.tip[k] << '\n';
    script << "e\n";
  }
  try {
    tools::charts::render_png(out / "crack-tip.png", script.str());
  } catch (const tools::charts::ChartError& e) {
    std::fprintf(stderr, "no chart: %s\n", e.what());
  }
  std::printf("wrote %s\n", csv.c_str());
  return 0;
}
