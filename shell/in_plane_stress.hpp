#pragma once
#include <Eigen/Core>

#include "shell/kinematics.hpp"

namespace shellfrac::shell {

using Vec9 = Eigen::Matrix<double, 9, 1>;
using Mat9 = Eigen::Matrix<double, 9, 9>;

// How the Kirchhoff-Love in-plane stress treats the thickness direction.
enum class TransverseModel {
  // The KL motion keeps the fibre length (g_3 = a_3), the trial 3D stress is computed from that F and
  // its transverse components are discarded (thesis sec. 4.5, Eq. 4.11-4.14, exactly as printed).
  // Its membrane stiffness is that of plane strain: E / (1 - nu^2) instead of E in uniaxial tension.
  Rigid,
  // Default. Before the projection, the fibre stretch lambda_3 is condensed so that the normal stress
  // vanishes (sigma_33 = 0), which is the plane-stress state the zero-transverse-stress condition asks
  // for; the projection of Eq. 4.11-4.14 then removes what is left. Matches plane-stress Neo-Hookean.
  Condensed,
  // The fibre stretch is supplied by the caller and held fixed (the Jiang et al. 2017 comparison model
  // takes it from its Type III director: lambda_3 = r_33).
  Given,
};

// Neo-Hookean first Piola-Kirchhoff stress (thesis Eq. 2.6).
Mat3 neo_hookean_pk1(const Mat3& F, double mu, double lambda);
// Neo-Hookean energy density (thesis Eq. 2.3).
double neo_hookean_energy(const Mat3& F, double mu, double lambda);

// Contravariant components sigma^ij of a symmetric tensor in the basis G = [g_1 g_2 g_3]
// (thesis Eq. 4.11): sigma = sum_ij sigma^ij g_i (x) g_j, i.e. S = G^-1 sigma G^-T (dual basis).
Mat3 contravariant_components(const Mat3& sigma, const Mat3& G);
// The same components by solving the 9x9 system of thesis Eq. 4.12 literally (for verification).
Mat3 contravariant_components_9x9(const Mat3& sigma, const Mat3& G);
// Keeps only the in-plane (alpha, beta) components (thesis Eq. 4.14).
Mat3 in_plane_part(const Mat3& sigma, const Mat3& G);

// Reference (undeformed) data of one quadrature point at one layer: the contravariant in-plane metric
// gbar^{alpha beta} and the area ratio sqrt(det gbar_{alpha beta}).
struct ReferenceLayer {
  double g11, g12, g22;  // contravariant metric of the reference layer
  double sqrt_det;       // sqrt(det of the covariant reference metric)
};
ReferenceLayer reference_layer(const Mat3& Gbar);

// In-plane Kirchhoff stress of the Neo-Hookean KL shell at one layer point in contravariant components
// tau^{alpha beta} = J sigma^{alpha beta} (thesis Eq. 4.14 times J), computed from the metrics:
//   tau^{ab} = mu (gbar^{ab} - g^{ab}) + lambda ln(J lambda_3) g^{ab},
// with J the in-plane area ratio and lambda_3 the fibre stretch (1, or condensed; see TransverseModel).
struct InPlaneStress {
  double t11, t12, t22;  // tau^{alpha beta}
  double J;              // in-plane area ratio of the layer
  double lambda3;        // fibre stretch used
  bool ok;               // false for an inverted or degenerate layer (J <= 0)
};
// given_lambda3 is used only with TransverseModel::Given.
InPlaneStress neo_hookean_in_plane(const Vec3& g1, const Vec3& g2, const ReferenceLayer& ref, double mu,
                                   double lambda, TransverseModel model, double given_lambda3 = 1.0);

// Fibre stretch lambda_3 with mu (lambda_3^2 - 1) + lambda ln(J lambda_3) = 0 (zero normal stress).
double condensed_fibre_stretch(double J, double mu, double lambda);

// Energy density of the same model (for verification and diagnostics).
double neo_hookean_in_plane_energy(const Vec3& g1, const Vec3& g2, const ReferenceLayer& ref, double mu,
                                   double lambda, TransverseModel model, double given_lambda3 = 1.0);

}  // namespace shellfrac::shell
