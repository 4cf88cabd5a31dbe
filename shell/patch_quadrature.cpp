#include "shell/patch_quadrature.hpp"

#include <stdexcept>
#include <string>

#include "shell/kinematics.hpp"

namespace shellfrac::shell {

namespace {
constexpr int kMaxSupport = 64;  // (p+1)(q+1) for degrees up to 7
}  // namespace

double PatchQuadrature::point_volume(size_t q) const {
  const size_t L = num_layers();
  double V = 0;
  for (size_t l = 0; l < L; ++l) V += volume[q * L + l];
  return V;
}

PatchQuadrature build_quadrature(const nurbs::NurbsSurface& reference, const LayerRule& layers,
                                 const QuadratureRule& rule) {
  PatchQuadrature out;
  out.layers = layers;
  const auto& ku = reference.knots_u();
  const auto& kv = reference.knots_v();
  const auto& X = reference.control_points();
  const int p = ku.degree(), q = kv.degree(), nu = reference.num_u();
  out.support_size = (p + 1) * (q + 1);
  if (out.support_size > kMaxSupport) throw std::invalid_argument("patch degree too high for the shell solver (max 7)");
  const GaussRule g = gauss_legendre(rule.points_per_direction);
  out.points_per_cell = g.x.size() * g.x.size();

  nurbs::SurfaceBasis basis;
  for (int jv = q; jv < reference.num_v(); ++jv) {
    const double v0 = kv[jv], v1 = kv[jv + 1];
    if (!(v1 > v0)) continue;
    for (int iu = p; iu < nu; ++iu) {
      const double u0 = ku[iu], u1 = ku[iu + 1];
      if (!(u1 > u0)) continue;
      ++out.num_cells;
      out.cell_center.emplace_back(0.5 * (u0 + u1), 0.5 * (v0 + v1));
      for (int b = 0; b <= q; ++b)
        for (int a = 0; a <= p; ++a) out.support.push_back((iu - p + a) + nu * (jv - q + b));
      for (size_t gj = 0; gj < g.x.size(); ++gj)
        for (size_t gi = 0; gi < g.x.size(); ++gi) {
          const double u = u0 + 0.5 * (g.x[gi] + 1.0) * (u1 - u0);
          const double w = v0 + 0.5 * (g.x[gj] + 1.0) * (v1 - v0);
          const double area_weight = 0.25 * g.w[gi] * g.w[gj] * (u1 - u0) * (v1 - v0);
          out.param.emplace_back(u, w);
          reference.rational_basis(u, w, basis);
          const size_t base = out.basis.size();
          out.basis.resize(base + static_cast<size_t>(out.support_size * kBasisStride), 0.0);
          for (int k = 0; k < basis.count; ++k) {
            const int idx = basis.index[static_cast<size_t>(k)];
            const int local = (idx % nu - (iu - p)) + (p + 1) * (idx / nu - (jv - q));
            double* d = &out.basis[base + static_cast<size_t>(local * kBasisStride)];
            d[0] = basis.R[static_cast<size_t>(k)];
            d[1] = basis.Ru[static_cast<size_t>(k)];
            d[2] = basis.Rv[static_cast<size_t>(k)];
            d[3] = basis.Ruu[static_cast<size_t>(k)];
            d[4] = basis.Ruv[static_cast<size_t>(k)];
            d[5] = basis.Rvv[static_cast<size_t>(k)];
          }
          // Reference KL basis and volume of each layer point: V_q = w |det Gbar| (thesis Eq. 4.6).
          const Vec3* pts[kMaxSupport];
          const int* sup = out.cell_support(out.num_cells - 1);
          for (int s = 0; s < out.support_size; ++s) pts[s] = &X[static_cast<size_t>(sup[s])];
          const SurfaceJet jet = surface_jet(pts, &out.basis[base + 1], out.support_size, kBasisStride);
          NormalJet nj;
          if (!normal_jet(jet, nj))
            throw std::invalid_argument("patch is degenerate (parallel tangents) at parameter (" +
                                        std::to_string(u) + ", " + std::to_string(w) + ")");
          for (size_t l = 0; l < layers.xi3.size(); ++l) {
            const ReferenceLayer ref = reference_layer(kl_basis(jet, nj, layers.xi3[l]));
            out.ref.push_back(ref);
            out.volume.push_back(area_weight * layers.w[l] * ref.sqrt_det);
          }
        }
    }
  }
  out.control_grid = ControlGrid::from_surface(reference);
  return out;
}

BasisLanes lay_out_basis_lanes(const PatchQuadrature& quad) {
  BasisLanes out;
  const size_t n = static_cast<size_t>(quad.support_size), points = quad.param.size();
  const size_t batches = (points + kType4Lanes - 1) / kType4Lanes;
  out.basis.assign(batches * n * 5 * kType4Lanes, 0.0);
  for (size_t q = 0; q < points; ++q) {
    const size_t batch = q / kType4Lanes, lane = q % kType4Lanes;
    for (size_t s = 0; s < n; ++s)
      for (size_t k = 0; k < 5; ++k)
        out.basis[((batch * n + s) * 5 + k) * kType4Lanes + lane] = quad.basis[(q * n + s) * kBasisStride + 1 + k];
  }
  // The rest metric of a plastic patch changes, so its kernel gathers from quad.ref instead.
  const size_t L = quad.num_layers();
  out.ref.assign(batches * L * 4 * kType4Lanes, 0.0);
  out.volume.assign(batches * L * kType4Lanes, 0.0);
  for (size_t q = 0; q < points; ++q) {
    const size_t batch = q / kType4Lanes, lane = q % kType4Lanes;
    for (size_t l = 0; l < L; ++l) {
      const ReferenceLayer& r = quad.ref[q * L + l];
      const double fields[4] = {r.g11, r.g12, r.g22, 1.0 / r.sqrt_det};  // the kernel multiplies by it
      for (size_t k = 0; k < 4; ++k) out.ref[((batch * L + l) * 4 + k) * kType4Lanes + lane] = fields[k];
      out.volume[(batch * L + l) * kType4Lanes + lane] = quad.volume[q * L + l];
    }
  }
  return out;
}

}  // namespace shellfrac::shell
