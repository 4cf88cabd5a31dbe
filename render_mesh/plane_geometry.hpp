#pragma once
// Small parameter-plane helpers shared by the cracked tessellation's steps.
#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh::detail {

inline constexpr double kTwoPi = 6.283185307179586476925286766559;
// z component of the 2D cross product: > 0 when b is counter-clockwise from a.
inline double cross2(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace shellfrac::render_mesh::detail
