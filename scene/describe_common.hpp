#pragma once
// What every part of the scene format's declarations (scene/describe.hpp) shares: whether a key is
// required, common ranges and small checks.
#include <cmath>
#include <string>

#include "scene/range.hpp"
#include "scene/scene.hpp"

namespace shellfrac::scene {

enum class Need { optional, required };
constexpr Need kRequired = Need::required;
constexpr Need kOptional = Need::optional;

inline const Range kCells = Range::closed(1, 10000);

// Error message when `format` is not an export format (lists the allowed ones), or "".
std::string export_format_problem(const std::string& format);

namespace detail {
inline double norm3(const Vec3& v) { return std::sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2]); }
inline std::string nonzero_direction(const Opt<Vec3>& v) {
  return v && norm3(*v) < 1e-12 ? "direction must be a non-zero vector" : "";
}
}  // namespace detail

}  // namespace shellfrac::scene
