#pragma once
#include "shell/in_plane_stress.hpp"

namespace shellfrac::shell {

// Associative von Mises plasticity of the Kirchhoff-Love in-plane stress (thesis sec. 4.3.2 item 4,
// after Ambati et al. 2018), for metal sheets.
//
// F^KL = F^E F^P. In the convected description the plastic part only changes the rest metric of a layer
// point: the elastic left Cauchy-Green tensor has contravariant in-plane components G_p^{ab}, the inverse
// "plastic metric", in place of gbar^{ab}. The Neo-Hookean in-plane stress of in_plane_stress.hpp then
// applies unchanged with ReferenceLayer = {G_p^{ab}, 1/sqrt(det G_p^{ab})}, so plasticity is a rest metric
// that the return mapping rewrites.
struct PlasticityParams {
  bool enabled = false;
  double yield_stress = 0;  // initial von Mises yield stress sigma_y [Pa] (Kirchhoff measure)
  double hardening = 0;     // linear isotropic hardening modulus H [Pa]
};

// Return mapping at one layer point with current tangents g1, g2. With the elastic principal in-plane
// stretches of the trial state, the fibre stretch condensed to zero normal stress (plane stress) and the
// principal Kirchhoff stresses tau_1, tau_2, the yield function is
//   q = sqrt(tau_1^2 - tau_1 tau_2 + tau_2^2) - (sigma_y + H alpha) <= 0.
// When violated, the plane-stress projection (Simo & Taylor) in principal log strains with Hencky moduli
// returns the stress to the surface (exact for the small elastic strains of metals; the Neo-Hookean stress
// of the corrected state is within a fraction of a percent of it), alpha grows by the plastic work over
// q, and `rest` is rewritten with the corrected elastic stretches (same principal directions).
// Returns true when the point yielded.
bool von_mises_return(const Vec3& g1, const Vec3& g2, double mu, double lambda, const PlasticityParams& p,
                      ReferenceLayer& rest, double& alpha);

// Von Mises measure q of the plane-stress in-plane Kirchhoff stress at tangents g1, g2 and rest metric.
double von_mises_stress(const Vec3& g1, const Vec3& g2, double mu, double lambda, const ReferenceLayer& rest);

}  // namespace shellfrac::shell
