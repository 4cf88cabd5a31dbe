#include "mpm/colliders.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {

namespace {

Eigen::Matrix3d rotation_matrix(const Vec3& rotation_vector) {
  const double angle = rotation_vector.norm();
  if (angle < 1e-300) return Eigen::Matrix3d::Identity();
  return Eigen::AngleAxisd(angle, rotation_vector / angle).toRotationMatrix();
}

}  // namespace

Eigen::Isometry3d RigidMotion::pose(double t) const {
  Vec3 translation, rotation;
  if (keyframes.empty()) {
    translation = linear_velocity * t;
    rotation = angular_velocity * t;
  } else if (t <= keyframes.front().time) {
    translation = keyframes.front().translation;
    rotation = keyframes.front().rotation;
  } else if (t >= keyframes.back().time) {
    translation = keyframes.back().translation;
    rotation = keyframes.back().rotation;
  } else {
    const auto hi = std::upper_bound(keyframes.begin(), keyframes.end(), t,
                                     [](double v, const Keyframe& k) { return v < k.time; });
    const auto lo = hi - 1;
    const double s = (t - lo->time) / (hi->time - lo->time);
    translation = (1 - s) * lo->translation + s * hi->translation;
    rotation = (1 - s) * lo->rotation + s * hi->rotation;
  }
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = rotation_matrix(rotation);
  T.translation() = pivot + translation - T.linear() * pivot;
  return T;
}

Vec3 RigidMotion::velocity_at(const Vec3& x, double t) const {
  if (keyframes.empty()) {
    const Vec3 centre = pivot + linear_velocity * t;
    return linear_velocity + angular_velocity.cross(x - centre);
  }
  // Keyframed: finite difference of the pose over a short interval (exact for linear segments).
  const double h = 1e-6;
  const Eigen::Isometry3d a = pose(t), b = pose(t + h);
  return (b * (a.inverse() * x) - x) / h;
}

Vec3 Sphere::normal(const Vec3& x) const {
  const Vec3 d = x - center_;
  const double n = d.norm();
  return n > 0 ? Vec3(d / n) : Vec3::UnitZ();
}

double Box::signed_distance(const Vec3& x) const {
  const Vec3 q = (x - center_).cwiseAbs() - half_;
  const double outside = q.cwiseMax(0.0).norm();
  const double inside = std::min(q.maxCoeff(), 0.0);
  return outside + inside;
}

Vec3 Box::normal(const Vec3& x) const {
  const Vec3 d = x - center_;
  const Vec3 q = d.cwiseAbs() - half_;
  if (q.maxCoeff() > 0) {  // outside: gradient of the distance to the nearest box point
    const Vec3 g = q.cwiseMax(0.0).cwiseProduct(d.cwiseSign());
    return g.normalized();
  }
  int axis;  // inside: the face closest to x
  q.maxCoeff(&axis);
  Vec3 n = Vec3::Zero();
  n[axis] = d[axis] >= 0 ? 1.0 : -1.0;
  return n;
}

double Collider::signed_distance(const Vec3& x, double t) const {
  return shape->signed_distance(motion.pose(t).inverse() * x);
}

Vec3 Collider::normal(const Vec3& x, double t) const {
  const Eigen::Isometry3d T = motion.pose(t);
  return T.linear() * shape->normal(T.inverse() * x);
}

Vec3 collide_velocity(const Vec3& v, const Vec3& vc, const Vec3& n, Boundary boundary, double friction) {
  if (boundary == Boundary::Sticky) return vc;
  const Vec3 rel = v - vc;
  const double vn = rel.dot(n);
  if (vn >= 0) return v;  // separating: no constraint
  Vec3 vt = rel - vn * n;
  if (boundary == Boundary::Friction) {
    const double t = vt.norm();
    // Coulomb: the tangential speed drops by mu times the removed normal speed, not below zero.
    vt = t > friction * -vn ? Vec3(vt * (1.0 + friction * vn / t)) : Vec3::Zero();
  }
  return vc + vt;
}

