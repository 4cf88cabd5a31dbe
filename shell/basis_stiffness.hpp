#pragma once
// How stiff a patch's current bases make the explicit step, and the selective mass scaling that buys the
// step back beside cracks (docs/fracture.md, "The time step follows the bases" and "Selective mass scaling").
//
// For every control point i, a Gershgorin row sum of the basis-gradient products over the points q that
// use it, divided by its mass:
//   membrane  max_i sum_q V_q a_iq (sum_j a_jq) / m_i,  a_kq = |(l_u R_k,1, l_v R_k,2)|   (cell units)
//   bending   the same with the second derivatives (l_a l_b R_k,ab), over points with a curvature.
// The largest eigenvalue of M^-1 K of either term is bounded by its value times the material constant, so
// the elastic-wave bound, calibrated on the uncut NURBS bases, scales by sqrt(reference / current).
#include <vector>

namespace shellfrac::shell {

struct BasisStiffness {
  double membrane = 0, bending = 0;
};

// The row sums per control point, before dividing by the mass.
struct BasisRows {
  std::vector<double> membrane, bending;
};

struct StepStiffness {
  BasisStiffness reference;          // of the uncut NURBS bases
  BasisStiffness current;            // of the current bases, with the added mass
  double mass_scaling_budget = 0;    // share of the patch's control-point mass that may be added
  std::vector<double> added_mass;    // per control point, >= 0
};

// max over control points with mass of row / (mass + added).
BasisStiffness stiffness_of(const BasisRows& rows, const std::vector<double>& mass,
                            const std::vector<double>& added_mass);

// The least added mass per control point that brings every row sum per mass back to `reference`; when the
// total exceeds budget x the control-point mass, the smallest ratio kappa >= 1 above the reference whose
// added mass fits (bisection). Points within round-off of the reference get none, so an uncut patch keeps
// its masses bit for bit. Writes `added_mass` (resized to mass.size()).
void choose_added_mass(const BasisRows& rows, const std::vector<double>& mass, const BasisStiffness& reference,
                       double budget, std::vector<double>& added_mass);

}  // namespace shellfrac::shell
