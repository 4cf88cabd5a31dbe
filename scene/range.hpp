#pragma once
#include <string>

namespace shellfrac::scene {

// Allowed interval for a number, with the wording used in error messages ("> 0", "in (-1, 0.5)").
struct Range {
  double lo = -1e308, hi = 1e308;
  bool lo_open = false, hi_open = false;

  static Range any() { return {}; }
  static Range positive() { return {0.0, 1e308, true, false}; }
  static Range non_negative() { return {0.0, 1e308, false, false}; }
  static Range at_least(double v) { return {v, 1e308, false, false}; }
  static Range open(double a, double b) { return {a, b, true, true}; }
  static Range closed(double a, double b) { return {a, b, false, false}; }
  static Range left_open(double a, double b) { return {a, b, true, false}; }

  bool contains(double v) const;
  std::string describe() const;
  // "value 0.7 is out of range: must be in (-1, 0.5)"
  std::string violation(double v) const;
};

// Numbers in messages: 10 significant digits.
std::string format_value(double v);

}  // namespace shellfrac::scene
