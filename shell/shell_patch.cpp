#include "shell/shell_patch.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <limits>
#include <cmath>
#include <stdexcept>

namespace shellfrac::shell {

namespace {
constexpr int kMaxSupport = 64;  // (p+1)(q+1) for degrees up to 7
}  // namespace

ShellPatch::ShellPatch(const nurbs::NurbsSurface& reference, const ShellMaterial& material,
                       const QuadratureRule& rule)
    : reference_(reference), material_(material), layers_(thickness_layers(rule.layers, material.thickness)) {
  if (!(material.thickness > 0) || !(material.density > 0) || !(material.mu > 0))
    throw std::invalid_argument("shell material needs thickness, density and shear modulus > 0");
  if (material.stress_model != StressModel::KirchhoffLove && material.plasticity.enabled)
    throw std::invalid_argument("plasticity needs the Kirchhoff-Love stress model");
  x = reference_.control_points().empty() ? std::vector<Vec3>{}
                                          : std::vector<Vec3>(reference_.control_points().begin(),
                                                              reference_.control_points().end());
  v.assign(x.size(), Vec3::Zero());
  force.assign(x.size(), Vec3::Zero());
  build_quadrature(rule);
  build_masses();
  build_force_gather();
  build_shear_particles();
  if (material_.plasticity.enabled) plastic_strain_.assign(ref_.size(), 0.0);
  control_grid_ = ControlGrid::from_surface(reference_);
  point_slot_.assign(param_.size(), -1);
  shear_slot_.assign(num_cells_, -1);
  control_near_crack_.assign(x.size(), 0);
  shear_near_crack_.assign(num_cells_, 0);
  mls_gather_offsets_.assign(x.size() + 1, 0);
  if (material_.fracture.enabled) {
    damage_.assign(ref_.size(), 0.0);
    damage_history_.assign(ref_.size(), 0.0);
    failure_stress_.assign(param_.size(), material_.fracture.failure_stress);
    brittleness_.assign(param_.size(), material_.brittleness);
  }
  reference_stiffness_ = basis_stiffness_ = compute_basis_stiffness();
}

nurbs::NurbsSurface ShellPatch::current_surface() const {
  return nurbs::NurbsSurface(reference_.knots_u(), reference_.knots_v(),
                             nurbs::Vec3List(x.begin(), x.end()), reference_.weights());
}

void ShellPatch::build_quadrature(const QuadratureRule& rule) {
  const auto& ku = reference_.knots_u();
  const auto& kv = reference_.knots_v();
  const int p = ku.degree(), q = kv.degree(), nu = reference_.num_u();
  support_size_ = (p + 1) * (q + 1);
  if (support_size_ > kMaxSupport) throw std::invalid_argument("patch degree too high for the shell solver (max 7)");
  const GaussRule g = gauss_legendre(rule.points_per_direction);
  points_per_cell_ = g.x.size() * g.x.size();

  nurbs::SurfaceBasis basis;
  for (int jv = q; jv < reference_.num_v(); ++jv) {
    const double v0 = kv[jv], v1 = kv[jv + 1];
    if (!(v1 > v0)) continue;
    for (int iu = p; iu < nu; ++iu) {
      const double u0 = ku[iu], u1 = ku[iu + 1];
      if (!(u1 > u0)) continue;
      ++num_cells_;
      cell_center_.emplace_back(0.5 * (u0 + u1), 0.5 * (v0 + v1));
      for (int b = 0; b <= q; ++b)
        for (int a = 0; a <= p; ++a) support_.push_back((iu - p + a) + nu * (jv - q + b));
      for (size_t gj = 0; gj < g.x.size(); ++gj)
        for (size_t gi = 0; gi < g.x.size(); ++gi) {
          const double u = u0 + 0.5 * (g.x[gi] + 1.0) * (u1 - u0);
          const double w = v0 + 0.5 * (g.x[gj] + 1.0) * (v1 - v0);
          const double area_weight = 0.25 * g.w[gi] * g.w[gj] * (u1 - u0) * (v1 - v0);
          param_.emplace_back(u, w);
          reference_.rational_basis(u, w, basis);
          const size_t base = basis_.size();
          basis_.resize(base + static_cast<size_t>(support_size_ * kBasisStride), 0.0);
          for (int k = 0; k < basis.count; ++k) {
            const int idx = basis.index[static_cast<size_t>(k)];
            const int local = (idx % nu - (iu - p)) + (p + 1) * (idx / nu - (jv - q));
            double* d = &basis_[base + static_cast<size_t>(local * kBasisStride)];
            d[0] = basis.R[static_cast<size_t>(k)];
            d[1] = basis.Ru[static_cast<size_t>(k)];
            d[2] = basis.Rv[static_cast<size_t>(k)];
            d[3] = basis.Ruu[static_cast<size_t>(k)];
            d[4] = basis.Ruv[static_cast<size_t>(k)];
            d[5] = basis.Rvv[static_cast<size_t>(k)];
          }
          // Reference KL basis and volume of each layer point: V_q = w |det Gbar| (thesis Eq. 4.6).
          const Vec3* pts[kMaxSupport];
          const int* sup = &support_[(num_cells_ - 1) * static_cast<size_t>(support_size_)];
          for (int s = 0; s < support_size_; ++s) pts[s] = &x[static_cast<size_t>(sup[s])];
          const SurfaceJet jet = surface_jet(pts, &basis_[base + 1], support_size_, kBasisStride);
          NormalJet nj;
          if (!normal_jet(jet, nj))
            throw std::invalid_argument("patch is degenerate (parallel tangents) at parameter (" +
                                        std::to_string(u) + ", " + std::to_string(w) + ")");
          for (size_t l = 0; l < layers_.xi3.size(); ++l) {
            const ReferenceLayer ref = reference_layer(kl_basis(jet, nj, layers_.xi3[l]));
            ref_.push_back(ref);
            volume_.push_back(area_weight * layers_.w[l] * ref.sqrt_det);
          }
        }
    }
  }
}

void ShellPatch::build_masses() {
  // Consistent-row-sum lumped mass: m_s = rho sum_q V_q R_s(xi_q), times the control points' share.
  mass.assign(x.size(), 0.0);
  const size_t L = layers_.xi3.size();
  for (size_t q = 0; q < param_.size(); ++q) {
    double vq = 0;
    for (size_t l = 0; l < L; ++l) vq += volume_[q * L + l];
    const int* sup = support(cell_of(q));
    for (int s = 0; s < support_size_; ++s)
      mass[static_cast<size_t>(sup[s])] +=
          (1.0 - kShearParticleMassShare) * material_.density * vq *
          basis_[(q * support_size_ + static_cast<size_t>(s)) * kBasisStride];
  }
}

void ShellPatch::build_force_gather() {
  cell_force_.assign(num_cells_ * static_cast<size_t>(support_size_), Vec3::Zero());
  gather_offsets_.assign(x.size() + 1, 0);
  for (int c : support_) ++gather_offsets_[static_cast<size_t>(c) + 1];
  for (size_t i = 0; i < x.size(); ++i) gather_offsets_[i + 1] += gather_offsets_[i];
  gather_.resize(support_.size());
  std::vector<int> cursor(gather_offsets_.begin(), gather_offsets_.end() - 1);
  for (size_t k = 0; k < support_.size(); ++k) gather_[static_cast<size_t>(cursor[static_cast<size_t>(support_[k])]++)] = static_cast<int>(k);
}

void ShellPatch::build_shear_particles() {
  const size_t L = layers_.xi3.size();
  nurbs::SurfaceBasis basis;
  shear.basis.assign(num_cells_ * static_cast<size_t>(support_size_ * kShearStride), 0.0);
  for (size_t c = 0; c < num_cells_; ++c) {
    const Vec2& uv = cell_center_[c];
    reference_.rational_basis(uv.x(), uv.y(), basis);
    const int* sup = support(c);
    double* out = &shear.basis[c * static_cast<size_t>(support_size_ * kShearStride)];
    Vec3 pos = Vec3::Zero(), A1 = Vec3::Zero(), A2 = Vec3::Zero();
    for (int k = 0; k < basis.count; ++k) {
      const int idx = basis.index[static_cast<size_t>(k)];
      int local = 0;
      while (sup[local] != idx) ++local;  // the cell's support holds every non-zero function
      out[local * kShearStride + 0] = basis.R[static_cast<size_t>(k)];
      out[local * kShearStride + 1] = basis.Ru[static_cast<size_t>(k)];
      out[local * kShearStride + 2] = basis.Rv[static_cast<size_t>(k)];
      const Vec3& X = x[static_cast<size_t>(idx)];
      pos += basis.R[static_cast<size_t>(k)] * X;
      A1 += basis.Ru[static_cast<size_t>(k)] * X;
      A2 += basis.Rv[static_cast<size_t>(k)] * X;
    }
    const Vec3 N = A1.cross(A2).normalized();
    const Vec3 E1 = A1.normalized(), E2 = N.cross(E1);
    Mat3 E, D;
    E << E1, E2, N;
    D << A1, A2, N;
    D = E.transpose() * D;  // upper triangular in the local frame; third column e_3
    shear.x.push_back(pos);
    shear.v.push_back(Vec3::Zero());
    shear.mass.push_back(0.0);  // set below from the cell volume
    shear.director.push_back(N);
    shear.reference_inverse.push_back(D.inverse());
    shear.stress.push_back(Mat3::Zero());
    shear.velocity_gradient.push_back(Mat3::Zero());
    double V = 0;
    for (size_t q = c * points_per_cell_; q < (c + 1) * points_per_cell_; ++q)
      for (size_t l = 0; l < L; ++l) V += volume_[q * L + l];
    shear.volume.push_back(V);
    shear.mass.back() = kShearParticleMassShare * material_.density * V;
  }
}

ShellPatch::BasisView ShellPatch::slot_view(int32_t slot) const {
  const MlsSupport& m = slots_[static_cast<size_t>(slot)];
  return {static_cast<int>(m.index.size()), m.index.data(), m.basis.data(), kBasisStride};
}

ShellPatch::BasisView ShellPatch::shear_basis(size_t c) const {
  const int32_t slot = shear_slot_[c];
  if (slot >= 0) return slot_view(slot);
  return {support_size_, support(c), &shear.basis[c * static_cast<size_t>(support_size_ * kShearStride)], kShearStride};
}

Vec3* ShellPatch::shear_force_target(size_t c) {
  const int32_t slot = shear_slot_[c];
  if (slot >= 0) return slots_[static_cast<size_t>(slot)].force.data();
  return &cell_force_[c * static_cast<size_t>(support_size_)];
}

Vec3* ShellPatch::point_force_target(size_t q) {
  const int32_t slot = point_slot_[q];
  if (slot >= 0) return slots_[static_cast<size_t>(slot)].force.data();
  return &cell_force_[cell_of(q) * static_cast<size_t>(support_size_)];
}

Vec3 ShellPatch::shear_particle_frame(size_t c, Vec3& a1, Vec3& a2) const {
  // thesis Eq. 4.10 with the NURBS basis, or the MLS basis near a crack (sec. 4.6)
  const BasisView b = shear_basis(c);
  Vec3 pos = shear_slot_[c] >= 0 ? slots_[static_cast<size_t>(shear_slot_[c])].rigid_offset : Vec3::Zero();
  a1.setZero();
  a2.setZero();
  for (int s = 0; s < b.n; ++s) {
    const Vec3& X = x[static_cast<size_t>(b.index[s])];
    const double* d = b.basis + s * b.stride;
    pos += d[0] * X;
    a1 += d[1] * X;
    a2 += d[2] * X;
  }
  return pos;
}

Mat3 ShellPatch::director_r(size_t c) const {
  if (shear_level(c) >= BasisLevel::Rigid) return Mat3::Identity();  // no tangents: unstrained
  Vec3 a1, a2;
  shear_particle_frame(c, a1, a2);
  Mat3 d;
  d << a1, a2, shear.director[c];
  Mat3 Q, R;
  qr_oriented(d * shear.reference_inverse[c], Q, R);
  return R;
}

double ShellPatch::director_stretch(size_t c) const { return director_r(c)(2, 2); }

void ShellPatch::update_shear_particles(double dt) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_cells_, 64), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c) {
      const BasisLevel level = shear_level(c);
      // A particle in a fragment without control points carries its mass on with its grid velocity; one in
      // a rigid sliver follows the sliver's control points. Neither has tangents: the director is kept.
      if (level == BasisLevel::Removed) {
        shear.x[c] += dt * shear.v[c];
        continue;
      }
      Vec3 a1, a2;
      shear.x[c] = shear_particle_frame(c, a1, a2);  // thesis Eq. 4.10
      if (level == BasisLevel::Rigid) continue;
      const Vec3 d3 = shear.director[c] + dt * (shear.velocity_gradient[c] * shear.director[c]);
      Mat3 d;
      d << a1, a2, d3;
      shear.director[c] = shear_return_map(d * shear.reference_inverse[c], material_.shear);
    }
  });
}

