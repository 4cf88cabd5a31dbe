#include "rigid/frames.hpp"

#include <Eigen/Eigenvalues>

namespace shellfrac::rigid {

Pose Pose::inverse() const {
  Pose p;
  p.rotation = rotation.conjugate();
  p.translation = -(p.rotation * translation);
  return p;
}

Pose Pose::operator*(const Pose& inner) const {
  Pose p;
  p.rotation = (rotation * inner.rotation).normalized();
  p.translation = rotation * inner.translation + translation;
  return p;
}

PrincipalFrame principal_frame(const brittle::MassProperties& properties) {
  const Eigen::SelfAdjointEigenSolver<Mat3> eig(0.5 * (properties.inertia + properties.inertia.transpose()));
  Mat3 axes = eig.eigenvectors();
  if (axes.determinant() < 0) axes.col(2) = -axes.col(2);  // a rotation, not a reflection
  PrincipalFrame f;
  f.body_to_material.rotation = Quat(axes).normalized();
  f.body_to_material.translation = properties.centroid;
  f.moments = eig.eigenvalues().cwiseMax(0.0);
  return f;
}

brittle::TriMesh transformed(const brittle::TriMesh& mesh, const Pose& pose) {
  brittle::TriMesh out = mesh;
  for (Vec3& x : out.positions) x = pose.apply(x);
  for (Vec3& n : out.normals) n = pose.rotate(n);
  return out;
}

}  // namespace shellfrac::rigid
