#pragma once
// Fragments of a fracture event as rigid bodies (thesis sec. 3.6.1): each starts in its place in the
// parent, moving with the parent's rigid velocity field, with its own mass and principal inertia, and a
// collision shape chosen by its class and convexity.
#include <string>
#include <vector>

#include "brittle/fragments.hpp"
#include "rigid/rigid_world.hpp"
#include "shatter/fragment_class.hpp"

namespace shellfrac::shatter {

struct SpawnSettings {
  VolumeRatios ratios;
  size_t collision_faces = 10000;  // N_df: face budget of a concave body's collision mesh
  // A body collides as its convex hull when the hull adds at most this share of its volume, else as its
  // mesh. The crack face one sibling bulges into is hollow on the other, so such hulls overlap their
  // siblings where they touch: siblings ignore each other until their bounds part (ShatterLoop).
  double convex_tolerance = 0.05;
  double margin = 1e-3;            // Bullet's collision margin [m], capped at a tenth of a piece's size
  rigid::Surface surface;
};

struct SpawnedFragment {
  rigid::BodyDesc body;           // ready for RigidWorld::add_body
  rigid::Pose material_to_body;   // the fragment mesh's (material) coordinates to its body frame
  FragmentClass fragment_class = FragmentClass::Tiny;
  double volume_ratio = 0;        // of the original object's volume
};

// The body of a closed mesh (material coordinates) placed by world_from_material, with the given rigid
// velocity field: v(x) = velocity + angular_velocity x (x - centre), centre in world coordinates.
SpawnedFragment rigid_piece(const brittle::TriMesh& mesh, const brittle::MassProperties& properties,
                            const rigid::Pose& world_from_material, const rigid::Vec3& centre,
                            const rigid::Vec3& velocity, const rigid::Vec3& angular_velocity, double root_volume,
                            const SpawnSettings& settings, const std::string& name);

// Momentum bookkeeping of a fracture event: the parent just before and its fragments just after.
struct RigidMoments {
  double mass = 0;
  rigid::Vec3 centre = rigid::Vec3::Zero();  // of mass (world)
  rigid::Vec3 momentum = rigid::Vec3::Zero();
  rigid::Vec3 angular_momentum = rigid::Vec3::Zero();  // about `centre`
  double kinetic_energy = 0;
};
// Sums over bodies given by mass, principal moments, pose and velocities (as the rigid world reports them).
RigidMoments rigid_moments(const std::vector<double>& masses, const std::vector<rigid::Vec3>& moments,
                           const std::vector<rigid::BodyState>& states);

}  // namespace shellfrac::shatter