ShellPatch::BasisView ShellPatch::point_basis(size_t q) const {
  const int32_t slot = point_slot_[q];
  if (slot >= 0) return slot_view(slot);
  const size_t c = cell_of(q);
  return {support_size_, support(c), &basis_[q * static_cast<size_t>(support_size_) * kBasisStride], kBasisStride};
}

ForceFailure ShellPatch::compute_forces() {
  const size_t L = layers_.xi3.size();
  const double mu = material_.mu, lambda = material_.lambda;
  const StressModel stress_model = material_.stress_model;
  const bool plane_strain = stress_model == StressModel::PlaneStrain;
  const bool with_director = stress_model == StressModel::DirectorF2D;
  const bool mid_surface = stress_model == StressModel::MidSurface2D || with_director;
  const TransverseModel model = stress_model == StressModel::KirchhoffLove ? material_.transverse
                                : with_director                         ? TransverseModel::Given
                                                                        : TransverseModel::Rigid;
  const bool plastic = material_.plasticity.enabled;
  const bool fracturing = !damage_.empty();
  const bool monotone = material_.fracture.rule == DamageRule::Monotone;
  std::vector<unsigned char> cell_failed(num_cells_, 0);
  for (MlsSupport& m : slots_)
    for (Vec3& f : m.force) f.setZero();

  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_cells_, 16), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<const Vec3*> pts;
    for (size_t c = r.begin(); c != r.end(); ++c) {
      Vec3* cell_out = &cell_force_[c * static_cast<size_t>(support_size_)];
      for (int s = 0; s < support_size_; ++s) cell_out[s].setZero();
      const double r33 = with_director ? director_stretch(c) : 1.0;  // Jiang 2017: J = J_2D r_33
      for (size_t q = c * points_per_cell_; q < (c + 1) * points_per_cell_; ++q) {
        // Fallback levels (docs/mls.md): a rigid or removed sliver carries no stress; a linear basis has
        // no curvature, so every layer sees the mid-surface metric (membrane only).
        const int32_t slot = point_slot_[q];
        const MlsSupport* ms = slot >= 0 ? &slots_[static_cast<size_t>(slot)] : nullptr;
        if (ms && ms->level >= BasisLevel::Rigid) continue;
        const bool membrane = mid_surface || (ms && ms->order == 1);
        const BasisView b = point_basis(q);
        Vec3* force = point_force_target(q);
        pts.resize(static_cast<size_t>(b.n));
        for (int s = 0; s < b.n; ++s) pts[static_cast<size_t>(s)] = &x[static_cast<size_t>(b.index[s])];
        const SurfaceJet jet = surface_jet(pts.data(), b.basis + 1, b.n, kBasisStride);
        NormalJet nj;
        if (!normal_jet(jet, nj)) {
          cell_failed[c] = 1;
          break;
        }
        // dPsi/dg_alpha summed over layers (K) and weighted by xi3 (C); the KL in-plane stress has no
        // g_3 component, so dPsi/dg_3 = 0 (thesis Eq. 4.14).
        Vec3 K1 = Vec3::Zero(), K2 = Vec3::Zero(), C1 = Vec3::Zero(), C2 = Vec3::Zero();
        for (size_t l = 0; l < L; ++l) {
          // The 2D mid-surface model sees the mid-surface metric at every layer (no bending); so does a
          // membrane-only point, against the mid-surface rest metric (its own layer's when plastic).
          const double xi3 = membrane ? 0.0 : layers_.xi3[l];
          const ReferenceLayer& ref = ref_[q * L + (mid_surface || (membrane && !plastic) ? L / 2 : l)];
          const Vec3 g1 = jet.a1 + xi3 * nj.dn1, g2 = jet.a2 + xi3 * nj.dn2;
          // Plastic materials: return-map the current (trial) state first; it needs the same kinematics.
          if (plastic)
            von_mises_return(g1, g2, mu, lambda, material_.plasticity, ref_[q * L + l], plastic_strain_[q * L + l]);
          const InPlaneStress st = neo_hookean_in_plane(g1, g2, ref, mu, lambda, model, r33);
          if (!st.ok) {
            cell_failed[c] = 1;
            break;
          }
          if (st.J > kRunawayAreaRatio) {  // no sheet survives this intact: the explicit step has diverged
            cell_failed[c] = 3;
            break;
          }
          InPlaneTensor tau{st.t11, st.t12, st.t22};
          // Plane strain keeps the transverse normal stress tau^33 = lambda ln J on g_3 = a_3. It does no
          // work (dPsi/dg_3 is parallel to the unit normal, whose variations are normal to it), so it
          // matters only as a principal stress of the damage criterion.
          double tau33 = plane_strain ? lambda * std::log(st.J) : 0.0;
          if (fracturing)
            tau = damaged_stress(tau, g1, g2, st.J * st.lambda3, q, q * L + l, monotone, plane_strain ? &tau33 : nullptr);
          // dPsi/dg_alpha = V tau^{alpha beta} g_beta (P~ : dF = tau^{ab} g_b . dg_a)
          const double V = volume_[q * L + l];
          const Vec3 k1 = V * (tau.t11 * g1 + tau.t12 * g2);
          const Vec3 k2 = V * (tau.t12 * g1 + tau.t22 * g2);
          K1 += k1;
          K2 += k2;
          C1 += xi3 * k1;
          C2 += xi3 * k2;
        }
        if (cell_failed[c]) break;
        const JetGradient gr = kl_basis_adjoint(jet, nj, K1, K2, C1, C2, Vec3::Zero());
        for (int s = 0; s < b.n; ++s) {
          const double* ds = b.basis + s * kBasisStride;
          force[s] -= ds[1] * gr.a1 + ds[2] * gr.a2 + ds[3] * gr.a11 + ds[4] * gr.a12 + ds[5] * gr.a22;
        }
      }
      if (!cell_failed[c] && !add_shear_force(c)) cell_failed[c] = 2;
    }
  });

  ForceFailure failure;
  for (size_t c = 0; c < num_cells_; ++c) {
    if (!cell_failed[c]) continue;
    failure.failed = true;
    failure.quadrature_point = c * points_per_cell_;
    failure.parameter = param_[failure.quadrature_point];
    const std::string cell = " in cell " + std::to_string(c);
    failure.reason = cell_failed[c] == 2 ? "shear particle director crushed into the tangent plane" + cell
                     : cell_failed[c] == 3
                         ? "shell element stretched to more than " + std::to_string(static_cast<int>(kRunawayAreaRatio)) +
                               " times its area" + cell + " (a diverging step: lower time.cfl or dt)"
                         : "degenerate or collapsed shell element (area ratio <= 0)" + cell;
    return failure;
  }
  // Deterministic gather: the cell contributions, then the MLS contributions, in a fixed order.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, x.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Vec3 f = Vec3::Zero();
      for (int k = gather_offsets_[i]; k < gather_offsets_[i + 1]; ++k) f += cell_force_[static_cast<size_t>(gather_[static_cast<size_t>(k)])];
      for (int k = mls_gather_offsets_[i]; k < mls_gather_offsets_[i + 1]; ++k) {
        const auto& e = mls_gather_[static_cast<size_t>(k)];
        f += slots_[static_cast<size_t>(e.first)].force[static_cast<size_t>(e.second)];
      }
      force[i] = f;
    }
  });
  return failure;
}

