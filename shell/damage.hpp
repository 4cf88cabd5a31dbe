#pragma once
#include "shell/kinematics.hpp"

namespace shellfrac::shell {

// How the damage variable evolves between steps (thesis sec. 4.4.1).
enum class DamageRule {
  // Default: c^{n+1} = cbar. Damage follows the current stress and heals when the stress unloads; the
  // explicit crack, not the particles, remembers the discontinuity. Avoids over-stretching (Fig. 4.6).
  Healing,
  // Conventional phase field: c^{n+1} = max(cbar, c^n). Kept for comparison.
  Monotone,
};

// Rankine linear strain-softening (thesis Eq. 2.28) parameters of one material.
struct FractureParams {
  bool enabled = false;
  double failure_stress = 0;     // sigma_f [Pa]; per-point overrides come from scene regions
  double fracture_energy = 0;    // G_f, mode-I fracture energy [J/m^2]
  DamageRule rule = DamageRule::Healing;
  // r: the share of its tensile stress a fully damaged point keeps. The thesis scales tensile principal
  // stresses by 1 - c (Eq. 2.30, r = 0); CD-MPM (Wolper et al. 2020, sec. 3.2) degrades to r at full
  // damage so that fully damaged material cannot stretch without bound. Here the factor is 1 - (1 - r) c.
  double residual_stiffness = 0;
};

// Brittleness H = Hbar l / (1 - Hbar l) with Hbar = sigma_f^2 / (2 E G_f) and the characteristic length
// l = l_ch (thesis sec. 2.3.1). Requires Hbar l < 1 (otherwise the softening branch snaps back); returns a
// negative value in that case so that the caller can report it with the scene context.
double brittleness(double failure_stress, double fracture_energy, double youngs_modulus, double characteristic_length);

// Damage cbar from the effective stress (thesis Eq. 2.28): 0 below sigma_f, linear strain softening up
// to sigma_f (1 + 1/H), 1 beyond.
double rankine_damage(double effective_stress, double failure_stress, double brittleness);

// In-plane Kirchhoff stress tau = sum tau^{ab} g_a (x) g_b in contravariant components.
struct InPlaneTensor {
  double t11, t12, t22;
};

// Largest principal value of tau (the in-plane Cauchy stress times det F) over the deformed tangents g_1,
// g_2. The third principal value of the in-plane stress is 0 (sigma g_3 = 0), so the 3D largest
// principal value is max(this, 0) (thesis sec. 4.4.1: sigma_bar = sigma_1).
double largest_principal(const InPlaneTensor& tau, const Vec3& g1, const Vec3& g2);

// Splits tau into tensile and compressive principal parts (thesis Eq. 2.29) and scales the tensile part
// by (1 - c) (Eq. 2.30), returning the weakened stress in the same contravariant components (Eq. 2.31).
InPlaneTensor weaken_tensile_part(const InPlaneTensor& tau, const Vec3& g1, const Vec3& g2, double c);

}  // namespace shellfrac::shell
