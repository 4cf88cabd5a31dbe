#pragma once
#include <stdexcept>
#include <string>

namespace shellfrac::coupling {

// Thrown when two patch edges cannot be coupled (mismatched degrees, non-coincident or differently
// parameterised edges, unclamped knot vectors). The message names the patches, sides and measured values.
class CouplingError : public std::invalid_argument {
 public:
  explicit CouplingError(const std::string& what) : std::invalid_argument(what) {}
};

}  // namespace shellfrac::coupling
