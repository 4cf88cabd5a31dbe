#include "nurbs/patch_builders.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "nurbs/degree_elevation.hpp"
#include "nurbs/detail.hpp"
#include "nurbs/knot_insertion.hpp"
#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {

using detail::format_number;

namespace {

constexpr double kPi = 3.14159265358979323846;

void check_frame(const Frame& f, const std::string& who) {
  constexpr double tol = 1e-9;
  if (!f.origin.allFinite() || !f.axis_u.allFinite() || !f.axis_v.allFinite()) {
    throw NurbsError(who + ": frame origin and axes must be finite");
  }
  const double lu = f.axis_u.norm();
  const double lv = f.axis_v.norm();
  const double dot = f.axis_u.dot(f.axis_v);
  if (std::abs(lu - 1.0) > tol || std::abs(lv - 1.0) > tol || std::abs(dot) > tol) {
    throw NurbsError(who + ": frame axes must be orthonormal (within 1e-9), got |axis_u| = " + format_number(lu) +
                     ", |axis_v| = " + format_number(lv) + ", axis_u . axis_v = " + format_number(dot));
  }
}

void check_positive(double value, const std::string& who, const std::string& name) {
  if (!std::isfinite(value) || !(value > 0.0)) {
    throw NurbsError(who + ": " + name + " = " + format_number(value) + " is invalid; it must be finite and > 0");
  }
}

void check_cells(int cells, const std::string& who, const std::string& name) {
  if (cells < 1) throw NurbsError(who + ": " + name + " = " + std::to_string(cells) + " is invalid; it must be >= 1");
}

// Greville abscissa of quadratic basis function i on an open uniform knot vector with `cells` spans on
// [0, 1]: 0, 1/(2 cells), 3/(2 cells), ..., 1 (borders at half the cell spacing).
double quadratic_greville(int i, int cells) {
  if (i == 0) return 0.0;
  if (i == cells + 1) return 1.0;
  return static_cast<double>(2 * i - 1) / (2.0 * cells);
}

// Greville abscissa of basis function i of an open uniform knot vector on [0, 1] (the quadratic case in
// the closed form above, which earlier runs were computed with).
double greville(const KnotVector& k, int i, int cells) {
  return k.degree() == 2 ? quadratic_greville(i, cells) : k.greville(i);
}

void check_degree(int degree, int lowest, const std::string& who, const std::string& name) {
  if (degree < lowest || degree > 7)
    throw NurbsError(who + ": " + name + " = " + std::to_string(degree) + " is invalid; it must be in [" +
                     std::to_string(lowest) + ", 7]");
}

}  // namespace

NurbsSurface flat_patch(double size_u, double size_v, int cells_u, int cells_v, const Frame& frame, int degree_u,
                        int degree_v) {
  const std::string who = "flat patch";
  check_positive(size_u, who, "size_u");
  check_positive(size_v, who, "size_v");
  check_cells(cells_u, who, "cells_u");
  check_cells(cells_v, who, "cells_v");
  check_frame(frame, who);
  check_degree(degree_u, 1, who, "degree_u");
  check_degree(degree_v, 1, who, "degree_v");

  KnotVector ku = KnotVector::open_uniform(degree_u, cells_u);
  KnotVector kv = KnotVector::open_uniform(degree_v, cells_v);
  const int nu = ku.num_basis();
  const int nv = kv.num_basis();
  Vec3List points;
  points.reserve(static_cast<std::size_t>(nu * nv));
  for (int j = 0; j < nv; ++j) {
    const double t = greville(kv, j, cells_v) * size_v;
    for (int i = 0; i < nu; ++i) {
      const double s = greville(ku, i, cells_u) * size_u;
      points.push_back(frame.origin + s * frame.axis_u + t * frame.axis_v);
    }
  }
  std::vector<double> weights(points.size(), 1.0);
  return NurbsSurface(std::move(ku), std::move(kv), std::move(points), std::move(weights));
}

NurbsSurface cone_segment(double r0, double r1, double height, double sweep, int cells_u, int cells_v,
                          const Frame& frame, int degree_u, int degree_v) {
  const std::string who = "cone segment";
  if (!std::isfinite(r0) || !std::isfinite(r1) || r0 < 0.0 || r1 < 0.0 || (r0 == 0.0 && r1 == 0.0)) {
    throw NurbsError(who + ": radii r0 = " + format_number(r0) + ", r1 = " + format_number(r1) +
                     " are invalid; both must be finite and >= 0, and not both 0");
  }
  check_positive(height, who, "height");
  if (!std::isfinite(sweep) || !(sweep > 0.0) || sweep > 2.0 * kPi * (1.0 + 1e-12)) {
    throw NurbsError(who + ": sweep " + format_number(sweep) + " is invalid; it must satisfy 0 < sweep <= 2*pi (radians)");
  }
  check_cells(cells_v, who, "cells_v");
  check_frame(frame, who);
  check_degree(degree_u, 2, who, "degree_u");  // a circle needs a rational quadratic at least
  check_degree(degree_v, 1, who, "degree_v");

  // Unit arc in its own xy-plane, split into pieces of at most 90 degrees, at the requested degree.
  const NurbsCurve arc = degree_u == 2 ? circular_arc(1.0, 0.0, sweep) : elevate_degree(circular_arc(1.0, 0.0, sweep), degree_u - 2);
  const int pieces = arc.knots().num_spans();
  if (cells_u < pieces) {
    throw NurbsError(who + ": cells_u = " + std::to_string(cells_u) + " is too small; a sweep of " +
                     format_number(sweep) + " rad is built from " + std::to_string(pieces) +
                     " arc pieces and needs cells_u >= " + std::to_string(pieces));
  }
  // Split piece k (on [k/pieces, (k+1)/pieces]) into an as-even-as-possible share of cells_u spans.
  std::vector<double> extra;
  for (int k = 0; k < pieces; ++k) {
    const int share = cells_u / pieces + (k < cells_u % pieces ? 1 : 0);
    for (int m = 1; m < share; ++m) {
      extra.push_back((k + static_cast<double>(m) / share) / pieces);
    }
  }
  const NurbsCurve ring = insert_knots(arc, extra);

  // Circle point (x, y) maps to x axis_u + y (axis_v x axis_u), so du x dv points away from the axis.
  const Vec3 axis = frame.axis_v;
  const Vec3 side = frame.axis_v.cross(frame.axis_u);
  KnotVector kv = KnotVector::open_uniform(degree_v, cells_v);
  const int nu = ring.knots().num_basis();
  const int nv = kv.num_basis();
  Vec3List points;
  std::vector<double> weights;
  points.reserve(static_cast<std::size_t>(nu * nv));
  weights.reserve(static_cast<std::size_t>(nu * nv));
  for (int j = 0; j < nv; ++j) {
    // Rows at the Greville heights; radius and height linear in t, hence exact in v (linear precision).
    const double t = greville(kv, j, cells_v);
    const double radius = r0 + t * (r1 - r0);
    const Vec3 centre = frame.origin + (t * height) * axis;
    for (int i = 0; i < nu; ++i) {
      const Vec3& c = ring.control_points()[static_cast<std::size_t>(i)];
      points.push_back(centre + radius * (c.x() * frame.axis_u + c.y() * side));
      weights.push_back(ring.weights()[static_cast<std::size_t>(i)]);
    }
  }
  return NurbsSurface(ring.knots(), std::move(kv), std::move(points), std::move(weights));
}

}  // namespace shellfrac::nurbs
