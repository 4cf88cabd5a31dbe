#pragma once
#include <string>
#include <vector>

#include "brittle/damage.hpp"
#include "brittle/material.hpp"
#include "brittle/strength.hpp"
#include "brittle/tri_mesh.hpp"
#include "mpm/solid_particles.hpp"

namespace shellfrac::brittle {

// A breakable volumetric solid: Type-I MLS-MPM particles (mpm::SolidParticles holds x, v, m, V^0, F, C
// and the stress term V^0 J sigma) plus what fracture needs per particle: the material-space position the
// crack is extracted in (thesis sec. 3.3.1), the damage state and the local strength.
struct BrittleSolid {
  BrittleMaterial material;
  mpm::SolidParticles particles;
  std::vector<Vec3> rest;                 // X_p, material (undeformed) positions
  std::vector<ParticleDamage> damage;     // c, c_his, tau_p
  std::vector<double> failure_stress;     // sigma_f per particle
  std::vector<double> brittleness;        // H per particle (from sigma_f, G_f, E, l_ch)
  double spacing = 0;                     // sampling spacing s_p

  size_t size() const { return rest.size(); }
  // Adds particles at rest at `points`, each with the given volume (total volume / count for a sampled
  // mesh), undamaged, with the material's failure stress.
  void add_particles(const std::vector<Vec3>& points, double particle_volume, const Vec3& velocity);
  // Per-particle sigma_f from regions and a Weibull draw, and H from it with l_ch = material's value or
  // sqrt(3) grid_dx. Throws InputError naming the first particle whose sigma_f^2 l_ch / (2 E G_f) >= 1.
  void set_strength(const std::vector<StrengthRegion>& regions, const WeibullStrength& weibull, double grid_dx);
  // Particles whose damage history reached `threshold` (1 = fully damaged).
  size_t count_damaged(double threshold = 1.0) const;
  std::vector<double> damage_history() const;
};

enum class Sampling {
  Regular,      // cell centres of a grid of the spacing: exact counts, fastest
  Jittered,     // one point per cell, uniformly jittered inside it
  PoissonDisk,  // blue noise (Bridson 2007) as in thesis sec. 3.2; about 0.7 points per spacing^3
};

// Points inside a closed mesh (checked with require_closed_solid, naming `source`), sorted by cell so
// that neighbours are close in memory. Refuses a spacing that would need more than `max_points` points,
// with an estimate, before sampling.
std::vector<Vec3> sample_mesh(const TriMesh& mesh, double spacing, Sampling sampling, unsigned seed,
                              const std::string& source, size_t max_points = 50'000'000);

// A solid sampled from a closed mesh; particle volumes are the mesh volume divided equally.
BrittleSolid make_solid(const TriMesh& mesh, const BrittleMaterial& material, double spacing, Sampling sampling,
                        unsigned seed, const std::string& source);

}  // namespace shellfrac::brittle
