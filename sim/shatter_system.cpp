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
  for (const shatter::ProjectileSpec& p : model.rigid->projectiles) loop_->add_projectile(p);
  for (const shatter::PropSpec& p : model.rigid->props) loop_->add_prop(p);
}

void ShatterSystem::advance_to(double t) {
  if (loop_) loop_->advance_to(t);
}

}  // namespace shellfrac::sim
