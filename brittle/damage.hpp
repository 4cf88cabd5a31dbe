#pragma once
#include <Eigen/Core>

#include "brittle/material.hpp"

namespace shellfrac::brittle {

using Mat3d = Eigen::Matrix3d;

// Brittleness H = Hbar l / (1 - Hbar l), Hbar = sigma_f^2 / (2 E G_f) (thesis sec. 2.3.1). Needs
// 0 < Hbar l < 1 (else the softening branch would snap back); returns a negative value then, so that the
// caller can name the particle or region.
double brittleness(double failure_stress, double fracture_energy, double youngs_modulus, double characteristic_length);

// c_bar from the effective stress sigma_bar (thesis Eq. 2.28): 0 up to sigma_f, (1 + H)(1 - sigma_f /
// sigma_bar) on the softening branch, 1 from sigma_f (1 + 1/H) on.
double rankine_damage(double effective_stress, double failure_stress, double brittleness);

// Kirchhoff stress tau = J sigma of the Neo-Hookean solid (Eq. 2.3, 2.6): mu (F F^T - I) + lambda ln J I.
Mat3d neo_hookean_kirchhoff(const Mat3d& F, double mu, double lambda);

// Scales the positive principal values of a symmetric tensor by (1 - c) and keeps the others (Eq.
// 2.29-2.31); also returns its largest principal value.
Mat3d weaken_tensile_part(const Mat3d& symmetric, double c, double* largest_principal = nullptr);

// Upper bound of the largest eigenvalue of a symmetric matrix (Gershgorin discs): a cheap test that the
// effective stress is below sigma_f, so that most particles skip the eigen-decomposition.
double largest_eigenvalue_bound(const Mat3d& symmetric);

// The damage state of one particle.
struct ParticleDamage {
  double c = 0;        // current damage
  double c_his = 0;    // largest damage so far
  double tau = -1;     // time c_his first reached 1 (thesis sec. 3.7), -1 while it has not
  double history = 0;  // phase field only: Psi^H, the largest tensile energy so far (CD-MPM Eq. 5) [J/m^3]
  double alpha = 0;    // NACC only: the hardening state (CD-MPM sec. 6.2.3), alpha0 at the start
};

// One damage step of a particle (thesis sec. 2.3.2): effective stress sigma_bar = tau(F)/J, its largest
// principal value, c_bar (Eq. 2.28), the rule, c_his and the damage time; returns the weakened stress
// term V^0 J sigma(F, c) the MLS-MPM force uses (Eq. 2.24, 2.27). `time` is the time after the step.
Mat3d damage_step(const Mat3d& F, double rest_volume, double mu, double lambda, double failure_stress,
                  double brittleness, DamageRule rule, double residual_stiffness, double time,
                  ParticleDamage& state);

// Clamps the principal stretches of F into [1 / limit, limit] (F changed in place, its rotations kept);
// true if any was outside. Used on fully damaged particles (BrittleMaterial::broken_stretch_limit): with
// no tensile stress left, nothing else stops their stretch from growing without bound.
bool limit_stretch(Mat3d& F, double limit);

}  // namespace shellfrac::brittle
