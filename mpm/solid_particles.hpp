#pragma once
#include <vector>

#include "mpm/colliders.hpp"
#include "mpm/particle_set.hpp"

namespace shellfrac::mpm {

// Neo-Hookean volumetric material of Type-I particles (thesis Eq. 2.3, 2.6).
struct SolidMaterial {
  double mu = 0, lambda = 0, density = 0;
};

// Type-I particles: volumetric solids with the MLS-MPM force form (thesis sec. 2.2.3): APIC affine C_p,
// the force -M_p^-1 V_p^0 P F^T (x_i - x_p) w_ip on the nodes (Eq. 2.24) and F <- (I + dt C) F (Eq. 2.26).
struct SolidParticles {
  SolidMaterial material;
  std::vector<Vec3> x, v;
  std::vector<double> mass, volume;  // m_p, V_p^0
  std::vector<Mat3> F, C, stress;    // deformation gradient, affine velocity, V_p^0 P F^T

  size_t size() const { return x.size(); }
  // Adds particles at `points`, each with volume spacing^3, at rest with velocity v0.
  void add(const std::vector<Vec3>& points, double spacing, const Vec3& v0);
  // stress = V^0 P(F) F^T; returns the index of the first particle with det F <= 0 or a non-finite F,
  // or size() when all are fine.
  size_t compute_stress();
  // After g2p: F <- (I + dt C) F (Eq. 2.26) and x <- x + dt v (Eq. 2.21).
  void update(double dt);
  // The view the grid transfers use (MLS-MPM force form, APIC).
  ParticleSet view();
};

// Points inside a shape (signed distance < 0) within [lo, hi]: one per cell of a grid with the given
// spacing, jittered uniformly inside its cell (deterministic for a seed).
std::vector<Vec3> sample_jittered(const Shape& shape, const Vec3& lo, const Vec3& hi, double spacing, unsigned seed);
// Poisson-disk points inside a shape (Bridson 2007): no two closer than `spacing`, the space filled
// until no candidate fits (30 tries per active point); deterministic for a seed.
std::vector<Vec3> sample_poisson_disk(const Shape& shape, const Vec3& lo, const Vec3& hi, double spacing,
                                      unsigned seed);

}  // namespace shellfrac::mpm
