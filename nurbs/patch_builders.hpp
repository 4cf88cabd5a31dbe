#pragma once
#include "nurbs/nurbs_surface.hpp"

namespace shellfrac::nurbs {

// Placement of a built-in patch in world space: origin plus two orthonormal in-plane axes.
// The patch normal is axis_u x axis_v.
struct Frame {
  Vec3 origin = Vec3::Zero();
  Vec3 axis_u = Vec3::UnitX();
  Vec3 axis_v = Vec3::UnitY();
};

// The thesis's flat layout (sec. 4.3.1): a size_u x size_v rectangle with cells_u x cells_v cells on
// open quadratic knot vectors over [0, 1]. Control points sit at the Greville abscissae: interior
// ones at the cell spacing l, the two next to each border at l/2 from it, giving (cells+2) points
// per direction and an exactly linear (distortion-free) parameterisation.
// Degrees other than 2 (k-refinement): open uniform knots of that degree and control points at their
// Greville abscissae, which is the bilinear patch elevated and then refined, still exactly linear.
NurbsSurface flat_patch(double size_u, double size_v, int cells_u, int cells_v,
                        const Frame& frame = Frame{}, int degree_u = 2, int degree_v = 2);

// A cone segment around the frame's axis_v (the axis), with its seam on axis_u: radius r0 at height 0
// and r1 at height `height`, swept by `sweep` radians (0 < sweep <= 2 pi). The circumferential
// direction u is an exact rational quadratic arc (circular_arc) refined to cells_u spans; the axial
// direction v is linear with cells_v spans. r0 == r1 gives a cylinder segment.
// Degrees above 2 (k-refinement): the arc is degree-elevated before its cells' knots are inserted, so
// the splines are C^(degree - 1) inside each arc piece; the axial direction as in flat_patch.
NurbsSurface cone_segment(double r0, double r1, double height, double sweep, int cells_u,
                          int cells_v, const Frame& frame = Frame{}, int degree_u = 2, int degree_v = 2);

inline NurbsSurface cylinder_segment(double radius, double height, double sweep, int cells_u,
                                     int cells_v, const Frame& frame = Frame{}, int degree_u = 2, int degree_v = 2) {
  return cone_segment(radius, radius, height, sweep, cells_u, cells_v, frame, degree_u, degree_v);
}

}  // namespace shellfrac::nurbs
