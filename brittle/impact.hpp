#pragma once
#include <string>
#include <vector>

#include "brittle/brittle_solid.hpp"
#include "brittle/hertz.hpp"
#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// An impact on the object (thesis sec. 3.6.2), in the object's material space: the impulse I delivered
// along `direction` over the contact duration t_c, as a constant force I / t_c from start_time on.
struct Impact {
  Vec3 point = Vec3::Zero();
  Vec3 direction = Vec3::Zero();  // of the force on the object (into it); normalised on use
  double impulse = 0;             // I [N s]
  double duration = 0;            // t_c [s]; e.g. from hertz_contact_time
  double start_time = 0;          // [s]
  // The force is spread uniformly over the surface within this distance of the point (thesis sec. 3.9:
  // a circular area avoids the exaggerated damage of a point load), one ghost per triangle at the
  // centroid of its part inside; 0 means two particle spacings. The surface's closest point alone if no
  // triangle reaches that close.
  double radius = 0;
  // A direction that does not point into the surface is an input error, unless this is set: then the
  // force pushes along the contact patch's inward normal (the thesis's traction I n / (t_c A), Eq. 3.12).
  // The shatter loop sets it: a rigid contact's mean normal and mean point, summed over several contact
  // points and steps, can meet a concave or edged fragment where its surface faces another way.
  bool normal_if_outward = false;
};

// A ghost particle (thesis Eq. 3.12): a massless point riding with an anchor particle that hands a
// constant force to its grid nodes while active. Its force is traction I n / (t_c A_e) times the element
// area: the impact's force divided over the chosen elements in proportion to their area.
struct GhostParticle {
  Vec3 rest = Vec3::Zero();   // material position (just inside the surface element)
  Vec3 force = Vec3::Zero();  // [N]
  size_t anchor = 0;          // nearest particle: the ghost moves with it
  double start = 0, end = 0;  // active for start <= t < end
};

// Ghost particles of one impact on the surface of `mesh` (material space) for a sampled solid. Throws
// InputError naming `source` when the impulse or duration is not positive, the direction is zero or
// points out of the object, or the point lies farther than max(radius, 2 s_p) from the surface.
std::vector<GhostParticle> impact_ghosts(const Impact& impact, const TriMesh& mesh, const BrittleSolid& solid,
                                         const std::string& source);

// Contact duration of a projectile (sphere of the given material, radius, mass) hitting the object at a
// point: the object's equivalent radius is the distance from the contact point to its centre of mass
// (thesis sec. 3.6.2) and its mass the solid's. Thin wrapper over hertz_contact_time (Eq. 3.8-3.11).
double impact_duration(const HertzBody& projectile, const BrittleSolid& solid, const Vec3& contact_point,
                       double relative_speed);

}  // namespace shellfrac::brittle
