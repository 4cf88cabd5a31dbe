#pragma once
// Free-vibration measurements of the particle-grid transfer's numerical damping: a square
// simply supported plate excited in its first mode, and a free-floating sheet with a bending mode, run
// with a chosen transfer. The plate's damping ratio comes from the logarithmic decrement of the centre
// deflection's extrema, its period from their spacing; Kirchhoff plate theory gives the reference
// omega_11 = 2 pi^2 / a^2 sqrt(D / (rho t)), D = E t^3 / (12 (1 - nu^2)).
#include <string>
#include <vector>

namespace shellfrac::tools {

// A particle-grid transfer: "pic", "apic", "flip", "aflip" (scene key grid.transfer) or "default" (no
// grid key), and the FLIP share.
struct TransferChoice {
  std::string transfer = "aflip";
  double flip = -1;  // < 0: the scene default for that transfer
  std::string cracking_shells;  // grid.cracking_shells when not empty
};

struct PlateVibrationCase {
  double side = 1.0;         // a [m]
  double thickness = 0.01;   // t [m]
  int cells = 16;            // per side
  int degree = 2;            // spline degree in both directions (patch.degree)
  double youngs_modulus = 1e6, poisson_ratio = 0.3, density = 1000;
  double cfl = 1.0;          // time.cfl
  double periods = 5;        // simulated time in reference periods (a little more is run, see .cpp)
  double amplitude = 1e-3;   // centre deflection amplitude of the initial velocity field, in units of a
  TransferChoice transfer;
  // A fracture material whose failure stress (0.1 E, a strain of 10%) the vibration never reaches: the
  // plate can crack (Shell::can_crack) and runs whatever transfer the scene gives such shells, but never does.
  bool breakable = false;
};

struct VibrationResult {
  double reference_period = 0;  // 2 pi / omega_11
  double period = 0;            // measured mean spacing of like extrema; 0 when fewer than two
  double damping_ratio = 0;     // zeta from the log decrement; 1 when the plate does not oscillate
  int extrema = 0;              // extrema of the centre deflection found in the measured window
  long steps = 0;
  std::vector<double> time, deflection;  // centre deflection samples
  std::vector<double> extremum_time, extremum_value;
};

// Damping ratio zeta and period of a sampled decaying oscillation w(t) from its extrema over at most
// `periods` periods after the first extremum: delta = ln(|w_0| / |w_n|) / n per period,
// zeta = delta / sqrt(4 pi^2 + delta^2). Extrema are located by a parabola through three samples.
void measure_decay(VibrationResult& r, double periods);

// The simply supported plate (edge control-point rows pinned, mid-surface free to rotate) started with
// v_z = omega_11 A sin(pi x / a) sin(pi y / a) on every mass-carrying particle.
VibrationResult simply_supported_plate(const PlateVibrationCase& c);

struct FreeSheetCase {
  double length = 0.5, width = 0.1, thickness = 0.002;
  int cells_u = 16, cells_v = 4;
  double youngs_modulus = 1e6, poisson_ratio = 0.3, density = 500;
  double cfl = 1.0;
  double end = 2.0;          // simulated seconds
  double amplitude = 0.01;   // initial deflection [m] of the bending shape
  TransferChoice transfer;
};

// Kinetic energy two ways: `kinetic` sums 1/2 m v^2 over the particles (control points and Type III, the
// lumped masses of the transfer); `consistent_kinetic` integrates 1/2 rho t |v(u, v)|^2 over the
// mid-surface with v(u, v) = sum_k R_k v_k (4 x 4 Gauss points per cell). total() uses the lumped one, the
// energy the transfers move; both converge to each other under refinement (32 x 8 cells: 1%).
struct EnergyHistory {
  std::vector<double> time, kinetic, consistent_kinetic, elastic;
  double total(size_t k) const { return kinetic[k] + elastic[k]; }
  double consistent_total(size_t k) const { return consistent_kinetic[k] + elastic[k]; }
  // Largest |E(t) - E(0)| / E(0) over the run.
  double max_relative_drift() const;
  long steps = 0;
};

// A free-floating strip without gravity, bent into w = A cos(2 pi x / L) at rest (the free-free bending
// shape's symmetric part) and let go; kinetic + elastic energy sampled `samples` times.
EnergyHistory free_bent_sheet(const FreeSheetCase& c, int samples = 200);

}  // namespace shellfrac::tools
