#pragma once
#include <Eigen/Core>

namespace shellfrac::brittle {

// The Neo-Hookean variant of CD-MPM (seed 001, Eq. 8-10) that phase-field fracture degrades: a shear
// term on the volume-free part J^{-1/3} F and a bulk term on J,
//   Psi^mu = mu/2 (tr(Fbar^T Fbar) - 3),  Fbar = J^{-1/3} F,
//   Psi^kappa = kappa/2 ((J^2 - 1)/2 - ln J),
// split into a tensile part that damage weakens and a compressive part it leaves alone (Amor et al.):
// Psi+ = Psi^mu + Psi^kappa for J >= 1, Psi^mu alone for J < 1; Psi- = Psi^kappa for J < 1, else 0.
struct SplitEnergy {
  double tensile = 0;      // Psi+ [J/m^3]
  double compressive = 0;  // Psi- [J/m^3]
};

// Bulk modulus kappa = lambda + 2 mu / 3 of the Lame parameters.
inline double bulk_modulus(double mu, double lambda) { return lambda + 2.0 * mu / 3.0; }

// Degradation g(c) = (1 - r) c^2 + r (seed 001, Eq. 3); c = 1 healthy, 0 broken, r the residual stiffness.
inline double degradation(double c, double residual) { return (1.0 - residual) * c * c + residual; }

SplitEnergy split_energy(const Eigen::Matrix3d& F, double mu, double kappa);

// Kirchhoff stress tau = J sigma of g Psi+ + Psi- (Eq. 3 with Eq. 10): the shear part
// mu J^{-2/3} dev(F F^T) and, for J >= 1 only, the bulk part kappa/2 (J^2 - 1) I are scaled by g.
// g = 1 gives the undamaged stress of Eq. 10.
Eigen::Matrix3d split_kirchhoff(const Eigen::Matrix3d& F, double mu, double kappa, double g);

}  // namespace shellfrac::brittle
