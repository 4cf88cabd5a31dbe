#include "coupling/edge.hpp"

#include "coupling/coupling_error.hpp"

namespace shellfrac::coupling {

namespace {

bool is_u_side(Side s) { return s == Side::U0 || s == Side::U1; }
bool is_begin_side(Side s) { return s == Side::U0 || s == Side::V0; }

// The boundary row must be the edge curve and the edge curve must start/end at corners.
void require_clamped(const nurbs::KnotVector& kv, const std::string& what) {
  const int p = kv.degree();
  const int n = kv.num_basis();
  bool clamped = true;
  for (int i = 1; i <= p; ++i) {
    clamped = clamped && kv[i] == kv[0] && kv[n + i] == kv[n];
  }
  if (!clamped) {
    throw CouplingError(what + " is not clamped (end knots must be repeated degree+1 times); "
                        "coupling reads the boundary curve directly from the boundary row of control points");
  }
}

}  // namespace

std::string side_name(Side side) {
  switch (side) {
    case Side::U0: return "U0";
    case Side::U1: return "U1";
    case Side::V0: return "V0";
    case Side::V1: return "V1";
  }
  return "?";
}

Edge extract_edge(const nurbs::NurbsSurface& surface, Side side) {
  const bool u_side = is_u_side(side);
  const nurbs::KnotVector& along = u_side ? surface.knots_v() : surface.knots_u();
  const nurbs::KnotVector& across = u_side ? surface.knots_u() : surface.knots_v();
  require_clamped(along, "knot vector along side " + side_name(side));
  require_clamped(across, "knot vector across side " + side_name(side));
  const int n_across = across.num_basis();
  if (n_across < 2) {
    throw CouplingError("side " + side_name(side) + " has a single row of control points across it; need at least 2");
  }

  const int q = across.degree();
  const bool begin = is_begin_side(side);
  const int i1 = begin ? 0 : n_across - 1;  // boundary row
  const int i2 = begin ? 1 : n_across - 2;  // next row inward
  // The first span from the boundary: [k_q, k_{q+1}] at the start, [k_{n-1}, k_n] at the end.
  const double span = begin ? across[q + 1] - across[q] : across[n_across] - across[n_across - 1];

  Edge e{side, along, {}, {}, {}, {}, q, span};
  const int n_along = along.num_basis();
  for (int k = 0; k < n_along; ++k) {
    const int f1 = u_side ? surface.flat_index(i1, k) : surface.flat_index(k, i1);
    const int f2 = u_side ? surface.flat_index(i2, k) : surface.flat_index(k, i2);
    e.row1.push_back(f1);
    e.row2.push_back(f2);
    e.weights1.push_back(surface.weights()[static_cast<std::size_t>(f1)]);
    e.weights2.push_back(surface.weights()[static_cast<std::size_t>(f2)]);
  }
  return e;
}

nurbs::NurbsCurve edge_curve(const nurbs::NurbsSurface& surface, const Edge& edge) {
  nurbs::Vec3List points;
  points.reserve(edge.row1.size());
  for (int f : edge.row1) points.push_back(surface.control_points()[static_cast<std::size_t>(f)]);
  return nurbs::NurbsCurve(edge.knots, std::move(points), edge.weights1);
}

nurbs::NurbsCurve edge_curve(const nurbs::NurbsSurface& surface, Side side) {
  return edge_curve(surface, extract_edge(surface, side));
}

Eigen::Vector2d edge_to_surface_parameter(const nurbs::NurbsSurface& surface, Side side, double t) {
  switch (side) {
    case Side::U0: return {surface.knots_u().domain_begin(), t};
    case Side::U1: return {surface.knots_u().domain_end(), t};
    case Side::V0: return {t, surface.knots_v().domain_begin()};
    case Side::V1: return {t, surface.knots_v().domain_end()};
  }
  return {t, t};
}

}  // namespace shellfrac::coupling
