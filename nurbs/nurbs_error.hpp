#pragma once
#include <stdexcept>
#include <string>

namespace shellfrac::nurbs {

// Thrown for invalid NURBS input (knot vectors, control nets, weights, parameters outside the domain).
// The message says what was wrong and what is allowed; callers that know a file/JSON path prefix it.
class NurbsError : public std::invalid_argument {
 public:
  explicit NurbsError(const std::string& what) : std::invalid_argument(what) {}
};

}  // namespace shellfrac::nurbs
