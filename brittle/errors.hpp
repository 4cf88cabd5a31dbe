#pragma once
#include <stdexcept>
#include <string>

namespace shellfrac::brittle {

// Bad user input for the brittle path (a mesh that is not closed, an impact outside the object, a voxel
// size too small for memory, ...). The message names the file or scene key and the reason; the run
// driver maps it to the bad-input exit code. Derives from std::invalid_argument so generic handlers
// that already catch that keep working.
class InputError : public std::invalid_argument {
 public:
  explicit InputError(const std::string& what) : std::invalid_argument(what) {}
};

// A numerical failure inside the brittle solver or the crack/fragment pipeline (inverted particle,
// failed Voronoi cell, boolean that did not close). The message names the particle, site or fragment.
class NumericalError : public std::runtime_error {
 public:
  explicit NumericalError(const std::string& what) : std::runtime_error(what) {}
};

}  // namespace shellfrac::brittle
