#pragma once
// The rigid-body world of the shatter loop (thesis sec. 3.6): Bullet's discrete dynamics world in double
// precision behind an interface of Eigen types. It holds a ground plane, static meshes, kinematic and
// dynamic bodies, steps them at a fixed step, and reports every contact point of the last step with the
// impulse the solver applied there, which is what starts fracture events.
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "brittle/tri_mesh.hpp"
#include "rigid/frames.hpp"

namespace shellfrac::rigid {

struct Surface {
  double friction = 0.5;
  double restitution = 0.2;
};

// Collision shapes. Both mesh shapes are offset inward by the margin, so that with Bullet's padding they
// collide as the mesh's own surface.
enum class Shape {
  ConvexHull,   // the hull of the mesh's vertices (convex bodies, tiny fragments)
  ConcaveMesh,  // the triangles (Bullet's GImpact mesh shape), for concave bodies
  Sphere,       // radius only (projectiles)
};

struct BodyDesc {
  std::string name;
  Shape shape = Shape::ConvexHull;
  brittle::TriMesh mesh;  // in body coordinates: origin at the centre of mass, principal axes (ConvexHull, ConcaveMesh)
  double radius = 0;      // Sphere
  double mass = 0;        // > 0 for dynamic bodies
  Vec3 inertia = Vec3::Zero();  // principal moments (body axes)
  Pose pose;              // body coordinates to world
  Vec3 velocity = Vec3::Zero(), angular_velocity = Vec3::Zero();  // of the centre of mass; world axes
  bool kinematic = false;  // moves at its velocity whatever it hits (infinite mass)
  Surface surface;
  double margin = 1e-3;    // Bullet's collision margin [m]
};

struct BodyState {
  Pose pose;
  Vec3 velocity = Vec3::Zero(), angular_velocity = Vec3::Zero();
};

// One contact point of the last step. `normal` points from body b to body a; the solver pushed a along
// +normal with `impulse` and b along -normal. The friction impulse is on a (b gets its negative).
struct ContactPoint {
  int a = -1, b = -1;   // body ids; the ground and static meshes have ids too
  Vec3 point = Vec3::Zero();   // world, midway between the two bodies' contact points
  Vec3 normal = Vec3::Zero();
  double impulse = 0;          // normal impulse [N s], >= 0
  Vec3 friction_impulse = Vec3::Zero();
  double approach_speed = 0;   // relative normal speed before the step, positive when closing [m/s]
  double distance = 0;         // signed separation (negative: penetration)
};

class RigidWorld {
 public:
  struct Options {
    Vec3 gravity = Vec3(0, 0, -9.81);
    int solver_iterations = 20;
  };
  explicit RigidWorld(const Options& options);
  ~RigidWorld();
  RigidWorld(const RigidWorld&) = delete;
  RigidWorld& operator=(const RigidWorld&) = delete;

  // Static geometry. Returns the id contacts name it by.
  int add_ground(const Vec3& point, const Vec3& normal, const Surface& surface);
  int add_static_mesh(const std::string& name, const brittle::TriMesh& mesh, const Surface& surface);
  int add_static_box(const std::string& name, const Pose& pose, const Vec3& half_extents, const Surface& surface);
  // A dynamic (mass > 0) or kinematic body. Throws core::InputError for a body without mass, inertia or
  // shape.
  int add_body(const BodyDesc& desc);
  // Removes a body and forgets every pair it was ignored in.
  void remove_body(int id);
  bool has_body(int id) const;
  size_t num_bodies() const;  // dynamic and kinematic bodies present
  const std::string& name(int id) const;

  // Advances every body by dt (one Bullet step, no interpolation substeps) and records the contacts.
  void step(double dt);
  size_t steps() const { return steps_; }

  BodyState state(int id) const;
  void set_gravity(const Vec3& gravity);
  // Sets a dynamic body's velocities (a kick by the scene or a test) and wakes it.
  void set_velocity(int id, const Vec3& velocity, const Vec3& angular_velocity);
  double mass(int id) const;                 // 0 for static or kinematic
  Vec3 principal_inertia(int id) const;
  double margin(int id) const;
  const std::vector<ContactPoint>& contacts() const { return contacts_; }
  // Contacts between the two bodies are skipped (ignore) or processed again (and both are woken).
  void ignore_pair(int a, int b, bool ignore);
  // How many bodies Bullet skips contacts with for `id` (ignored pairs as Bullet holds them).
  size_t ignored_count(int id) const;
  // Whether the bodies' bounding boxes (shape padding included) overlap.
  bool bounds_overlap(int a, int b) const;
  // Closest signed distance between two bodies' collision shapes, margins included, as Bullet's pair query
  // reports it (negative: overlap); +infinity when they are farther apart than their margins.
  double pair_distance(int a, int b) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::vector<ContactPoint> contacts_;
  size_t steps_ = 0;
};

}  // namespace shellfrac::rigid
