#include "tools/vibration.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "core/constants.hpp"
#include "scene/build.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::tools {

namespace {

constexpr double kPi = 3.14159265358979323846;

// The scene's "grid" object, or "grid": {} for the scene default ("default").
std::string grid_json(const TransferChoice& t) {
  std::ostringstream os;
  os.precision(17);
  os << R"("grid": {)";
  const char* separator = "";
  if (t.transfer != "default") {
    os << R"("transfer": ")" << t.transfer << '"';
    separator = ", ";
  }
  if (t.flip >= 0) {
    os << separator << R"("flip_ratio": )" << t.flip;
    separator = ", ";
  }
  if (!t.cracking_shells.empty()) os << separator << R"("cracking_shells": ")" << t.cracking_shells << '"';
  os << "}";
  return os.str();
}

}  // namespace

void measure_decay(VibrationResult& r, double periods) {
  r.extremum_time.clear();
  r.extremum_value.clear();
  const std::vector<double>& t = r.time;
  const std::vector<double>& w = r.deflection;
  for (size_t k = 1; k + 1 < w.size(); ++k) {
    const bool max = w[k] > w[k - 1] && w[k] >= w[k + 1];
    const bool min = w[k] < w[k - 1] && w[k] <= w[k + 1];
    if (!max && !min) continue;
    // Parabola through the three samples (uniform spacing h): vertex offset s in units of h.
    const double h = t[k + 1] - t[k];
    const double curv = w[k - 1] - 2 * w[k] + w[k + 1];
    const double s = curv != 0 ? 0.5 * (w[k - 1] - w[k + 1]) / curv : 0.0;
    r.extremum_time.push_back(t[k] + s * h);
    r.extremum_value.push_back(w[k] - 0.25 * (w[k - 1] - w[k + 1]) * s);
  }
  // Extrema of one oscillation alternate in sign; keep those within `periods` periods of the first, as
  // estimated from the spacing of the first two like extrema.
  r.extrema = static_cast<int>(r.extremum_time.size());
  if (r.extrema < 3) {  // no oscillation to speak of: over-damped
    r.damping_ratio = 1;
    r.period = 0;
    return;
  }
  const double first_period = r.extremum_time[2] - r.extremum_time[0];
  int last = 0;
  for (int k = 0; k < r.extrema; ++k)
    if (r.extremum_time[static_cast<size_t>(k)] <= r.extremum_time[0] + periods * first_period * 1.02) last = k;
  last -= last % 2;  // a like extremum: a whole number of periods
  const double n = last / 2.0;
  r.period = (r.extremum_time[static_cast<size_t>(last)] - r.extremum_time[0]) / n;
  const double a0 = std::abs(r.extremum_value[0]), an = std::abs(r.extremum_value[static_cast<size_t>(last)]);
  const double delta = std::log(a0 / an) / n;  // log decrement per period
  r.damping_ratio = delta / std::sqrt(4 * kPi * kPi + delta * delta);
  r.extrema = last + 1;
}