bool ShellPatch::add_shear_force(size_t c) {
  if (shear_level(c) >= BasisLevel::Rigid) {  // a sliver without tangents carries no stress
    shear.stress[c].setZero();
    return true;
  }
  const BasisView b = shear_basis(c);
  Vec3 a1, a2;
  shear_particle_frame(c, a1, a2);
  const Vec3& d3 = shear.director[c];
  Mat3 d;
  d << a1, a2, d3;
  const Mat3& Dinv = shear.reference_inverse[c];
  const Mat3 F = d * Dinv;
  if (std::abs(F.determinant()) < 1e-12 * a1.norm() * a2.norm() * d3.norm()) return false;
  // dPsi/dd = V P D^-T: columns 1, 2 act on the tangents (control points), column 3 on the director
  // (through the grid velocity gradient that advects it).
  const Mat3 G = shear.volume[c] * shear_pk1(F, material_.shear) * Dinv.transpose();
  Vec3* force = shear_force_target(c);
  for (int s = 0; s < b.n; ++s) force[s] -= b.basis[s * b.stride + 1] * G.col(0) + b.basis[s * b.stride + 2] * G.col(1);
  shear.stress[c] = G.col(2) * d3.transpose();
  return true;
}

double ShellPatch::parameter_spacing() const {
  return std::min(control_grid_.cell_u, control_grid_.cell_v) / std::sqrt(static_cast<double>(points_per_cell_));
}

