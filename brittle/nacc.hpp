#pragma once
#include <Eigen/Core>
#include <string>

namespace shellfrac::brittle {

// Non-associated Cam-Clay plasticity (NACC, seed 001, sec. 6.2) on the elasticity of seed 001, Eq. 9-10.
// The yield surface is an ellipse in (p, q), pressure p = -tr(tau)/3 and shear q = sqrt(3/2) |dev tau|:
//   y(p, q) = q^2 (1 + 2 beta) + M^2 (p + beta p0)(p - p0)                         (sec. 6.2.1)
// with p0 = kappa sinh(xi max(-alpha, 0)). The hardening state alpha starts at alpha0 < 0; it falls (the
// ellipse grows) under compression and rises (it shrinks) under tension or shear on the tensile side.
// Once alpha >= 0 the ellipse is a point: the material carries no stress and is broken.
struct NaccParams {
  double alpha0 = -0.01;  // initial hardening state; < 0 for a material with strength
  double beta = 0.5;      // cohesion: tensile strength beta p0 against compressive strength p0
  double xi = 1.0;        // hardening factor
  double friction = 1.0;  // M, the slope of the ellipse (shear strength against pressure)
  bool hardening = true;  // sec. 6.2.3; off keeps alpha (and the ellipse) fixed
  // Empty when physical, else what is wrong.
  std::string validate() const;
};

// Which branch of the return mapping a trial state took (sec. 6.2.2).
enum class NaccCase {
  Elastic,      // inside the yield surface: unchanged
  Compression,  // case 1, p > p0: projected to the compressive tip (p0, 0)
  Tension,      // case 2, p < -beta p0: projected to the tensile tip (-beta p0, 0)
  Shear,        // case 3: q brought onto the ellipse at the trial pressure, volume kept
};
const char* to_string(NaccCase c);

// The return mapping acts in the principal (singular value) space of the elastic deformation gradient.
struct NaccState {
  Eigen::Vector3d stretch;  // singular values of F^E
  double alpha = 0;         // hardening state
  NaccCase branch = NaccCase::Elastic;
  int iterations = 0;       // Newton iterations (0 for the analytic return)
};

// p0 = kappa sinh(xi max(-alpha, 0)), the compressive tip of the ellipse.
double nacc_p0(double alpha, double kappa, const NaccParams& m);
// Pressure and shear invariants (p, q) of Eq. 10's Kirchhoff stress at principal stretches s.
Eigen::Vector2d nacc_invariants(const Eigen::Vector3d& s, double mu, double kappa);
// y(p, q) of sec. 6.2.1.
double nacc_yield(double p, double q, double p0, const NaccParams& m);

// The analytic return of sec. 6.2.2-6.2.3. Cases 1 and 2 set J^E = sqrt(1 - 2 p/kappa) at the tip (the
// inverse of Eq. 10's pressure; the printed sqrt(-2p/kappa) + 1 is a misprint). Case 3 keeps J^E and the direction of the
// deviatoric stress, solves Eq. 14 for q, and picks the isotropic part of b^E so that det b^E = J^2
// exactly (a closed-form cubic), so det F^P is unchanged to round-off: the flow is isochoric.
NaccState nacc_return(const Eigen::Vector3d& trial_stretch, double alpha, double mu, double kappa, const NaccParams& m);
// The same equations solved iteratively: Newton on (log stretches, shear scale) for case 3 and on J and
// the ray parameter for the tips and the hardening. The reference for tests and the benchmark that
// measures the analytic return's speed-up (seed 001 claims 2x over an iterative return).
NaccState nacc_return_newton(const Eigen::Vector3d& trial_stretch, double alpha, double mu, double kappa,
                             const NaccParams& m);

enum class NaccSolve { Analytic, Newton };

// Projects F^E in place (SVD, return, reconstruction U Sigma V^T) and updates alpha. Returns the branch.
// F must have det F > 0. The solver uses the analytic return; Newton is there to measure it against.
NaccCase nacc_project(Eigen::Matrix3d& F, double& alpha, double mu, double kappa, const NaccParams& m,
                      NaccSolve solve = NaccSolve::Analytic);

// Damage in the thesis's convention (0 intact, 1 broken) from how far the ellipse has shrunk:
// 1 - p0(alpha) / p0(alpha0), clamped to [0, 1]. Hardening beyond alpha0 reads as intact.
double nacc_damage(double alpha, double kappa, const NaccParams& m);

}  // namespace shellfrac::brittle