void apply_colliders(SparseGrid& grid, const std::vector<Collider>& colliders, double t) {
  if (colliders.empty()) return;
  std::vector<Eigen::Isometry3d> inverse_pose;
  for (const Collider& c : colliders) inverse_pose.push_back(c.motion.pose(t).inverse());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, grid.num_nodes(), 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t n = r.begin(); n != r.end(); ++n) {
      if (grid.node_mass(n) <= 0) continue;
      const Vec3 x = grid.node_position(n);
      for (size_t c = 0; c < colliders.size(); ++c) {
        const Collider& col = colliders[c];
        const Vec3 local = inverse_pose[c] * x;
        if (col.shape->signed_distance(local) > 0) continue;
        const Vec3 normal = inverse_pose[c].linear().transpose() * col.shape->normal(local);
        grid.node_velocity(n) = collide_velocity(grid.node_velocity(n), col.motion.velocity_at(x, t), normal,
                                                 col.boundary, col.friction);
      }
    }
  });
}

void project_particles(std::vector<Vec3>& x, std::vector<Vec3>& v, const std::vector<Collider>& colliders, double t) {
  if (colliders.empty()) return;
  std::vector<Eigen::Isometry3d> pose, inverse_pose;
  for (const Collider& c : colliders) {
    pose.push_back(c.motion.pose(t));
    inverse_pose.push_back(pose.back().inverse());
  }
  tbb::parallel_for(tbb::blocked_range<size_t>(0, x.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p != r.end(); ++p) {
      for (size_t c = 0; c < colliders.size(); ++c) {
        const Collider& col = colliders[c];
        const Vec3 local = inverse_pose[c] * x[p];
        const double phi = col.shape->signed_distance(local);
        if (phi >= 0) continue;
        const Vec3 normal = pose[c].linear() * col.shape->normal(local);
        x[p] -= phi * normal;
        v[p] = collide_velocity(v[p], col.motion.velocity_at(x[p], t), normal, col.boundary, col.friction);
      }
    }
  });
}

namespace {

// Sums f(i) over [0, n) in fixed ranges of `grain` in parallel, then the ranges in order.
template <class F>
ContactImpulse ordered_sum(size_t n, size_t grain, F f) {
  std::vector<ContactImpulse> part((n + grain - 1) / grain);
  tbb::parallel_for(size_t{0}, part.size(), [&](size_t r) {
    for (size_t i = r * grain; i < std::min(n, (r + 1) * grain); ++i) part[r] += f(i);
  });
  ContactImpulse total;
  for (const ContactImpulse& c : part) total += c;
  return total;
}

}  // namespace

ContactImpulse apply_collider(SparseGrid& grid, const Collider& col, double t, const Vec3& about) {
  const Eigen::Isometry3d inverse_pose = col.motion.pose(t).inverse();
  return ordered_sum(grid.num_nodes(), 512, [&](size_t n) {
    ContactImpulse out;
    const double m = grid.node_mass(n);
    if (m <= 0) return out;
    const Vec3 x = grid.node_position(n);
    const Vec3 local = inverse_pose * x;
    if (col.shape->signed_distance(local) > 0) return out;
    const Vec3 normal = inverse_pose.linear().transpose() * col.shape->normal(local);
    const Vec3 before = grid.node_velocity(n);
    grid.node_velocity(n) = collide_velocity(before, col.motion.velocity_at(x, t), normal, col.boundary, col.friction);
    out.linear = m * (grid.node_velocity(n) - before);
    out.angular = (x - about).cross(out.linear);
    return out;
  });
}

ContactImpulse project_particles(std::vector<Vec3>& x, std::vector<Vec3>& v, const double* mass, const Collider& col,
                                 double t, const Vec3& about) {
  const Eigen::Isometry3d pose = col.motion.pose(t), inverse_pose = pose.inverse();
  return ordered_sum(x.size(), 256, [&](size_t p) {
    ContactImpulse out;
    const Vec3 local = inverse_pose * x[p];
    const double phi = col.shape->signed_distance(local);
    if (phi >= 0) return out;
    const Vec3 normal = pose.linear() * col.shape->normal(local);
    x[p] -= phi * normal;
    const Vec3 before = v[p];
    v[p] = collide_velocity(before, col.motion.velocity_at(x[p], t), normal, col.boundary, col.friction);
    out.linear = mass[p] * (v[p] - before);
    out.angular = (x[p] - about).cross(out.linear);
    return out;
  });
}

}  // namespace shellfrac::mpm
