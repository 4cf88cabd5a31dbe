#pragma once
// Rigid frames: a pose (rotation and translation) and the principal frame of a solid's mass properties,
// where a rigid-body engine wants a body's origin (its centre of mass) and axes (its principal axes).
#include <Eigen/Core>
#include <Eigen/Geometry>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::rigid {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// x_out = rotation * x_in + translation.
struct Pose {
  Quat rotation = Quat::Identity();
  Vec3 translation = Vec3::Zero();

  Vec3 apply(const Vec3& x) const { return rotation * x + translation; }
  Vec3 rotate(const Vec3& d) const { return rotation * d; }
  Pose inverse() const;
  Pose operator*(const Pose& inner) const;  // (this * inner)(x) = this(inner(x))
};

// A body frame for a solid: origin at the centre of mass, axes along the principal axes of inertia
// (right-handed), with the principal moments in that order.
struct PrincipalFrame {
  Pose body_to_material;  // maps body coordinates to the mesh's (material) coordinates
  Vec3 moments = Vec3::Zero();
};
PrincipalFrame principal_frame(const brittle::MassProperties& properties);

// The mesh with its positions (and normals) moved by a pose.
brittle::TriMesh transformed(const brittle::TriMesh& mesh, const Pose& pose);

}  // namespace shellfrac::rigid
