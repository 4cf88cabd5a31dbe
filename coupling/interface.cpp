#include "coupling/interface.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "coupling/arc_length.hpp"
#include "coupling/coupling_error.hpp"
#include "coupling/edge_gap.hpp"
#include "coupling/format.hpp"
#include "coupling/virtual_refinement.hpp"

namespace shellfrac::coupling {

namespace {

std::string edge_label(int patch, Side side) {
  return "patch " + std::to_string(patch) + " side " + side_name(side);
}

template <class Points>
PointRows gather(const Points& x, const std::vector<int>& rows, const char* what) {
  PointRows out(static_cast<Eigen::Index>(rows.size()), 3);
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const std::size_t f = static_cast<std::size_t>(rows[k]);
    if (f >= x.size()) {
      throw CouplingError(std::string(what) + " control point array has " + std::to_string(x.size()) +
                          " entries but the interface refers to index " + std::to_string(f));
    }
    out.row(static_cast<Eigen::Index>(k)) = x[f].transpose();
  }
  return out;
}

template <class Points>
PointRows rows_from_leader(const Interface& itf, const Points& leader_x) {
  const PointRows c1 = gather(leader_x, itf.leader_row1, "leader");
  const PointRows row1 = itf.M0 * c1;  // Eq. 4.29
  if (itf.continuity == Continuity::C0) return row1;
  const PointRows c2 = gather(leader_x, itf.leader_row2, "leader");
  PointRows out(2 * row1.rows(), 3);
  out.topRows(row1.rows()) = row1;
  if (itf.M1_row2.size() == 0)
    out.bottomRows(row1.rows()) = row1 + itf.M1 * (c1 - c2);  // Eq. 4.34, sign per docs/coupling.md
  else
    out.bottomRows(row1.rows()) = row1 + itf.M1 * c1 - itf.M1_row2 * c2;
  return out;
}

template <class Points>
void scatter(const Interface& itf, const PointRows& rows, Points& follower_x) {
  const std::size_t n = itf.follower_row1.size();
  const std::size_t needed = static_cast<std::size_t>(
      std::max(*std::max_element(itf.follower_row1.begin(), itf.follower_row1.end()),
               *std::max_element(itf.follower_row2.begin(), itf.follower_row2.end())));
  if (needed >= follower_x.size()) {
    throw CouplingError("follower control point array has " + std::to_string(follower_x.size()) +
                        " entries but the interface refers to index " + std::to_string(needed));
  }
  for (std::size_t k = 0; k < n; ++k) {
    follower_x[static_cast<std::size_t>(itf.follower_row1[k])] = rows.row(static_cast<Eigen::Index>(k)).transpose();
  }
  if (itf.continuity == Continuity::C0) return;
  for (std::size_t k = 0; k < n; ++k) {
    follower_x[static_cast<std::size_t>(itf.follower_row2[k])] =
        rows.row(static_cast<Eigen::Index>(n + k)).transpose();
  }
}

PointRows rows_of(const nurbs::NurbsSurface& s, const std::vector<int>& rows) {
  return gather(s.control_points(), rows, "reference");
}

}  // namespace

PointRows Interface::follower_rows(const std::vector<Vec3>& leader_x) const { return rows_from_leader(*this, leader_x); }
PointRows Interface::follower_rows(const nurbs::Vec3List& leader_x) const { return rows_from_leader(*this, leader_x); }

std::vector<Vec3> Interface::follower_positions(const std::vector<Vec3>& leader_x) const {
  const PointRows rows = follower_rows(leader_x);
  std::vector<Vec3> out(static_cast<std::size_t>(rows.rows()));
  for (Eigen::Index k = 0; k < rows.rows(); ++k) out[static_cast<std::size_t>(k)] = rows.row(k).transpose();
  return out;
}

void Interface::apply(const std::vector<Vec3>& leader_x, std::vector<Vec3>& follower_x) const {
  scatter(*this, follower_rows(leader_x), follower_x);
}

void Interface::apply(const nurbs::Vec3List& leader_x, nurbs::Vec3List& follower_x) const {
  scatter(*this, follower_rows(leader_x), follower_x);
}

