#pragma once
#include <cstdint>
#include <vector>

#include "brittle/damage.hpp"
#include "brittle/impact.hpp"
#include "brittle/point_locator.hpp"
#include "brittle/tri_mesh.hpp"
#include "mpm/solid_particles.hpp"

namespace shellfrac::brittle {

// Rubble: a fully damaged particle (c_his >= 1) whose every neighbour within a rest distance is fully
// damaged too. Nothing intact is left around it to load it, and its damage can no longer change the
// crack (extraction reads the damage history, which stays 1), so the solver may take it out of the
// transfers (docs/brittle.md, "Fully damaged particles"). The caller may hold a candidate back for now
// (`eligible`, the solver: while it is compressed, since crushed material still carries the load).
// A particle once marked stays rubble.
class RubbleFinder {
 public:
  RubbleFinder() = default;
  // rest: the particles' material positions (kept by reference); radius: the neighbourhood [m].
  RubbleFinder(const std::vector<Vec3>& rest, double radius);

  // Marks every particle that has become rubble since the last call in `rubble` (sized to the particle
  // count) and returns the newly marked indices in increasing order. Only particles with eligible[p] set
  // are marked (null: all are).
  std::vector<uint32_t> update(const std::vector<ParticleDamage>& damage, const uint8_t* eligible,
                               std::vector<uint8_t>& rubble);

 private:
  // An intact neighbour of p within the radius, or -1 when every neighbour is fully damaged.
  int64_t intact_neighbour(size_t p, const std::vector<ParticleDamage>& damage) const;

  const std::vector<Vec3>* rest_ = nullptr;
  double radius_ = 0;
  PointBuckets buckets_;  // bucket edge >= radius: the neighbours of p lie in the 27 buckets around its own
  // Per particle: the intact neighbour that kept it from being rubble at the last check. It is checked
  // again only once that neighbour has broken, so a step costs O(1) per waiting candidate.
  std::vector<int64_t> blocker_;
};

// The rubble of one solid in a fracture run (material.fully_damaged "rubble"): which particles have left
// the transfers, the masses the transfers see instead of the particles' own (0 for rubble), where each
// piece of rubble is held, and the momentum it took along. Empty (enabled() false) when the rule is off.
class Rubble {
 public:
  Rubble() = default;
  // rest: the solid's material positions (kept by reference); radius: the neighbourhood [m].
  Rubble(const std::vector<Vec3>& rest, double radius);
  bool enabled() const { return !flag_.empty(); }

  // Takes the particles that have become rubble out of the transfers: zero transfer mass and stress,
  // held where they are now. A candidate waits while it is compressed (det F < 1): crushed material still
  // carries the load into the solid. Returns how many left.
  size_t retire(mpm::SolidParticles& q, const std::vector<ParticleDamage>& damage);
  // Puts the rubble back where it was retired, at rest (after g2p moved it).
  void hold(mpm::SolidParticles& q) const;
  // Moves every ghost anchored on rubble to the nearest particle that is not rubble (rest positions):
  // crushed material passes the contact force on.
  void reanchor(std::vector<GhostParticle>& ghosts, const std::vector<Vec3>& rest);

  // The masses p2g and the momentum books use: the particles' own while nothing is rubble.
  const double* transfer_mass(const mpm::SolidParticles& q) const {
    return count_ > 0 ? transfer_mass_.data() : q.mass.data();
  }
  size_t count() const { return count_; }
  bool contains(size_t p) const { return count_ > 0 && flag_[p]; }
  size_t reanchored_ghosts() const { return reanchored_ghosts_; }
  // The momentum the rubble had when it left the transfers.
  Vec3 momentum() const { return momentum_; }

 private:
  RubbleFinder finder_;
  std::vector<uint8_t> flag_, eligible_;  // per particle
  std::vector<double> transfer_mass_;
  size_t count_ = 0;
  std::vector<size_t> list_;  // rubble particles in the order they were retired
  std::vector<Vec3> held_x_;  // and their positions then
  size_t reanchored_ghosts_ = 0;
  Vec3 momentum_ = Vec3::Zero();
};

}  // namespace shellfrac::brittle
