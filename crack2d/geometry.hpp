#pragma once
// Planar primitives and robust predicates for the crack graph in a patch's parameter plane.
//
// Orientation uses a floating-point filter with an exact fallback (error-free transformations:
// two_diff / fma-based two_product / expansion growth), so its sign is exact for all finite doubles
// whose products do not underflow. Everything built on it (segment crossing, segment-box overlap) is
// therefore exact as well: touching and collinear overlap are decided without tolerance.
#include <Eigen/Core>

#include <algorithm>
#include <cmath>

namespace shellfrac::crack2d {

using Point = Eigen::Vector2d;
struct Segment {
  Point a, b;
};
struct Box {  // axis-aligned, closed
  Point lo, hi;
};

namespace detail {

inline void two_sum(double a, double b, double& x, double& y) {
  x = a + b;
  const double bv = x - a;
  const double av = x - bv;
  y = (a - av) + (b - bv);
}

inline void two_diff(double a, double b, double& x, double& y) {
  x = a - b;
  const double bv = a - x;
  const double av = x + bv;
  y = (a - av) + (bv - b);
}

inline void two_product(double a, double b, double& x, double& y) {
  x = a * b;
  y = std::fma(a, b, -x);  // exact rounding error of the product
}

// Exact sign of (ax + ay)(bx + by) - (cx + cy)(dx + dy) where each pair is a two-term expansion.
inline int exact_det_sign(const double a[2], const double b[2], const double c[2], const double d[2]) {
  double terms[16];
  int n = 0;
  for (int i = 0; i < 2; ++i)
    for (int j = 0; j < 2; ++j) {
      two_product(a[i], b[j], terms[n], terms[n + 1]);
      n += 2;
      two_product(-c[i], d[j], terms[n], terms[n + 1]);
      n += 2;
    }
  // Grow a non-overlapping expansion term by term; its sign is the sign of its largest component.
  double expansion[17];
  int m = 0;
  for (int t = 0; t < 16; ++t) {
    double q = terms[t];
    for (int k = 0; k < m; ++k) {
      double sum, err;
      two_sum(q, expansion[k], sum, err);
      expansion[k] = err;
      q = sum;
    }
    expansion[m++] = q;
  }
  for (int k = m - 1; k >= 0; --k)
    if (expansion[k] != 0.0) return expansion[k] > 0.0 ? 1 : -1;
  return 0;
}

}  // namespace detail

// Sign of the signed area of triangle (a, b, c): +1 counter-clockwise, -1 clockwise, 0 collinear. Exact.
inline int orientation(const Point& a, const Point& b, const Point& c) {
  const double left = (b.x() - a.x()) * (c.y() - a.y());
  const double right = (b.y() - a.y()) * (c.x() - a.x());
  const double det = left - right;
  // Shewchuk's static bound for this evaluation order: beyond it the rounded sign is already right.
  const double bound = 3.3306690738754716e-16 * (std::abs(left) + std::abs(right));
  if (det > bound) return 1;
  if (-det > bound) return -1;
  if (left == 0.0 && right == 0.0) return 0;
  double ux[2], uy[2], vx[2], vy[2];
  detail::two_diff(b.x(), a.x(), ux[0], ux[1]);
  detail::two_diff(c.y(), a.y(), vy[0], vy[1]);
  detail::two_diff(b.y(), a.y(), uy[0], uy[1]);
  detail::two_diff(c.x(), a.x(), vx[0], vx[1]);
  return detail::exact_det_sign(ux, vy, uy, vx);
}

// Closed segments [a,b] and [c,d] share at least one point (touching and collinear overlap count).
inline bool segments_intersect(const Point& a, const Point& b, const Point& c, const Point& d) {
  // Cheap rejection on bounding boxes; exact because it only compares coordinates.
  if (std::max(a.x(), b.x()) < std::min(c.x(), d.x()) || std::max(c.x(), d.x()) < std::min(a.x(), b.x()) ||
      std::max(a.y(), b.y()) < std::min(c.y(), d.y()) || std::max(c.y(), d.y()) < std::min(a.y(), b.y()))
    return false;
  const int o1 = orientation(a, b, c), o2 = orientation(a, b, d);
  if (o1 != 0 && o1 == o2) return false;
  const int o3 = orientation(c, d, a), o4 = orientation(c, d, b);
  if (o3 != 0 && o3 == o4) return false;
  // All collinear: the bounding boxes overlap (checked above), so the 1D intervals overlap.
  return true;
}

inline bool segments_intersect(const Segment& s, const Segment& t) { return segments_intersect(s.a, s.b, t.a, t.b); }

inline bool box_contains(const Box& box, const Point& p) {
  return p.x() >= box.lo.x() && p.x() <= box.hi.x() && p.y() >= box.lo.y() && p.y() <= box.hi.y();
}

// Closed segment and closed box share a point. Exact: endpoint containment or a crossing of a box side.
inline bool segment_intersects_box(const Segment& s, const Box& box) {
  if (box_contains(box, s.a) || box_contains(box, s.b)) return true;
  const Point p00 = box.lo, p11 = box.hi, p10(box.hi.x(), box.lo.y()), p01(box.lo.x(), box.hi.y());
  return segments_intersect(s.a, s.b, p00, p10) || segments_intersect(s.a, s.b, p10, p11) ||
         segments_intersect(s.a, s.b, p11, p01) || segments_intersect(s.a, s.b, p01, p00);
}

// p lies within tol of the box's outline (or outside it).
inline bool on_box_boundary(const Point& p, const Box& box, double tol) {
  return p.x() <= box.lo.x() + tol || p.x() >= box.hi.x() - tol || p.y() <= box.lo.y() + tol || p.y() >= box.hi.y() - tol;
}

inline double point_segment_distance(const Point& p, const Segment& s) {
  const Point d = s.b - s.a;
  const double len2 = d.squaredNorm();
  double t = len2 > 0.0 ? (p - s.a).dot(d) / len2 : 0.0;
  t = std::clamp(t, 0.0, 1.0);
  return (s.a + t * d - p).norm();
}

// Liang-Barsky clip of segment to the closed box; false when nothing is left.
inline bool clip_segment_to_box(Segment& s, const Box& box) {
  double t0 = 0.0, t1 = 1.0;
  const Point d = s.b - s.a;
  const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
  const double q[4] = {s.a.x() - box.lo.x(), box.hi.x() - s.a.x(), s.a.y() - box.lo.y(), box.hi.y() - s.a.y()};
  for (int i = 0; i < 4; ++i) {
    if (p[i] == 0.0) {
      if (q[i] < 0.0) return false;
      continue;
    }
    const double r = q[i] / p[i];
    if (p[i] < 0.0)
      t0 = std::max(t0, r);
    else
      t1 = std::min(t1, r);
    if (t0 > t1) return false;
  }
  const Point a = s.a;
  if (t0 > 0.0) s.a = a + t0 * d;
  if (t1 < 1.0) s.b = a + t1 * d;
  // Round-off can leave a clipped end a hair outside: pin it to the box.
  for (Point* e : {&s.a, &s.b}) {
    e->x() = std::clamp(e->x(), box.lo.x(), box.hi.x());
    e->y() = std::clamp(e->y(), box.lo.y(), box.hi.y());
  }
  return true;
}

}  // namespace shellfrac::crack2d
