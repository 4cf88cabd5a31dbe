#pragma once
// Helpers shared by the coupling tests: patch layouts, curve comparison, random displacements.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <string>
#include <vector>

#include "coupling/edge.hpp"
#include "nurbs/patch_builders.hpp"

namespace shellfrac::coupling::test {

using nurbs::Vec3List;

constexpr double kPi = 3.14159265358979323846;

// Runs `f`, expects a std::invalid_argument and returns its message.
template <class F>
std::string error_message(F&& f) {
  try {
    f();
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected std::invalid_argument";
  return {};
}

// A flat polynomial patch of any degrees with control points at the Greville abscissae (an exactly
// linear parameterisation): size_u x size_v, placed by `frame`.
inline nurbs::NurbsSurface flat_patch_general(const nurbs::KnotVector& ku, const nurbs::KnotVector& kv,
                                              double size_u, double size_v, const nurbs::Frame& frame) {
  Vec3List points;
  for (int j = 0; j < kv.num_basis(); ++j) {
    for (int i = 0; i < ku.num_basis(); ++i) {
      points.push_back(frame.origin + size_u * ku.greville(i) * frame.axis_u + size_v * kv.greville(j) * frame.axis_v);
    }
  }
  std::vector<double> w(points.size(), 1.0);
  return nurbs::NurbsSurface(ku, kv, std::move(points), std::move(w));
}

inline nurbs::Frame frame_at(const Vec3& origin, const Vec3& axis_u = Vec3::UnitX(), const Vec3& axis_v = Vec3::UnitY()) {
  nurbs::Frame f;
  f.origin = origin;
  f.axis_u = axis_u;
  f.axis_v = axis_v;
  return f;
}

// A copy of `s` with new control points (same knots and weights).
inline nurbs::NurbsSurface with_points(const nurbs::NurbsSurface& s, Vec3List points) {
  return nurbs::NurbsSurface(s.knots_u(), s.knots_v(), std::move(points), s.weights());
}

// Max distance between curve a at t and curve b at the matching parameter (affine map of the domains,
// reversed if asked), over `samples` uniform parameters of a.
inline double parametric_gap(const nurbs::NurbsCurve& a, const nurbs::NurbsCurve& b, bool reversed,
                             int samples = 200) {
  const double a0 = a.knots().domain_begin(), a1 = a.knots().domain_end();
  const double b0 = b.knots().domain_begin(), b1 = b.knots().domain_end();
  double worst = 0.0;
  for (int k = 0; k < samples; ++k) {
    const double f = static_cast<double>(k) / (samples - 1);
    const double g = reversed ? 1.0 - f : f;
    worst = std::max(worst, (a.point(a0 + f * (a1 - a0)) - b.point(b0 + g * (b1 - b0))).norm());
  }
  return worst;
}

// Uniform random vector in [-amplitude, amplitude]^3.
inline Vec3 random_vec(std::mt19937& rng, double amplitude) {
  std::uniform_real_distribution<double> d(-amplitude, amplitude);
  const double x = d(rng), y = d(rng), z = d(rng);
  return Vec3(x, y, z);
}

}  // namespace shellfrac::coupling::test
