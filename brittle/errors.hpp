#pragma once
// The brittle layer throws the project's error classes (core/error.hpp): InputError for bad user input
// (exit code 2; the message names the file or scene key), NumericalError for a failure inside the solver
// or the crack/fragment pipeline (exit code 3; the message names the particle, site or fragment).
#include "core/error.hpp"

namespace shellfrac::brittle {

using core::InputError;
using core::NumericalError;

}  // namespace shellfrac::brittle