namespace {

// Geometric checks in the reference configuration: the two edges have the same length and coincide (with
// the orientation flag). Returns their largest gap.
double check_edges_coincide(const nurbs::NurbsSurface& a, Side sa, const Edge& ea, const nurbs::NurbsSurface& b, Side sb,
                            const Edge& eb, bool reversed, const InterfaceOptions& options, const std::string& pair) {
  const nurbs::NurbsCurve ca = edge_curve(a, ea), cb = edge_curve(b, eb);
  const double len_a = ArcLength(ca).total(), len_b = ArcLength(cb).total();
  if (std::abs(len_a - len_b) > options.tolerance) {
    throw CouplingError("cannot couple " + pair + ": the edges have different lengths (" + format_number(len_a) +
                        " vs " + format_number(len_b) + ", tolerance " + format_number(options.tolerance) + ")");
  }
  const double gap = edge_gap(a, sa, b, sb, reversed, options.gap_samples);
  if (gap > options.tolerance) {
    throw CouplingError("cannot couple " + pair + ": the edges do not coincide (max gap " + format_number(gap) +
                        " > tolerance " + format_number(options.tolerance) + ", reversed = " +
                        (reversed ? "true" : "false") + "); check the sides and the orientation flag");
  }
  return gap;
}

// Exact closure needs a closed rest state: the leader's reference rows lie in the space both edges share.
void check_rest_state_closed(const SharedSpace& shared, const PointRows& lead1, const PointRows& lead2,
                             const InterfaceOptions& options, const std::string& pair) {
  auto off_space = [](const Eigen::MatrixXd& E, const PointRows& rows) {
    return (E * pseudo_inverse(E) * rows - rows).rowwise().norm().maxCoeff();
  };
  double off = off_space(shared.E1, lead1);
  if (options.continuity == Continuity::C1) off = std::max(off, off_space(shared.E2, lead2));
  if (off > options.tolerance) {
    throw CouplingError("exact closure of " + pair + ": the leader's reference rows are " + format_number(off) +
                        " away from the " + std::to_string(shared.E1.cols()) +
                        " control points both edges share (tolerance " + format_number(options.tolerance) +
                        "); use \"closure\": \"least_squares\" for this seam");
  }
}

}  // namespace

Interface make_interface(const nurbs::NurbsSurface& a, int patch_a, Side sa, const nurbs::NurbsSurface& b,
                         int patch_b, Side sb, bool reversed, const InterfaceOptions& options) {
  const std::string pair = edge_label(patch_a, sa) + " and " + edge_label(patch_b, sb);
  const Edge ea = extract_edge(a, sa);
  const Edge eb = extract_edge(b, sb);
  if (ea.knots.degree() != eb.knots.degree()) {
    throw CouplingError("cannot couple " + pair + ": degrees along the edge differ (" +
                        std::to_string(ea.knots.degree()) + " vs " + std::to_string(eb.knots.degree()) +
                        "); elevate one patch so both edges have the same degree");
  }

  const double gap = check_edges_coincide(a, sa, ea, b, sb, eb, reversed, options, pair);

  // The lower-resolution edge leads (lambda), the other follows (eta).
  const bool a_leads = ea.row1.size() <= eb.row1.size();
  const nurbs::NurbsSurface& leader = a_leads ? a : b;
  const nurbs::NurbsSurface& follower = a_leads ? b : a;
  const Edge& el = a_leads ? ea : eb;
  const Edge& ef = a_leads ? eb : ea;

  const VirtualRefinement r = virtual_refinement(ef.knots, ef.weights1, el.knots, el.weights1, reversed);

  // Same curve after refinement <=> same refined control points (Eq. 4.28: U_eta c_eta = U_lambda c_lambda).
  const PointRows lead1 = rows_of(leader, el.row1), fol1 = rows_of(follower, ef.row1);
  const double mismatch = (r.U_follower * fol1 - r.U_leader * lead1).rowwise().norm().maxCoeff();
  if (mismatch > options.tolerance) {
    throw CouplingError("cannot couple " + pair + ": the edges coincide (gap " + format_number(gap) +
                        ") but are parameterised differently (refined control points differ by " +
                        format_number(mismatch) + "); coupling needs edge parameterisations related by an affine map");
  }

  Interface itf;
  itf.leader_patch = a_leads ? patch_a : patch_b;
  itf.follower_patch = a_leads ? patch_b : patch_a;
  itf.leader_side = el.side;
  itf.follower_side = ef.side;
  itf.reversed = reversed;
  itf.continuity = options.continuity;
  itf.leader_row1 = el.row1;
  itf.leader_row2 = el.row2;
  itf.follower_row1 = ef.row1;
  itf.follower_row2 = ef.row2;
  itf.common_knots = r.common_knots.knots();

  const Eigen::MatrixXd pinv = pseudo_inverse(r.U_follower);  // once, at set-up
  itf.M0 = c0_operator(pinv, r.U_leader);
  if (options.continuity == Continuity::C1) {
    if (options.cross_scale == CrossScale::KnotSpans) {
      itf.D = cross_scale_from_knots(ef, el, r);
    } else {
      const PointRows fol2 = rows_of(follower, ef.row2), lead2 = rows_of(leader, el.row2);
      itf.D = cross_scale_from_reference(r, fol2 - fol1, lead2 - lead1);
    }
    itf.M1 = c1_operator(pinv, itf.D, r.U_leader);
  }
  if (options.closure == Closure::Exact) {
    itf.exact = true;
    itf.shared = shared_space(el, ef, reversed, options.continuity == Continuity::C1);
    const bool c1 = options.continuity == Continuity::C1;
    check_rest_state_closed(itf.shared, lead1, c1 ? rows_of(leader, el.row2) : PointRows(), options, pair);
  }
  return itf;
}

}  // namespace shellfrac::coupling
