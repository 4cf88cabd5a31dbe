#pragma once
#include <Eigen/Geometry>
#include <memory>
#include <vector>

#include "mpm/bspline_weights.hpp"

namespace shellfrac::mpm {

class SparseGrid;

// How a collider treats grid velocity where it overlaps the material.
enum class Boundary {
  Sticky,    // velocity becomes the collider's
  Slip,      // approaching normal velocity removed, tangential kept
  Friction,  // slip plus Coulomb friction on the tangential part
};

// Rigid kinematic motion of a collider: constant linear and angular velocity about `pivot`, or
// piecewise-linear keyframes of translation (and rotation about `pivot`).
struct Keyframe {
  double time = 0;
  Vec3 translation = Vec3::Zero();
  Vec3 rotation = Vec3::Zero();  // rotation vector (axis * angle, radians)
};

struct RigidMotion {
  Vec3 pivot = Vec3::Zero();
  Vec3 linear_velocity = Vec3::Zero();
  Vec3 angular_velocity = Vec3::Zero();
  std::vector<Keyframe> keyframes;  // when non-empty, overrides the constant velocities

  // Pose at time t: world = rotation * (local - pivot) + pivot + translation.
  Eigen::Isometry3d pose(double t) const;
  // Velocity of the rigid body at world point x and time t.
  Vec3 velocity_at(const Vec3& x, double t) const;
};

// Signed distance (negative inside) and outward unit normal of a shape in its own (local) frame.
class Shape {
 public:
  virtual ~Shape() = default;
  virtual double signed_distance(const Vec3& local) const = 0;
  virtual Vec3 normal(const Vec3& local) const = 0;
};

class HalfSpace : public Shape {
 public:
  HalfSpace(Vec3 point, Vec3 normal) : point_(std::move(point)), normal_(normal.normalized()) {}
  double signed_distance(const Vec3& x) const override { return (x - point_).dot(normal_); }
  Vec3 normal(const Vec3&) const override { return normal_; }

 private:
  Vec3 point_, normal_;
};

class Sphere : public Shape {
 public:
  Sphere(Vec3 center, double radius) : center_(std::move(center)), radius_(radius) {}
  double signed_distance(const Vec3& x) const override { return (x - center_).norm() - radius_; }
  Vec3 normal(const Vec3& x) const override;

 private:
  Vec3 center_;
  double radius_;
};

// Axis-aligned (in its local frame) box given by centre and half extents.
class Box : public Shape {
 public:
  Box(Vec3 center, Vec3 half_extents) : center_(std::move(center)), half_(std::move(half_extents)) {}
  double signed_distance(const Vec3& x) const override;
  Vec3 normal(const Vec3& x) const override;

 private:
  Vec3 center_, half_;
};

struct Collider {
  std::shared_ptr<const Shape> shape;
  RigidMotion motion;
  Boundary boundary = Boundary::Friction;
  double friction = 0.3;  // Coulomb coefficient for Boundary::Friction

  double signed_distance(const Vec3& x, double t) const;
  Vec3 normal(const Vec3& x, double t) const;
};

// Velocity after contact of material moving with v at a point where the collider has velocity vc and
// outward normal n (applied where the signed distance is <= 0).
Vec3 collide_velocity(const Vec3& v, const Vec3& vc, const Vec3& n, Boundary boundary, double friction);

// Applies every collider to the grid node velocities at time t (after the grid velocity update).
void apply_colliders(SparseGrid& grid, const std::vector<Collider>& colliders, double t);

// Applies every collider to particles after advection: a particle found inside is moved back to the
// surface along the normal and its velocity is treated as at a node. Grid-only contact lets material
// sink up to about a cell into a collider; this keeps the advected particles outside.
void project_particles(std::vector<Vec3>& x, std::vector<Vec3>& v, const std::vector<Collider>& colliders, double t);

// Momentum a collider gave the material, and its moment about a point: what a dynamic collider (a rigid
// body) must lose in return.
struct ContactImpulse {
  Vec3 linear = Vec3::Zero();
  Vec3 angular = Vec3::Zero();
  ContactImpulse& operator+=(const ContactImpulse& o) {
    linear += o.linear;
    angular += o.angular;
    return *this;
  }
};

// One collider on the grid nodes, as apply_colliders does, returning sum m_i (v_i' - v_i) and its moment
// sum (x_i - about) x m_i (v_i' - v_i). Summed in fixed node ranges, then in order: the same for any
// thread count.
ContactImpulse apply_collider(SparseGrid& grid, const Collider& collider, double t, const Vec3& about);
// One collider on advected particles of masses `mass`, as project_particles does, returning the momentum
// it gave them and its moment about `about` (at their projected positions).
ContactImpulse project_particles(std::vector<Vec3>& x, std::vector<Vec3>& v, const double* mass, const Collider& collider,
                                 double t, const Vec3& about);

}  // namespace shellfrac::mpm
