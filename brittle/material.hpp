#pragma once
#include <cmath>

#include "brittle/nacc.hpp"

namespace shellfrac::brittle {

// How the damage variable evolves between steps (thesis sec. 2.3.1 and 4.4.1).
enum class DamageRule {
  Healing,   // c^{n+1} = c_bar: damage follows the current effective stress; c_his keeps the maximum
  Monotone,  // c^{n+1} = max(c_bar, c^n): the conventional phase-field rule
};

// Which damage model drives the solid's fracture.
enum class DamageModel {
  Rankine,     // local Rankine damage with linear softening (thesis sec. 2.3), on the Neo-Hookean solid
  PhaseField,  // the non-local phase field of CD-MPM (seed 001, secs. 3.4-5) on its split Neo-Hookean solid
  Nacc,        // CD-MPM's non-associated Cam-Clay plasticity (seed 001, sec. 6.2): fracture by softening
};

// An isotropic brittle solid: Neo-Hookean elasticity (thesis Eq. 2.3) with local Rankine damage by linear
// strain softening (Eq. 2.28-2.31), the CD-MPM phase field (the solver's PhaseFieldOptions, with
// fracture_energy as its G), or NACC plasticity on the elasticity of seed 001, Eq. 9-10 (nacc). SI units.
struct BrittleMaterial {
  double youngs_modulus = 0;   // E [Pa]
  double poisson_ratio = 0;    // nu
  double density = 0;          // rho [kg/m^3]
  double failure_stress = 0;   // sigma_f [Pa]: the default; regions and Weibull sampling vary it per particle
  double fracture_energy = 0;  // G_f [J/m^2], mode-I fracture energy
  DamageRule rule = DamageRule::Healing;  // Rankine only; the phase field never heals
  // Rankine only: the share r of its tensile stress a fully damaged particle keeps (tensile principal
  // stresses scaled by 1 - (1 - r) c instead of the thesis's 1 - c, Eq. 2.30). 0 is the thesis.
  double residual_stiffness = 0;
  // Rankine only: once its damage has reached 1 a particle's principal stretches are kept within
  // [1 / limit, limit] (limit_stretch, every step before damage_step); 0 leaves them unbounded, as the
  // thesis does (the default: docs/brittle.md, "Fully damaged particles").
  double broken_stretch_limit = 0.0;
  // Rankine only: a fully damaged particle whose every neighbour within one grid spacing (rest
  // positions) is fully damaged too is rubble (RubbleFinder) and leaves the transfers: from then on it
  // has no mass and no stress and follows the grid velocity. Off is the thesis (docs/brittle.md).
  bool retire_rubble = false;
  DamageModel model = DamageModel::Rankine;
  // l_ch [m]; 0 means the grid-cell diagonal sqrt(3) h the thesis uses (sec. 2.3.1, Table 3.3 caption).
  double characteristic_length = 0;
  NaccParams nacc;  // DamageModel::Nacc only

  double mu() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  double lambda() const {
    return youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  }
  // Dilatational (P) wave speed sqrt((lambda + 2 mu) / rho), the CFL speed of an explicit step.
  double wave_speed() const { return std::sqrt((lambda() + 2.0 * mu()) / density); }
};

}  // namespace shellfrac::brittle
