#include "sim/brittle_system.hpp"

#include "core/error.hpp"

namespace shellfrac::sim {

BrittleSystem::BrittleSystem(const scene::Model& model) {
  for (const scene::model::BrittleBody& spec : model.brittle_solids) {
    if (spec.rigid) continue;  // carried by the shatter loop (ShatterSystem)
    Body b;
    b.spec = &spec;
    b.solid = std::make_unique<brittle::BrittleSolid>(*spec.solid);
    brittle::SolverOptions options = spec.solver;
    options.gravity = model.gravity;
    b.solver = std::make_unique<brittle::BrittleSolver>(*b.solid, options);
    for (const scene::model::ColliderSpec& c : model.colliders) b.solver->add_collider(c.collider);
    if (!spec.ghosts.empty()) b.solver->add_ghosts(spec.ghosts);
    bodies_.push_back(std::move(b));
  }
}

bool BrittleSystem::done() const {
  for (const Body& b : bodies_)
    if (!b.event) return false;
  return true;
}

size_t BrittleSystem::num_particles() const {
  size_t n = 0;
  for (const Body& b : bodies_) n += b.solid->size();
  return n;
}

void BrittleSystem::advance_to(double t) {
  for (Body& b : bodies_) {
    if (b.event) continue;
    brittle::BrittleSolver& s = *b.solver;
    const size_t interval = static_cast<size_t>(b.spec->crack_interval);
    try {
      while (s.time() < t && !s.should_stop()) {
        s.step();
        // thesis sec. 3.8 extracts every ten steps; the interval is the scene's
        if (b.spec->solver.two_fields && s.steps() % interval == 0 && s.damaged_count() > 0) {
          s.update_crack(b.spec->event.crack);
          ++b.crack_updates;
        }
      }
    } catch (const core::NumericalError& e) {
      throw core::NumericalError("brittle solid \"" + b.spec->name + "\" (" + b.spec->json_path + "): " + e.what());
    }
    if (s.should_stop()) finish(b);
  }
}

void BrittleSystem::finish_running() {
  for (Body& b : bodies_)
    if (!b.event) finish(b);
}

void BrittleSystem::finish(Body& b) {
  b.event_time = b.solver->time();
  try {
    b.event = brittle::fracture_event(*b.solid, b.spec->mesh, b.spec->event, b.spec->name);
  } catch (const core::Error& e) {
    throw core::NumericalError("fracture event of brittle solid \"" + b.spec->name + "\" at t = " +
                               std::to_string(b.event_time) + " s: " + e.what());
  }
}

}  // namespace shellfrac::sim
