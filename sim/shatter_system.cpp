#include "sim/shatter_system.hpp"

namespace shellfrac::sim {

ShatterSystem::ShatterSystem(const scene::Model& model) {
  if (!model.rigid) return;
  loop_ = std::make_unique<shatter::ShatterLoop>(model.rigid->options);
  for (const scene::model::BrittleBody& b : model.brittle_solids) {
    if (!b.rigid) continue;
    const scene::model::BrittleBody::Rigid& r = *b.rigid;
    shatter::BreakableSpec s;
    s.name = b.name;
    s.mesh = b.mesh;
    s.particles = b.solid;
    s.sampling = r.sampling;
    s.seed = r.seed;
    s.strength_regions = r.strength_regions;
    s.weibull = r.weibull;
    s.solver = b.solver;
    s.crack_interval = b.crack_interval;
    s.event = b.event;
    s.contact_times = r.contact_times;
    s.impulse_threshold = r.impulse_threshold;
    s.impact_radius = r.impact_radius;
    s.velocity = r.velocity;
    s.angular_velocity = r.angular_velocity;
    s.spawn.ratios = model.rigid->ratios;
    s.spawn.collision_faces = r.collision_faces;
    s.spawn.surface = r.surface;
    loop_->add_breakable(s);
  }
  for (const shatter::ProjectileSpec& p : model.rigid->projectiles) {
    loop_->add_projectile(p);
    if (model.shells.empty() && model.solids.empty()) continue;  // nothing of MPM's to strike
    Striker s;
    s.piece = loop_->pieces().size() - 1;
    s.radius = p.radius;
    s.friction = p.surface.friction;
    s.boundary = s.friction > 0 ? mpm::Boundary::Friction : mpm::Boundary::Slip;
    strikers_.push_back(s);
  }
  for (const shatter::PropSpec& p : model.rigid->props) loop_->add_prop(p);
}

void ShatterSystem::advance_to(double t) {
  if (loop_) loop_->advance_to(t);
}

const mpm::Collider* ShatterSystem::striker(size_t k, double t) {
  Striker& s = strikers_[k];
  if (!loop_->alive(s.piece)) return nullptr;
  const rigid::BodyState b = loop_->world().state(loop_->pieces()[s.piece].body);
  s.centre = b.pose.translation + (t - loop_->time()) * b.velocity;
  s.collider.shape = std::make_shared<mpm::Sphere>(s.centre, s.radius);
  s.collider.motion = mpm::RigidMotion{};
  s.collider.motion.pivot = s.centre;
  s.collider.motion.linear_velocity = b.velocity;
  s.collider.motion.angular_velocity = b.angular_velocity;
  s.collider.boundary = s.boundary;
  s.collider.friction = s.friction;
  return &s.collider;
}

void ShatterSystem::take_contacts() {
  for (Striker& s : strikers_) {
    if (!loop_->alive(s.piece) || (s.pending.linear.isZero(0) && s.pending.angular.isZero(0))) {
      s.pending = mpm::ContactImpulse{};
      continue;
    }
    rigid::RigidWorld& w = loop_->world();
    const int id = loop_->pieces()[s.piece].body;
    const double m = w.mass(id);
    if (m > 0) {  // a kinematic projectile (mass 0 here) moves on regardless
      const rigid::BodyState b = w.state(id);
      // A sphere's inertia is isotropic: the angular impulse about its centre divides by one moment.
      const double inertia = w.principal_inertia(id).x();
      // The moment was taken about the sphere's centre at the time of contact: its centre of mass.
      w.set_velocity(id, b.velocity - s.pending.linear / m, b.angular_velocity - s.pending.angular / inertia);
    }
    s.total += s.pending;
    s.pending = mpm::ContactImpulse{};
  }
}

}  // namespace shellfrac::sim
