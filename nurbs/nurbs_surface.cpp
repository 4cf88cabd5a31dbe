#include "nurbs/nurbs_surface.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <string>

#include "nurbs/bspline_basis.hpp"
#include "nurbs/detail.hpp"
#include "nurbs/nurbs_error.hpp"

namespace shellfrac::nurbs {

using detail::format_number;

namespace {

using Vec4 = Eigen::Vector4d;

constexpr std::size_t kStackBasis = 3 * (static_cast<std::size_t>(kStackDegree) + 1);

// Derivative slots of the homogeneous sums, in the order they are filled.
enum Slot { kS = 0, kSu = 1, kSv = 2, kSuu = 3, kSuv = 4, kSvv = 5 };

// Homogeneous surface sums H = sum_ij N_i M_j (w P, w)_ij and their parametric derivatives up to
// `order` (0, 1 or 2); slots follow Slot. Tensor-product evaluation: first along u for each row j,
// then combined along v.
void homogeneous_sums(const NurbsSurface& s, double u, double v, int order, Vec4* h) {
  const KnotVector& ku = s.knots_u();
  const KnotVector& kv = s.knots_v();
  const int p = ku.degree();
  const int q = kv.degree();
  const std::size_t Pu = static_cast<std::size_t>(p) + 1;
  const std::size_t Pv = static_cast<std::size_t>(q) + 1;
  const std::size_t rows = static_cast<std::size_t>(order) + 1;
  detail::ScratchBuffer<kStackBasis> bu(rows * Pu);
  detail::ScratchBuffer<kStackBasis> bv(rows * Pv);
  const int span_u = bspline_basis_derivs(ku, u, order, bu.data());
  const int span_v = bspline_basis_derivs(kv, v, order, bv.data());
  const double* Nu = bu.data();
  const double* Nv = bv.data();

  const int slots = order == 0 ? 1 : (order == 1 ? 3 : 6);
  for (int k = 0; k < slots; ++k) h[k].setZero();

  const Vec3List& points = s.control_points();
  const std::vector<double>& weights = s.weights();
  const int nu = s.num_u();
  for (int b = 0; b <= q; ++b) {
    const int j = span_v - q + b;
    Vec4 row[3] = {Vec4::Zero(), Vec4::Zero(), Vec4::Zero()};  // u-derivatives 0..2 along this row
    for (int a = 0; a <= p; ++a) {
      const std::size_t idx = static_cast<std::size_t>(span_u - p + a + nu * j);
      const double w = weights[idx];
      Vec4 hp;
      hp << w * points[idx], w;
      for (int k = 0; k <= order; ++k) row[k] += Nu[static_cast<std::size_t>(k) * Pu + static_cast<std::size_t>(a)] * hp;
    }
    const double m0 = Nv[b];
    h[kS] += m0 * row[0];
    if (order >= 1) {
      const double m1 = Nv[Pv + static_cast<std::size_t>(b)];
      h[kSu] += m0 * row[1];
      h[kSv] += m1 * row[0];
      if (order >= 2) {
        const double m2 = Nv[2 * Pv + static_cast<std::size_t>(b)];
        h[kSuu] += m0 * row[2];
        h[kSuv] += m1 * row[1];
        h[kSvv] += m2 * row[0];
      }
    }
  }
}

// Unit normal from the tangents. Where |du x dv| vanishes (a collapsed edge such as a cone apex),
// the normal is undefined and is returned as the zero vector; callers must handle that case.
Vec3 unit_normal(const Vec3& du, const Vec3& dv) {
  const Vec3 c = du.cross(dv);
  const double norm = c.norm();
  return norm > 1e-300 ? Vec3(c / norm) : Vec3(Vec3::Zero());
}

}  // namespace

NurbsSurface::NurbsSurface(KnotVector knots_u, KnotVector knots_v, Vec3List control_points,
                           std::vector<double> weights)
    : knots_u_(std::move(knots_u)),
      knots_v_(std::move(knots_v)),
      control_points_(std::move(control_points)),
      weights_(std::move(weights)) {
  const std::size_t nu = static_cast<std::size_t>(num_u());
  const std::size_t nv = static_cast<std::size_t>(num_v());
  const std::size_t n = nu * nv;
  if (control_points_.size() != n) {
    throw NurbsError("control net has " + std::to_string(control_points_.size()) +
                     " points but knots and degrees require " + std::to_string(nu) + " x " + std::to_string(nv) +
                     " = " + std::to_string(n));
  }
  if (weights_.size() != n) {
    throw NurbsError("surface has " + std::to_string(weights_.size()) + " weights but " + std::to_string(n) +
                     " control points; give one weight per control point");
  }
  for (std::size_t k = 0; k < n; ++k) {
    const std::string where = "(" + std::to_string(k % nu) + ", " + std::to_string(k / nu) + ")";
    if (!std::isfinite(weights_[k]) || !(weights_[k] > 0.0)) {
      throw NurbsError("weight " + where + " = " + format_number(weights_[k]) +
                       " is invalid; weights must be finite and > 0");
    }
    if (!control_points_[k].allFinite()) {
      throw NurbsError("control point " + where + " is not finite; coordinates must be finite numbers");
    }
    if (weights_[k] != 1.0) rational_ = true;
  }
}

Vec3 NurbsSurface::point(double u, double v) const {
  Vec4 h[1];
  homogeneous_sums(*this, u, v, 0, h);
  return h[kS].head<3>() / h[kS][3];
}

Vec3 NurbsSurface::normal(double u, double v) const {
  Vec4 h[3];
  homogeneous_sums(*this, u, v, 1, h);
  const double w = h[kS][3];
  const Vec3 x = h[kS].head<3>() / w;
  const Vec3 du = (h[kSu].head<3>() - h[kSu][3] * x) / w;
  const Vec3 dv = (h[kSv].head<3>() - h[kSv][3] * x) / w;
  return unit_normal(du, dv);
}

SurfacePoint NurbsSurface::evaluate(double u, double v) const {
  // Quotient rule on S = A / W, A = sum N M w P, W = sum N M w (thesis Eq. 2.37–2.38).
  Vec4 h[6];
  homogeneous_sums(*this, u, v, 2, h);
  auto A = [&](int k) { return h[k].head<3>(); };
  auto W = [&](int k) { return h[k][3]; };
  const double w = W(kS);
  SurfacePoint sp;
  sp.x = A(kS) / w;
  sp.du = (A(kSu) - W(kSu) * sp.x) / w;
  sp.dv = (A(kSv) - W(kSv) * sp.x) / w;
  sp.duu = (A(kSuu) - 2.0 * W(kSu) * sp.du - W(kSuu) * sp.x) / w;
  sp.duv = (A(kSuv) - W(kSu) * sp.dv - W(kSv) * sp.du - W(kSuv) * sp.x) / w;
  sp.dvv = (A(kSvv) - 2.0 * W(kSv) * sp.dv - W(kSvv) * sp.x) / w;
  sp.normal = unit_normal(sp.du, sp.dv);
  return sp;
}

void NurbsSurface::rational_basis(double u, double v, SurfaceBasis& out) const {
  const int p = knots_u_.degree();
  const int q = knots_v_.degree();
  const std::size_t Pu = static_cast<std::size_t>(p) + 1;
  const std::size_t Pv = static_cast<std::size_t>(q) + 1;
  detail::ScratchBuffer<kStackBasis> bu(3 * Pu);
  detail::ScratchBuffer<kStackBasis> bv(3 * Pv);
  const int span_u = bspline_basis_derivs(knots_u_, u, 2, bu.data());
  const int span_v = bspline_basis_derivs(knots_v_, v, 2, bv.data());
  const double* Nu = bu.data();
  const double* Nv = bv.data();

  const std::size_t count = Pu * Pv;
  out.count = static_cast<int>(count);
  // resize() is a no-op when the degrees did not change, so repeated calls do not allocate.
  out.index.resize(count);
  out.R.resize(count);
  out.Ru.resize(count);
  out.Rv.resize(count);
  out.Ruu.resize(count);
  out.Ruv.resize(count);
  out.Rvv.resize(count);

  // Pass 1: weighted products f = w N M and their derivatives (stored in place), and their sums W.
  double W = 0, Wu = 0, Wv = 0, Wuu = 0, Wuv = 0, Wvv = 0;
  const int nu = num_u();
  std::size_t k = 0;
  for (std::size_t b = 0; b < Pv; ++b) {
    const int j = span_v - q + static_cast<int>(b);
    const double m0 = Nv[b], m1 = Nv[Pv + b], m2 = Nv[2 * Pv + b];
    for (std::size_t a = 0; a < Pu; ++a, ++k) {
      const int i = span_u - p + static_cast<int>(a);
      const int idx = i + nu * j;
      const double w = weights_[static_cast<std::size_t>(idx)];
      const double n0 = w * Nu[a], n1 = w * Nu[Pu + a], n2 = w * Nu[2 * Pu + a];
      out.index[k] = idx;
      W += out.R[k] = n0 * m0;
      Wu += out.Ru[k] = n1 * m0;
      Wv += out.Rv[k] = n0 * m1;
      Wuu += out.Ruu[k] = n2 * m0;
      Wuv += out.Ruv[k] = n1 * m1;
      Wvv += out.Rvv[k] = n0 * m2;
    }
  }
  // Pass 2: quotient rule R = f / W (thesis Eq. 2.38), differentiated twice.
  const double inv = 1.0 / W;
  for (k = 0; k < count; ++k) {
    const double R = out.R[k] * inv;
    const double Ru = (out.Ru[k] - R * Wu) * inv;
    const double Rv = (out.Rv[k] - R * Wv) * inv;
    out.Ruu[k] = (out.Ruu[k] - 2.0 * Ru * Wu - R * Wuu) * inv;
    out.Ruv[k] = (out.Ruv[k] - Ru * Wv - Rv * Wu - R * Wuv) * inv;
    out.Rvv[k] = (out.Rvv[k] - 2.0 * Rv * Wv - R * Wvv) * inv;
    out.R[k] = R;
    out.Ru[k] = Ru;
    out.Rv[k] = Rv;
  }
}

}  // namespace shellfrac::nurbs
