#pragma once
#include <string>
#include <vector>

#include "nurbs/nurbs_curve.hpp"
#include "nurbs/nurbs_surface.hpp"

namespace shellfrac::coupling {

using nurbs::Vec3;

// A boundary of a patch: U0 is u = u_begin, U1 is u = u_end, V0 is v = v_begin, V1 is v = v_end.
enum class Side { U0, U1, V0, V1 };

std::string side_name(Side side);

// The control-net data of one patch boundary (thesis sec. 4.8.2: rows c_*1 and c_*2).
// Along the edge the order follows the patch's own edge parameter (v for U sides, u for V sides).
struct Edge {
  Side side;
  nurbs::KnotVector knots;        // knot vector along the edge
  std::vector<int> row1;          // flat indices of the boundary row c_*1
  std::vector<int> row2;          // flat indices of the next row inward c_*2
  std::vector<double> weights1;   // weights of row1: the edge curve's weights
  std::vector<double> weights2;   // weights of row2
  int cross_degree;               // degree across the edge
  double cross_first_span;        // length (in the cross parameter) of the knot span touching the edge
};

// Reads the edge of `surface` on `side`. Both knot vectors must be clamped (end knots repeated p+1
// times) so that the boundary curve is exactly row1; CouplingError otherwise.
Edge extract_edge(const nurbs::NurbsSurface& surface, Side side);

// The boundary curve of the edge (row1 with its weights): S restricted to the side.
nurbs::NurbsCurve edge_curve(const nurbs::NurbsSurface& surface, const Edge& edge);
nurbs::NurbsCurve edge_curve(const nurbs::NurbsSurface& surface, Side side);

// Surface parameter (u, v) of the point with edge parameter t on the side.
Eigen::Vector2d edge_to_surface_parameter(const nurbs::NurbsSurface& surface, Side side, double t);

}  // namespace shellfrac::coupling
