#pragma once
#include <cstdint>
#include <vector>

#include "brittle/damage.hpp"
#include "brittle/point_locator.hpp"
#include "brittle/tri_mesh.hpp"

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

}  // namespace shellfrac::brittle
