#pragma once
#include <cstdio>
#include <string>

namespace shellfrac::coupling {

// A double for error messages: enough digits to tell measured values from tolerances.
inline std::string format_number(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.6g", x);
  return buf;
}

}  // namespace shellfrac::coupling
