#pragma once
// The rigid-body world of a running scene (docs/brittle.md, "The shatter loop"): the brittle solids with
// "rigid_body" and the projectiles in one rigid-body world, advanced to the simulation's time by the
// "rigid" stage; fracture events happen inside it. Projectiles also strike the MPM material (shells and
// solids) two ways (thesis sec. 4.10.7): each is a moving sphere collider on the grid and the particles,
// and the momentum it gives the material is taken from it before the rigid world steps on. No I/O here.
#include <memory>
#include <utility>
#include <vector>

#include "mpm/colliders.hpp"
#include "scene/model.hpp"
#include "shatter/shatter_loop.hpp"

namespace shellfrac::sim {

class ShatterSystem {
 public:
  explicit ShatterSystem(const scene::Model& model);
  bool empty() const { return !loop_; }
  // Rigid steps (at the scene's rigid dt) until the loop reaches t.
  void advance_to(double t);
  const shatter::ShatterLoop& loop() const { return *loop_; }
  void set_event_observer(shatter::EventObserver observer) {
    if (loop_) loop_->set_event_observer(std::move(observer));
  }

  // Projectiles as colliders of the MPM grid at time t: the sphere where the rigid world last put it,
  // moved on at its current velocity to t, as a collider whose pose is the identity at time 0 (pass
  // t = 0 to mpm::apply_collider). Slots of projectiles that left the world are null.
  size_t num_strikers() const { return strikers_.size(); }
  const mpm::Collider* striker(size_t k, double t);
  Eigen::Vector3d striker_centre(size_t k) const { return strikers_[k].centre; }
  // Momentum projectile k gave the MPM material in this step; taken from it by take_contacts().
  void add_contact(size_t k, const mpm::ContactImpulse& impulse) { strikers_[k].pending += impulse; }
  // Every projectile loses the momentum and angular momentum (about its centre) it gave the material
  // this step (kinematic ones move on regardless).
  void take_contacts();
  // Total momentum projectile k has given the MPM material.
  const mpm::ContactImpulse& contact_total(size_t k) const { return strikers_[k].total; }

 private:
  struct Striker {
    size_t piece = 0;  // in loop().pieces()
    double radius = 0;
    mpm::Boundary boundary = mpm::Boundary::Friction;
    double friction = 0;
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();  // at the time of the last striker() call
    mpm::Collider collider;
    mpm::ContactImpulse pending, total;
  };
  std::unique_ptr<shatter::ShatterLoop> loop_;
  std::vector<Striker> strikers_;
};

}  // namespace shellfrac::sim