VibrationResult simply_supported_plate(const PlateVibrationCase& c) {
  const double a = c.side, t = c.thickness;
  const double D = c.youngs_modulus * t * t * t / (12 * (1 - c.poisson_ratio * c.poisson_ratio));
  const double omega = 2 * kPi * kPi / (a * a) * std::sqrt(D / (c.density * t));
  VibrationResult r;
  r.reference_period = 2 * kPi / omega;
  const int n = c.cells + c.degree;  // control points per side
  std::ostringstream pins;
  bool first = true;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      if (i != 0 && j != 0 && i != n - 1 && j != n - 1) continue;
      pins << (first ? "" : ",") << '[' << i << ',' << j << ']';
      first = false;
    }
  // Failure stress and a fracture energy ten times the grid's minimum (docs/scene-format.md).
  const double failure_stress = 0.1 * c.youngs_modulus;
  const double fracture_energy =
      10 * failure_stress * failure_stress * std::sqrt(3.0) * (a / c.cells) / (2 * c.youngs_modulus);
  std::ostringstream fracture;
  fracture.precision(17);
  if (c.breakable)
    fracture << R"(, "fracture": {"failure_stress": )" << failure_stress << R"(, "fracture_energy": )" << fracture_energy
             << "}";
  std::ostringstream js;
  js.precision(17);
  js << R"({"name": "ss_plate", "gravity": [0, 0, 0], "time": {"cfl": )" << c.cfl << "}, " << grid_json(c.transfer)
     << R"(, "shells": [{"name": "plate", "patch": {"type": "flat", "size": [)" << a << ',' << a << R"(], "cells": [)"
     << c.cells << ',' << c.cells << R"(], "degree": [)" << c.degree << ',' << c.degree << R"(]}, "thickness": )" << t << R"(, "material": {"E": )" << c.youngs_modulus
     << R"(, "nu": )" << c.poisson_ratio << R"(, "density": )" << c.density
     << fracture.str() << R"(}}],
     "pins": [{"shell": "plate", "control_points": [)"
     << pins.str() << "]}]}";
  sim::Simulation sim(scene::build_model(js.str(), "ss_plate.json"));
  // First mode as a velocity field on the control points (Greville abscissae = positions of a flat
  // uniform patch) and the shear particles.
  const double v0 = omega * c.amplitude * a;
  auto mode = [&](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(0, 0, v0 * std::sin(kPi * x.x() / a) * std::sin(kPi * x.y() / a));
  };
  const auto x = sim.positions(0);
  const auto v = sim.velocities(0);
  for (size_t k = 0; k < x.size(); ++k)
    if (sim.world().transfer_mass(0)[k] > 0) v[k] = mode(x[k]);
  const auto vs = sim.shear_velocities(0);
  const auto& xs = sim.world().shell(0).shear.x;
  for (size_t k = 0; k < xs.size(); ++k) vs[k] = mode(xs[k]);

  const double end = (c.periods + 0.6) * r.reference_period;
  const double sample = r.reference_period / 200;
  r.time.push_back(0);
  r.deflection.push_back(0);
  for (double ts = sample; ts <= end; ts += sample) {
    r.steps += sim.advance_to(ts);
    r.time.push_back(ts);
    r.deflection.push_back(sim.world().shell(0).current_surface().point(0.5, 0.5).z());
  }
  measure_decay(r, c.periods);
  // An over-damped plate creeps to rest with ripples far below the excited amplitude: no oscillation.
  if (r.extrema >= 3 && std::abs(r.extremum_value[0]) < 0.2 * c.amplitude * a) {
    r.damping_ratio = 1;
    r.period = 0;
  }
  return r;
}

namespace {

// 1/2 rho t int |v|^2 dA over a flat length x width patch whose parameter domain is [0, 1]^2.
double consistent_kinetic_energy(const shell::ShellPatch& p, double rho_t, double area, int cells_u, int cells_v) {
  const nurbs::NurbsSurface velocity(p.reference().knots_u(), p.reference().knots_v(),
                                     nurbs::Vec3List(p.v.begin(), p.v.end()), p.reference().weights());
  static const double g[4] = {-0.8611363115940526, -0.3399810435848563, 0.3399810435848563, 0.8611363115940526};
  static const double w[4] = {0.3478548451374538, 0.6521451548625461, 0.6521451548625461, 0.3478548451374538};
  double sum = 0;
  for (int cu = 0; cu < cells_u; ++cu)
    for (int cv = 0; cv < cells_v; ++cv)
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) {
          const double u = (cu + 0.5 + 0.5 * g[a]) / cells_u, v = (cv + 0.5 + 0.5 * g[b]) / cells_v;
          sum += 0.25 * w[a] * w[b] * velocity.point(u, v).squaredNorm();
        }
  return 0.5 * rho_t * area * sum / (cells_u * cells_v);
}

}  // namespace

double EnergyHistory::max_relative_drift() const {
  double worst = 0;
  for (size_t k = 0; k < time.size(); ++k) worst = std::max(worst, std::abs(total(k) - total(0)) / total(0));
  return worst;
}

EnergyHistory free_bent_sheet(const FreeSheetCase& c, int samples) {
  std::ostringstream js;
  js.precision(17);
  js << R"({"name": "free_sheet", "gravity": [0, 0, 0], "time": {"cfl": )" << c.cfl << "}, " << grid_json(c.transfer)
     << R"(, "shells": [{"name": "sheet", "patch": {"type": "flat", "size": [)" << c.length << ',' << c.width
     << R"(], "cells": [)" << c.cells_u << ',' << c.cells_v << R"(]}, "thickness": )" << c.thickness
     << R"(, "material": {"E": )" << c.youngs_modulus << R"(, "nu": )" << c.poisson_ratio << R"(, "density": )"
     << c.density << "}}]}";
  sim::Simulation sim(scene::build_model(js.str(), "free_sheet.json"));
  // Bending velocity v_z = V cos(2 pi x / L): no net momentum, no net angular momentum. V is chosen so
  // that the deflection reaches about the requested amplitude (free-free beam, first symmetric mode
  // beta L = 4.730).
  const double D = c.youngs_modulus * std::pow(c.thickness, 3) / (12 * (1 - c.poisson_ratio * c.poisson_ratio));
  const double beta = 4.730 / c.length;
  const double omega = beta * beta * std::sqrt(D / (c.density * c.thickness));
  const double v0 = omega * c.amplitude;
  auto shape = [&](const Eigen::Vector3d& x) { return Eigen::Vector3d(0, 0, v0 * std::cos(2 * kPi * x.x() / c.length)); };
  const auto x = sim.positions(0);
  const auto v = sim.velocities(0);
  for (size_t k = 0; k < x.size(); ++k) v[k] = shape(x[k]);
  const auto vs = sim.shear_velocities(0);
  const auto& xs = sim.world().shell(0).shear.x;
  for (size_t k = 0; k < xs.size(); ++k) vs[k] = shape(xs[k]);
  EnergyHistory h;
  auto record = [&] {
    h.time.push_back(sim.time());
    h.kinetic.push_back(sim.kinetic_energy());
    h.consistent_kinetic.push_back(consistent_kinetic_energy(sim.world().shell(0), c.density * c.thickness,
                                                             c.length * c.width, c.cells_u, c.cells_v));
    h.elastic.push_back(sim.world().shell(0).elastic_energy());
  };
  record();
  for (int s = 1; s <= samples; ++s) {
    h.steps += sim.advance_to(c.end * s / samples);
    record();
  }
  return h;
}

}  // namespace shellfrac::tools
