#include "shatter/fragment_spawn.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "rigid/collision_mesh.hpp"

namespace shellfrac::shatter {

SpawnedFragment rigid_piece(const brittle::TriMesh& mesh, const brittle::MassProperties& properties,
                            const rigid::Pose& world_from_material, const rigid::Vec3& centre,
                            const rigid::Vec3& velocity, const rigid::Vec3& angular_velocity, double root_volume,
                            const SpawnSettings& settings, const std::string& name) {
  SpawnedFragment out;
  out.volume_ratio = properties.volume / root_volume;
  out.fragment_class = classify(out.volume_ratio, settings.ratios);
  const rigid::PrincipalFrame frame = rigid::principal_frame(properties);
  out.material_to_body = frame.body_to_material.inverse();

  rigid::BodyDesc& b = out.body;
  b.name = name;
  b.mass = properties.mass;
  b.inertia = frame.moments;
  b.pose = world_from_material * frame.body_to_material;
  // thesis sec. 3.6.1: a fragment inherits the parent's rigid velocity field at its own centre of mass
  b.velocity = velocity + angular_velocity.cross(b.pose.translation - centre);
  b.angular_velocity = angular_velocity;
  b.surface = settings.surface;
  b.margin = std::min(settings.margin, 0.1 * std::cbrt(properties.volume));

  const brittle::TriMesh local = rigid::transformed(mesh, out.material_to_body);
  if (out.fragment_class == FragmentClass::Tiny) {
    b.shape = rigid::Shape::ConvexHull;
    b.mesh = rigid::decimate(local, std::numeric_limits<size_t>::max()).mesh;  // welded; the hull needs no faces
  } else {
    b.mesh = rigid::decimate(local, settings.collision_faces).mesh;
    b.shape = rigid::hull_volume_ratio(b.mesh) <= 1 + settings.convex_tolerance ? rigid::Shape::ConvexHull
                                                                               : rigid::Shape::ConcaveMesh;
  }
  return out;
}

RigidMoments rigid_moments(const std::vector<double>& masses, const std::vector<rigid::Vec3>& moments,
                           const std::vector<rigid::BodyState>& states) {
  RigidMoments m;
  for (size_t i = 0; i < masses.size(); ++i) {
    m.mass += masses[i];
    m.centre += masses[i] * states[i].pose.translation;
    m.momentum += masses[i] * states[i].velocity;
  }
  m.centre /= m.mass;
  for (size_t i = 0; i < masses.size(); ++i) {
    const rigid::BodyState& s = states[i];
    const rigid::Mat3 R = s.pose.rotation.toRotationMatrix();
    const rigid::Mat3 inertia = R * moments[i].asDiagonal() * R.transpose();  // world axes
    const rigid::Vec3 spin = inertia * s.angular_velocity;
    m.angular_momentum += spin + masses[i] * (s.pose.translation - m.centre).cross(s.velocity);
    m.kinetic_energy += 0.5 * masses[i] * s.velocity.squaredNorm() + 0.5 * s.angular_velocity.dot(spin);
  }
  return m;
}

}  // namespace shellfrac::shatter
