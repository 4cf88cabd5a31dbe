#pragma once
// The error base of shellfrac: every error the library throws on purpose derives from core::Error and
// knows the exit code a command should end with (apps map every exception through exit_code_for()).
#include <stdexcept>
#include <string>

#include "core/exit_code.hpp"

namespace shellfrac::core {

class Error : public std::runtime_error {
 public:
  Error(const std::string& what, ExitCode code) : std::runtime_error(what), code_(code) {}
  ExitCode exit_code() const { return code_; }

 private:
  ExitCode code_;
};

// Bad user input: the message names the file or option and what is allowed (exit code 2).
class InputError : public Error {
 public:
  explicit InputError(const std::string& what) : Error(what, ExitCode::bad_input) {}
};

// A numerical failure at run time (NaN, blow-up, stability violation), naming the particle, body and
// step where it started (exit code 3).
// Where a numerical failure started, as fields (the message says the same in words): for callers that
// report or react to it (the Python module's NumericalError attributes). Unknown fields keep their defaults.
struct NumericalLocation {
  std::string body;           // shell or solid name ("" when unknown)
  std::string body_kind;      // "shell" or "solid"
  std::string particle_kind;  // "control point", "shear particle", "quadrature point", "solid particle"
  long particle = -1;         // index within its body and kind, -1 when unknown
  long step = -1;             // steps completed before the failing one, -1 when unknown
  double time = 0;            // simulated time [s] at the start of the failing step
};

class NumericalError : public Error {
 public:
  explicit NumericalError(const std::string& what) : Error(what, ExitCode::numerical) {}
  NumericalError(const std::string& what, NumericalLocation where)
      : Error(what, ExitCode::numerical), where_(std::move(where)) {}
  const NumericalLocation& where() const { return where_; }

 private:
  NumericalLocation where_;
};

// The exit code for any exception: the code of a core::Error, else ExitCode::other.
inline ExitCode exit_code_for(const std::exception& e) {
  if (const auto* err = dynamic_cast<const Error*>(&e)) return err->exit_code();
  return ExitCode::other;
}

}  // namespace shellfrac::core
