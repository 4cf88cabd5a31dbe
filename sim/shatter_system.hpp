#pragma once
// The shatter loop of a running scene (docs/brittle.md, "The shatter loop"): the brittle solids with
// "rigid_body" and the projectiles in one rigid-body world, advanced to the simulation's time by the
// "rigid" stage; fracture events happen inside it. No I/O here.
#include <memory>

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

 private:
  std::unique_ptr<shatter::ShatterLoop> loop_;
};

}  // namespace shellfrac::sim
