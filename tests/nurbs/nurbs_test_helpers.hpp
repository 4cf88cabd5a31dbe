#pragma once
// Helpers shared by the NURBS tests.
#include <gtest/gtest.h>

#include <string>

#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {

// Runs `f`, expects a NurbsError and returns its message (empty, with a test failure, if none was thrown).
template <class F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const NurbsError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected NurbsError";
  return {};
}

}  // namespace shellfrac::nurbs
