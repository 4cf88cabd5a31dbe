#include "coupling/virtual_refinement.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "coupling/coupling_error.hpp"
#include "coupling/format.hpp"
#include "nurbs/knot_insertion.hpp"

namespace shellfrac::coupling {

namespace {

// Relative tolerance for treating two mapped knots as one, scaled by the parameter range.
constexpr double kKnotTolerance = 1e-10;
// Relative tolerance for the refined weights of the two edges being proportional.
constexpr double kWeightTolerance = 1e-10;

// Distinct values with multiplicities of a sorted knot list, merging values within tol.
struct Run {
  double value;
  int count;
};

std::vector<Run> runs_of(const std::vector<double>& knots, double tol) {
  std::vector<Run> runs;
  for (double k : knots) {
    if (!runs.empty() && std::abs(k - runs.back().value) <= tol) {
      ++runs.back().count;
    } else {
      runs.push_back({k, 1});
    }
  }
  return runs;
}

Eigen::MatrixXd to_dense(const nurbs::SparseMatrix& m) { return Eigen::MatrixXd(m); }

// Snaps each value onto a knot of kv closer than tol, so insertion raises that knot's multiplicity.
std::vector<double> snap_to_knots(std::vector<double> values, const nurbs::KnotVector& kv, double tol) {
  for (double& x : values) {
    for (double k : kv.knots()) {
      if (std::abs(x - k) <= tol) {
        x = k;
        break;
      }
    }
    x = std::clamp(x, kv.domain_begin(), kv.domain_end());
  }
  return values;
}

}  // namespace

double ParameterMap::operator()(double t) const {
  const double f = (t - from_begin) / (from_end - from_begin);
  return to_begin + (to_end - to_begin) * (reversed ? 1.0 - f : f);
}

double ParameterMap::inverse(double s) const {
  const double f = (s - to_begin) / (to_end - to_begin);
  return from_begin + (from_end - from_begin) * (reversed ? 1.0 - f : f);
}

std::vector<double> map_knots(const nurbs::KnotVector& kv, const ParameterMap& map) {
  std::vector<double> out;
  out.reserve(kv.knots().size());
  for (double k : kv.knots()) {
    if (k == kv.domain_begin()) {
      out.push_back(map.reversed ? map.to_end : map.to_begin);
    } else if (k == kv.domain_end()) {
      out.push_back(map.reversed ? map.to_begin : map.to_end);
    } else {
      out.push_back(map(k));
    }
  }
  std::sort(out.begin(), out.end());
  return out;
}

std::vector<double> knot_union(const std::vector<double>& a, const std::vector<double>& b, double tolerance) {
  const std::vector<Run> ra = runs_of(a, tolerance), rb = runs_of(b, tolerance);
  std::vector<double> out;
  std::size_t i = 0, j = 0;
  while (i < ra.size() || j < rb.size()) {
    if (j == rb.size() || (i < ra.size() && ra[i].value < rb[j].value - tolerance)) {
      out.insert(out.end(), static_cast<std::size_t>(ra[i].count), ra[i].value);
      ++i;
    } else if (i == ra.size() || rb[j].value < ra[i].value - tolerance) {
      out.insert(out.end(), static_cast<std::size_t>(rb[j].count), rb[j].value);
      ++j;
    } else {  // same knot: max multiplicity, a's value
      out.insert(out.end(), static_cast<std::size_t>(std::max(ra[i].count, rb[j].count)), ra[i].value);
      ++i;
      ++j;
    }
  }
  return out;
}

std::vector<double> knot_intersection(const std::vector<double>& a, const std::vector<double>& b, double tolerance) {
  const std::vector<Run> ra = runs_of(a, tolerance), rb = runs_of(b, tolerance);
  std::vector<double> out;
  std::size_t j = 0;
  for (const Run& r : ra) {
    while (j < rb.size() && rb[j].value < r.value - tolerance) ++j;
    if (j < rb.size() && std::abs(rb[j].value - r.value) <= tolerance)
      out.insert(out.end(), static_cast<std::size_t>(std::min(r.count, rb[j].count)), r.value);
  }
  return out;
}

std::vector<double> knot_difference(const std::vector<double>& refined, const std::vector<double>& original,
                                    double tolerance) {
  const std::vector<Run> rr = runs_of(refined, tolerance), ro = runs_of(original, tolerance);
  std::vector<double> out;
  std::size_t j = 0;
  for (const Run& r : rr) {
    while (j < ro.size() && ro[j].value < r.value - tolerance) ++j;
    const int have = (j < ro.size() && std::abs(ro[j].value - r.value) <= tolerance) ? ro[j].count : 0;
    if (r.count > have) out.insert(out.end(), static_cast<std::size_t>(r.count - have), r.value);
  }
  return out;
}

std::vector<double> refined_row_weights(const nurbs::KnotVector& knots, const std::vector<double>& weights,
                                        const std::vector<double>& inserts, bool reverse_order) {
  std::vector<double> w = nurbs::refine_knots(knots, weights, inserts).weights;
  if (reverse_order) std::reverse(w.begin(), w.end());
  return w;
}

VirtualRefinement virtual_refinement(const nurbs::KnotVector& follower_knots,
                                     const std::vector<double>& follower_weights,
                                     const nurbs::KnotVector& leader_knots,
                                     const std::vector<double>& leader_weights, bool reversed) {
  if (follower_knots.degree() != leader_knots.degree()) {
    throw CouplingError("edge degrees differ: follower degree " + std::to_string(follower_knots.degree()) +
                        ", leader degree " + std::to_string(leader_knots.degree()) +
                        "; virtual knot insertion needs the same degree along the shared edge (elevate one patch)");
  }
  const ParameterMap map{leader_knots.domain_begin(), leader_knots.domain_end(), follower_knots.domain_begin(),
                         follower_knots.domain_end(), reversed};
  const double tol_f = kKnotTolerance * (follower_knots.domain_end() - follower_knots.domain_begin());
  const double tol_l = kKnotTolerance * (leader_knots.domain_end() - leader_knots.domain_begin());

  // Eq. 4.27: k' = k_eta U k_lambda, and the knots each side lacks.
  const std::vector<double> leader_mapped = map_knots(leader_knots, map);
  const std::vector<double> common = knot_union(follower_knots.knots(), leader_mapped, tol_f);
  const std::vector<double> follower_inserts = snap_to_knots(
      knot_difference(common, follower_knots.knots(), tol_f), follower_knots, tol_f);
  std::vector<double> leader_inserts;
  for (double k : knot_difference(common, leader_mapped, tol_f)) leader_inserts.push_back(map.inverse(k));
  leader_inserts = snap_to_knots(std::move(leader_inserts), leader_knots, tol_l);

  // Eq. 4.28 / D.8: U = W'^-1 A W for each side.
  nurbs::CurveRefinement rf = nurbs::refine_knots(follower_knots, follower_weights, follower_inserts);
  nurbs::CurveRefinement rl = nurbs::refine_knots(leader_knots, leader_weights, leader_inserts);
  Eigen::MatrixXd U_leader = to_dense(rl.U);
  std::vector<double> leader_refined_weights = rl.weights;
  if (reversed) {
    U_leader = U_leader.colwise().reverse().eval();
    std::reverse(leader_refined_weights.begin(), leader_refined_weights.end());
  }
  if (U_leader.rows() != rf.U.rows()) {  // cannot happen when the union is right; guards the tolerances
    throw CouplingError("virtual refinement produced " + std::to_string(rf.U.rows()) + " follower and " +
                        std::to_string(U_leader.rows()) + " leader control points; the knot union is inconsistent");
  }

  // Cartesian coupling U_eta c_eta = U_lambda c_lambda means the same curve only if the refined weights
  // agree up to one common factor.
  const double scale = rf.weights.front() / leader_refined_weights.front();
  for (std::size_t k = 0; k < rf.weights.size(); ++k) {
    const double expected = scale * leader_refined_weights[k];
    if (std::abs(rf.weights[k] - expected) > kWeightTolerance * std::abs(expected)) {
      throw CouplingError("rational edges have incompatible weights: after refinement to the common knots, "
                          "follower weight " + format_number(rf.weights[k]) + " vs scaled leader weight " +
                          format_number(expected) + " at refined control point " + std::to_string(k) +
                          "; the two edges must carry the same rational parameterisation");
    }
  }
  return VirtualRefinement{rf.knots,         rf.weights,         follower_inserts, leader_inserts,
                           to_dense(rf.U),   std::move(U_leader), map};
}

}  // namespace shellfrac::coupling
