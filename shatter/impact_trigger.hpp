#pragma once
// What the rigid solver's contacts of one step did to each body (thesis sec. 3.6.2): the total normal
// impulse it received, where and along which direction, and how fast the contact closed. A body whose
// total exceeds its threshold RB_imp starts a fracture event.
#include <vector>

#include "rigid/rigid_world.hpp"

namespace shellfrac::shatter {

struct BodyImpact {
  int body = -1;
  double impulse = 0;                    // sum of the normal impulses on the body [N s]
  rigid::Vec3 point = rigid::Vec3::Zero();      // impulse-weighted contact point (world)
  rigid::Vec3 direction = rigid::Vec3::Zero();  // unit direction of the impulse on the body (into it)
  double approach_speed = 0;             // impulse-weighted closing speed of its contacts [m/s]
  int partner = -1;                      // the body that delivered it
  double partner_impulse = 0;
};

// One entry per (body, partner) pair whose contacts gave the body a positive normal impulse in the step,
// in order of body and partner id: each collision is judged on its own (a statue's weight on its column
// must neither add to the blow of a ball nor pull the blow's point into the statue).
std::vector<BodyImpact> gather_impacts(const std::vector<rigid::ContactPoint>& contacts);

// One impact from a body's impacts over consecutive steps (the rigid solver resolves a collision over two
// or three steps): impulses summed; point and direction weighted by impulse; the largest closing speed
// (the first step's, before the collision slowed it).
BodyImpact merge_impacts(const std::vector<BodyImpact>& steps);

}  // namespace shellfrac::shatter
