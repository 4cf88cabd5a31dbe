#pragma once
// The brittle solids of a running scene (thesis ch. 3): one BrittleSolver per solid with a "fracture"
// object, each on its own dense MLS-MPM grid and with its own time step, advanced to the simulation's time
// by the "brittle" stage. When a solid's fracture run meets its stopping criterion, its fracture event is
// computed (crack surface, regions, fragments) and kept for the output layer; the solid then rests (the
// rigid-body loop of the fragments is part 2 of the brittle work). No I/O here.
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brittle/fracture_event.hpp"
#include "brittle/solver.hpp"
#include "scene/model.hpp"

namespace shellfrac::sim {

class BrittleSystem {
 public:
  struct Body {
    const scene::model::BrittleBody* spec = nullptr;
    std::unique_ptr<brittle::BrittleSolid> solid;  // the solver holds a reference: never moved
    std::unique_ptr<brittle::BrittleSolver> solver;
    size_t crack_updates = 0;
    std::optional<brittle::FractureEvent> event;  // set once the run stopped
    double event_time = 0;                        // the solver's time when it stopped [s]
  };

  // The solids' particles are copied from the model; colliders are the scene's.
  explicit BrittleSystem(const scene::Model& model);

  bool empty() const { return bodies_.empty(); }
  size_t size() const { return bodies_.size(); }
  const Body& body(size_t i) const { return bodies_[i]; }
  // True once every brittle solid has stopped and has its fracture event.
  bool done() const;
  size_t num_particles() const;

  // Steps every running solid until its own time reaches t (each step at the solver's stable dt), extracting
  // the crack for the two velocity fields every crack_interval steps; a solid that meets its stopping
  // criterion gets its fracture event. Throws core::NumericalError naming the solid and step.
  void advance_to(double t);
  // Computes the fracture event of every solid still running (the scene ended before its criterion).
  void finish_running();

 private:
  void finish(Body& b);
  std::vector<Body> bodies_;
};

}  // namespace shellfrac::sim