InPlaneTensor ShellPatch::damaged_stress(const InPlaneTensor& tau, const Vec3& g1, const Vec3& g2, double detF,
                                        size_t q, size_t ql, bool monotone, double* tau33) {
  // Effective stress: the largest principal Cauchy stress of the undamaged trial state (thesis sec.
  // 4.4.1). The in-plane stress has a zero transverse principal value, so it is at least 0; plane strain
  // has tau^33 there instead (g_3 = a_3 is a unit principal direction).
  const double normal = tau33 ? *tau33 : 0.0;
  const double effective = std::max(normal, largest_principal(tau, g1, g2)) / detF;
  double c = rankine_damage(effective, failure_stress_[q], brittleness_[q]);  // thesis Eq. 2.28
  if (monotone) c = std::max(c, damage_[ql]);  // conventional rule, kept for comparison
  damage_[ql] = c;                              // healing rule: c^{n+1} = cbar
  damage_history_[ql] = std::max(damage_history_[ql], c);
  if (tau33 && *tau33 > 0) *tau33 *= 1.0 - c;
  return c > 0 ? weaken_tensile_part(tau, g1, g2, c) : tau;  // thesis Eq. 2.29-2.31
}

std::vector<unsigned char> ShellPatch::fully_damaged_points() const {
  const size_t L = layers_.xi3.size();
  std::vector<unsigned char> out(param_.size(), 0);
  for (size_t q = 0; q < param_.size() && !damage_history_.empty(); ++q)
    for (size_t l = 0; l < L; ++l)
      if (damage_history_[q * L + l] >= 1.0) out[q] = 1;
  return out;
}

