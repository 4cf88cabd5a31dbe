#include "shell/shell_patch.hpp"

#include "core/rigid_rotation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <cstdint>
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
  build_basis_lanes();
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
  added_mass_.assign(x.size(), 0.0);
  reference_stiffness_ = basis_stiffness_ = stiffness_of(basis_rows());
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
          (1.0 - material_.shear_mass_share) * material_.density * vq *
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
    shear.mass.back() = material_.shear_mass_share * material_.density * V;
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

namespace {

// Angular momentum about the origin of the particles' x_p x m_p v_p, summed in index order.
Vec3 moment_of_momentum(const ShearParticles& s) {
  Vec3 L = Vec3::Zero();
  for (size_t c = 0; c < s.x.size(); ++c) L += s.mass[c] * s.x[c].cross(s.v[c]);
  return L;
}

// Adds omega x (x_p - x_c) to every particle's velocity, x_c their centre of mass, with omega chosen so
// that sum x_p x m_p v_p changes by `change` (core::rotation_for; nothing for one row of cells).
void add_rotation(ShearParticles& s, const Vec3& change) {
  double mass = 0;
  Vec3 first = Vec3::Zero();
  for (size_t c = 0; c < s.x.size(); ++c) {
    mass += s.mass[c];
    first += s.mass[c] * s.x[c];
  }
  if (mass <= 0) return;
  const Vec3 centre = first / mass;
  Mat3 spread = Mat3::Zero();
  for (size_t c = 0; c < s.x.size(); ++c) spread += s.mass[c] * (s.x[c] - centre) * (s.x[c] - centre).transpose();
  const Vec3 omega = core::rotation_for(spread, change);
  for (size_t c = 0; c < s.x.size(); ++c) s.v[c] += omega.cross(s.x[c] - centre);
}

}  // namespace

void ShellPatch::update_shear_particles(double dt) {
  // Placing the particles by Eq. 4.10 moves them off the path their grid velocity would take (x + dt v),
  // and that move changes their angular momentum, which the transfers otherwise keep (APIC, and g2p's
  // correction of the FLIP shares). A rotation of their velocities about their centre of mass gives it
  // back: a spinning cut sheet lost 2.1e-5 of it in 400 steps without (docs/shell-model.md, "Transfer").
  const Vec3 before = moment_of_momentum(shear);
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
  add_rotation(shear, before - moment_of_momentum(shear));
}

ShellPatch::BasisView ShellPatch::point_basis(size_t q) const {
  const int32_t slot = point_slot_[q];
  if (slot >= 0) return slot_view(slot);
  const size_t c = cell_of(q);
  return {support_size_, support(c), &basis_[q * static_cast<size_t>(support_size_) * kBasisStride], kBasisStride};
}

void ShellPatch::build_basis_lanes() {
  const size_t n = static_cast<size_t>(support_size_), points = param_.size();
  const size_t batches = (points + kType4Lanes - 1) / kType4Lanes;
  basis_lanes_.assign(batches * n * 5 * kType4Lanes, 0.0);
  for (size_t q = 0; q < points; ++q) {
    const size_t batch = q / kType4Lanes, lane = q % kType4Lanes;
    for (size_t s = 0; s < n; ++s)
      for (size_t k = 0; k < 5; ++k)
        basis_lanes_[((batch * n + s) * 5 + k) * kType4Lanes + lane] = basis_[(q * n + s) * kBasisStride + 1 + k];
  }
  // Rest metrics and volumes in the same lanes, so that the kernel loads them instead of gathering
  // (the rest metric of a plastic patch changes, so its kernel keeps gathering from ref_).
  const size_t L = static_cast<size_t>(num_layers());
  ref_lanes_.assign(batches * L * 4 * kType4Lanes, 0.0);
  volume_lanes_.assign(batches * L * kType4Lanes, 0.0);
  for (size_t q = 0; q < points; ++q) {
    const size_t batch = q / kType4Lanes, lane = q % kType4Lanes;
    for (size_t l = 0; l < L; ++l) {
      const ReferenceLayer& r = ref_[q * L + l];
      const double fields[4] = {r.g11, r.g12, r.g22, 1.0 / r.sqrt_det};  // the kernel multiplies by it
      for (size_t k = 0; k < 4; ++k) ref_lanes_[((batch * L + l) * 4 + k) * kType4Lanes + lane] = fields[k];
      volume_lanes_[(batch * L + l) * kType4Lanes + lane] = volume_[q * L + l];
    }
  }
}

double ShellPatch::parameter_spacing() const {
  return std::min(control_grid_.cell_u, control_grid_.cell_v) / std::sqrt(static_cast<double>(points_per_cell_));
}

bool ShellPatch::point_fully_damaged(size_t q) const {
  const size_t L = layers_.xi3.size();
  for (size_t l = 0; l < L; ++l)
    if (damage_history_[q * L + l] >= 1.0) return true;
  return false;
}

std::vector<unsigned char> ShellPatch::fully_damaged_points() const {
  std::vector<unsigned char> out(param_.size(), 0);
  for (size_t q = 0; q < param_.size() && !damage_history_.empty(); ++q) out[q] = point_fully_damaged(q);
  return out;
}

size_t ShellPatch::num_fully_damaged_points() const {
  // Most calls find nothing fully damaged: a pass two values at a time (GCC leaves the scalar form of
  // this loop unvectorised) settles that before the per-point count.
  typedef double Pair __attribute__((vector_size(2 * sizeof(double))));
  typedef long long PairMask __attribute__((vector_size(2 * sizeof(long long))));
  const Pair one = {1.0, 1.0};
  PairMask reached = {0, 0};
  const size_t n = damage_history_.size();
  size_t i = 0;
  for (; i + 2 <= n; i += 2) {
    Pair h;
    std::memcpy(&h, &damage_history_[i], sizeof(Pair));
    reached |= h >= one;
  }
  bool any = reached[0] || reached[1];
  for (; i < n; ++i) any = any || damage_history_[i] >= 1.0;
  if (!any) return 0;
  size_t count = 0;
  for (size_t q = 0; q < param_.size(); ++q) count += point_fully_damaged(q);
  return count;
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
