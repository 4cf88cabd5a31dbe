#include "scene/range.hpp"

#include <cmath>

#include "core/format.hpp"

namespace shellfrac::scene {

std::string format_value(double v) { return core::format_number(v, 10); }

bool Range::contains(double v) const {
  if (!std::isfinite(v)) return false;
  const bool lo_ok = lo_open ? v > lo : v >= lo;
  const bool hi_ok = hi_open ? v < hi : v <= hi;
  return lo_ok && hi_ok;
}

std::string Range::describe() const {
  const bool no_lo = lo <= -1e307, no_hi = hi >= 1e307;
  if (no_lo && no_hi) return "a finite number";
  if (no_hi) return std::string(lo_open ? "> " : ">= ") + format_value(lo);
  if (no_lo) return std::string(hi_open ? "< " : "<= ") + format_value(hi);
  return std::string("in ") + (lo_open ? "(" : "[") + format_value(lo) + ", " + format_value(hi) + (hi_open ? ")" : "]");
}

std::string Range::violation(double v) const {
  return "value " + format_value(v) + " is out of range: must be " + describe();
}

}  // namespace shellfrac::scene