double ShellPatch::max_damage() const {
  double m = 0;
  for (double c : damage_) m = std::max(m, c);
  return m;
}

double ShellPatch::max_plastic_strain() const {
  double m = 0;
  for (double a : plastic_strain_) m = std::max(m, a);
  return m;
}

SurfaceJet ShellPatch::point_jet(size_t q, std::vector<const Vec3*>& pts) const {
  const BasisView b = point_basis(q);
  pts.resize(static_cast<size_t>(b.n));
  for (int s = 0; s < b.n; ++s) pts[static_cast<size_t>(s)] = &x[static_cast<size_t>(b.index[s])];
  return surface_jet(pts.data(), b.basis + 1, b.n, kBasisStride);
}

double ShellPatch::elastic_energy() const {
  const size_t L = layers_.xi3.size();
  std::vector<double> per_point(param_.size(), 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, param_.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<const Vec3*> pts;
    for (size_t q = r.begin(); q != r.end(); ++q) {
      if (point_level(q) >= BasisLevel::Rigid) continue;  // no stress, no energy
      const bool membrane = point_slot_[q] >= 0 && slots_[static_cast<size_t>(point_slot_[q])].order == 1;
      const SurfaceJet jet = point_jet(q, pts);
      NormalJet nj;
      if (!normal_jet(jet, nj)) {
        per_point[q] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      // Plane strain and the 2D model have lambda_3 = 1 (the rigid energy); the KL projection changes the
      // stress, not the energy, so only the condensed default is an exact gradient of its energy.
      const bool with_director = material_.stress_model == StressModel::DirectorF2D;
      const bool mid_surface = material_.stress_model == StressModel::MidSurface2D || with_director || membrane;
      const bool plastic = material_.plasticity.enabled;
      const TransverseModel model = material_.stress_model == StressModel::KirchhoffLove ? material_.transverse
                                    : with_director ? TransverseModel::Given
                                                    : TransverseModel::Rigid;
      const double r33 = with_director ? director_stretch(cell_of(q)) : 1.0;
      for (size_t l = 0; l < L; ++l) {
        const double xi3 = mid_surface ? 0.0 : layers_.xi3[l];
        const bool mid_ref = (mid_surface && !membrane) || (membrane && !plastic);
        per_point[q] += volume_[q * L + l] *
                        neo_hookean_in_plane_energy(jet.a1 + xi3 * nj.dn1, jet.a2 + xi3 * nj.dn2,
                                                    ref_[q * L + (mid_ref ? L / 2 : l)], material_.mu,
                                                    material_.lambda, model, r33);
      }
    }
  });
  double e = 0;
  for (double v : per_point) e += v;
  // Type III shear/compression energy at the current directors.
  for (size_t c = 0; c < num_cells_; ++c) e += shear.volume[c] * shear_energy_density(director_r(c), material_.shear);
  return e;
}

std::vector<double> ShellPatch::mid_surface_stress() const {
  const size_t L = layers_.xi3.size();
  std::vector<double> out(param_.size(), 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, param_.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<const Vec3*> pts;
    for (size_t q = r.begin(); q != r.end(); ++q) {
      if (point_level(q) >= BasisLevel::Rigid) continue;
      const SurfaceJet jet = point_jet(q, pts);
      const InPlaneStress st = neo_hookean_in_plane(jet.a1, jet.a2, ref_[q * L + L / 2], material_.mu, material_.lambda,
                                                    material_.transverse);
      if (!st.ok) continue;
      const InPlaneTensor tau{st.t11, st.t12, st.t22};
      const InPlaneTensor neg{-st.t11, -st.t12, -st.t22};
      out[q] = std::max(largest_principal(tau, jet.a1, jet.a2), largest_principal(neg, jet.a1, jet.a2)) /
               (st.J * st.lambda3);
    }
  });
  return out;
}

double ShellPatch::reference_volume() const {
  double V = 0;
  for (double v : volume_) V += v;
  return V;
}

}  // namespace shellfrac::shell
