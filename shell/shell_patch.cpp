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

// Points first .. first + 7 into the lanes of `batch`: those inside [q_begin, q_end) on NURBS bases (no
// MLS slot) are active; the others repeat a valid point and are not evaluated. Fibre stretches start at 1.
void assign_lanes(const ShellPatch& patch, const int32_t* point_slot, size_t first, size_t q_begin, size_t q_end,
                  Type4Batch& batch, size_t (&lane_cell)[kType4Lanes]) {
  const size_t fill = q_begin > first ? q_begin : first;
  batch.active = 0;
  for (int i = 0; i < kType4Lanes; ++i) {
    const size_t q = first + static_cast<size_t>(i);
    const bool inside = q >= q_begin && q < q_end && q < patch.num_inplane_points();
    const size_t lane_q = inside ? q : fill;
    if (inside && point_slot[q] < 0) batch.active |= 1u << i;
    batch.q[i] = lane_q;
    lane_cell[i] = patch.cell_of(lane_q);
    batch.support[i] = patch.support(lane_cell[i]);
    batch.r33[i] = 1.0;
  }
  batch.shared_support = true;
  for (int i = 1; i < kType4Lanes; ++i) batch.shared_support &= batch.support[i] == batch.support[0];
}

// Each control point's force: its cell slots, then its MLS supports' slots, in a fixed order, so the sum
// does not depend on the threads.
template <class Slots>
void gather_control_forces(const std::vector<int>& offsets, const std::vector<int>& entries,
                           const std::vector<Vec3>& cell_force, const std::vector<int>& mls_offsets,
                           const std::vector<std::pair<int, int>>& mls_entries, const Slots& slots,
                           std::vector<Vec3>& force) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, force.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Vec3 f = Vec3::Zero();
      for (int k = offsets[i]; k < offsets[i + 1]; ++k) f += cell_force[static_cast<size_t>(entries[static_cast<size_t>(k)])];
      for (int k = mls_offsets[i]; k < mls_offsets[i + 1]; ++k) {
        const auto& e = mls_entries[static_cast<size_t>(k)];
        f += slots[static_cast<size_t>(e.first)].force[static_cast<size_t>(e.second)];
      }
      force[i] = f;
    }
  });
}

// Adds one batch's lane forces to the cell slots, one run of lanes per cell: a whole batch in one cell by a
// fixed pairwise sum (no serial chain), a partial run lane by lane in point order. Either order is fixed by
// the data, so the sums do not depend on the threads. A failing lane marks its cell, whose forces are then
// dropped. `cell_force` holds n force vectors per cell.
void scatter_batch(const Type4BatchResult& result, unsigned active, const size_t (&lane_cell)[kType4Lanes], size_t n,
                   Vec3* cell_force, unsigned char* cell_failed) {
  for (int i = 0; i < kType4Lanes;) {
    const size_t c = lane_cell[i];
    int lanes[kType4Lanes], count = 0, end = i;
    for (; end < kType4Lanes && lane_cell[end] == c; ++end) {
      if (!((active >> end) & 1u) || cell_failed[c]) continue;
      if (result.status[end] != kType4Ok)
        cell_failed[c] = static_cast<unsigned char>(result.status[end]);
      else
        lanes[count++] = end;
    }
    i = end;
    if (cell_failed[c] || !count) continue;
    double* out = cell_force[c * n].data();
    if (count == kType4Lanes) {
      for (size_t s = 0; s < n; ++s)
        for (int k = 0; k < 3; ++k) {
          const double* f = result.force[s][k];
          out[3 * s + static_cast<size_t>(k)] += ((f[0] + f[1]) + (f[2] + f[3])) + ((f[4] + f[5]) + (f[6] + f[7]));
        }
      continue;
    }
    for (size_t s = 0; s < n; ++s)
      for (int k = 0; k < 3; ++k) {
        double sum = out[3 * s + static_cast<size_t>(k)];
        for (int j = 0; j < count; ++j) sum += result.force[s][k][lanes[j]];
        out[3 * s + static_cast<size_t>(k)] = sum;
      }
  }
}

// What failed in cell c (status 2: a shear director, 3: a runaway stretch, else a collapsed element),
// reported at its first point.
ForceFailure cell_failure(size_t c, unsigned char status, size_t first_point, const Eigen::Vector2d& parameter) {
  ForceFailure failure;
  failure.failed = true;
  failure.quadrature_point = first_point;
  failure.parameter = parameter;
  const std::string cell = " in cell " + std::to_string(c);
  failure.reason = status == 2 ? "shear particle director crushed into the tangent plane" + cell
                   : status == 3
                       ? "shell element stretched to more than " + std::to_string(static_cast<int>(kRunawayAreaRatio)) +
                             " times its area" + cell + " (a diverging step: lower time.cfl or dt)"
                       : "degenerate or collapsed shell element (area ratio <= 0)" + cell;
  return failure;
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

Type4Data ShellPatch::type4_data() {
  const StressModel stress_model = material_.stress_model;
  const bool with_director = stress_model == StressModel::DirectorF2D;
  Type4Data d;
  d.mu = material_.mu;
  d.lambda = material_.lambda;
  d.model = stress_model == StressModel::KirchhoffLove ? material_.transverse
            : with_director                         ? TransverseModel::Given
                                                    : TransverseModel::Rigid;
  d.plane_strain = stress_model == StressModel::PlaneStrain;
  d.mid_surface = stress_model == StressModel::MidSurface2D || with_director;
  d.plastic = material_.plasticity.enabled;
  d.plasticity = material_.plasticity;
  d.fracturing = !damage_.empty();
  d.monotone = material_.fracture.rule == DamageRule::Monotone;
  d.residual = material_.fracture.residual_stiffness;
  d.layers = num_layers();
  d.xi3 = layers_.xi3.data();
  d.x = x.data();
  d.ref = ref_.data();
  d.volume = volume_.data();
  d.plastic_strain = plastic_strain_.data();
  d.damage = damage_.data();
  d.damage_history = damage_history_.data();
  d.failure_stress = failure_stress_.data();
  d.brittleness = brittleness_.data();
  return d;
}

ForceFailure ShellPatch::compute_forces() {
  const Type4Data data = type4_data();
  const bool with_director = material_.stress_model == StressModel::DirectorF2D;
  const bool batched = force_kernel_ != ForceKernel::Scalar && num_layers() <= kType4MaxLayers;
  const bool lane_volume = force_kernel_ == ForceKernel::Batched || force_kernel_ == ForceKernel::BatchedScalarMls;
  // A plastic patch's rest metric changes, so its lanes are gathered from ref_ (build_basis_lanes).
  const bool lane_ref = lane_volume && !material_.plasticity.enabled;
  const bool mls_lanes = batched && force_kernel_ != ForceKernel::BatchedScalarMls;
  const size_t n = static_cast<size_t>(support_size_);
  std::vector<unsigned char> cell_failed(num_cells_, 0);
  for (MlsSupport& m : slots_)
    for (Vec3& f : m.force) f.setZero();

  // Per cell: the Type IV forces of its points (cell slots for NURBS points, MLS supports' own slots
  // otherwise), then its Type III force. Each cell's slots are summed in point order, whichever kernel runs,
  // and no lane depends on the others, so the forces do not depend on the partition into threads.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_cells_, 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c)
      for (size_t s = 0; s < n; ++s) cell_force_[c * n + s].setZero();
    // Jiang 2017: J = J_2D r_33, one QR per cell (the last cell's value is kept for its other points).
    size_t r33_cell = SIZE_MAX;
    double r33_value = 1.0;
    auto r33_of = [&](size_t c) {
      if (!with_director) return 1.0;
      if (c != r33_cell) {
        r33_cell = c;
        r33_value = director_stretch(c);
      }
      return r33_value;
    };
    // A point the batches leave to the scalar code: MLS supports (any fallback level with stress) or all
    // points when the scalar kernel is chosen. Rigid and removed slivers carry no stress.
    auto scalar_point = [&](size_t q) {
      const size_t c = cell_of(q);
      const int32_t slot = point_slot_[q];
      const MlsSupport* ms = slot >= 0 ? &slots_[static_cast<size_t>(slot)] : nullptr;
      if (ms && ms->level >= BasisLevel::Rigid) return;
      const BasisView b = point_basis(q);
      // A linear basis has no curvature: every layer sees the mid-surface metric (membrane only).
      const bool membrane = ms && ms->order == 1;
      const Type4Status st = type4_point_force(data, q, {b.n, b.index, b.basis}, membrane, r33_of(c), point_force_target(q));
      if (st != kType4Ok) cell_failed[c] = static_cast<unsigned char>(st);
    };
    const size_t q_begin = r.begin() * points_per_cell_, q_end = r.end() * points_per_cell_;
    if (!batched) {
      for (size_t q = q_begin; q < q_end; ++q)
        if (!cell_failed[cell_of(q)]) scalar_point(q);
    } else {
      Type4Batch batch;
      batch.n = support_size_;
      Type4BatchResult result;
      // Batches of the fixed grouping (8 consecutive points); one that straddles the range's ends runs
      // only the lanes inside it.
      for (size_t first = q_begin - q_begin % kType4Lanes; first < q_end; first += kType4Lanes) {
        batch.basis = &basis_lanes_[first / kType4Lanes * n * 5 * kType4Lanes];
        const size_t L = static_cast<size_t>(num_layers());
        batch.ref_lanes = lane_ref ? &ref_lanes_[first / kType4Lanes * L * 4 * kType4Lanes] : nullptr;
        batch.volume_lanes = lane_volume ? &volume_lanes_[first / kType4Lanes * L * kType4Lanes] : nullptr;
        size_t lane_cell[kType4Lanes];
        assign_lanes(*this, point_slot_.data(), first, q_begin, q_end, batch, lane_cell);
        if (!batch.active) continue;
        if (with_director)
          for (int i = 0; i < kType4Lanes; ++i) batch.r33[i] = r33_of(lane_cell[i]);
        type4_force_batch(data, batch, result);
        scatter_batch(result, batch.active, lane_cell, n, cell_force_.data(), cell_failed.data());
      }
      for (size_t q = q_begin; q < q_end; ++q)
        if (point_slot_[q] >= 0 && !(mls_lanes && mls_batched_[q]) && !cell_failed[cell_of(q)]) scalar_point(q);
    }
    for (size_t c = r.begin(); c != r.end(); ++c)
      if (!cell_failed[c] && !add_shear_force(c)) cell_failed[c] = 2;
  });

  if (mls_lanes) mls_batch_forces(data, with_director, cell_failed);

  for (size_t c = 0; c < num_cells_; ++c)
    if (cell_failed[c]) return cell_failure(c, cell_failed[c], c * points_per_cell_, param_[c * points_per_cell_]);
  gather_control_forces(gather_offsets_, gather_, cell_force_, mls_gather_offsets_, mls_gather_, slots_, force);
  return {};
}

void ShellPatch::mls_batch_forces(const Type4Data& data, bool with_director, std::vector<unsigned char>& cell_failed) {
  // Each lane writes only its own support's forces and its own point's state, so batches run in any
  // order and the forces do not depend on the threads; statuses are folded into the cells afterwards.
  std::vector<int> status(mls_batches_.size() * kType4Lanes, kType4Ok);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mls_batches_.size(), 4), [&](const tbb::blocked_range<size_t>& r) {
    Type4Batch batch;
    Type4BatchResult result;
    for (size_t b = r.begin(); b != r.end(); ++b) {
      const MlsLaneBatch& mb = mls_batches_[b];
      batch.n = mb.n;
      batch.active = mb.active;
      batch.basis = mls_lane_basis_.data() + 5 * mb.first;
      for (int i = 0; i < kType4Lanes; ++i) {
        batch.q[i] = mb.q[i];
        batch.support[i] = mls_lane_support_.data() + mb.first + static_cast<size_t>(i * mb.n);
        batch.r33[i] = with_director ? director_stretch(cell_of(mb.q[i])) : 1.0;
      }
      type4_force_batch(data, batch, result);
      for (int i = 0; i < kType4Lanes; ++i) {
        if (!((mb.active >> i) & 1u)) continue;
        status[b * kType4Lanes + static_cast<size_t>(i)] = result.status[i];
        if (result.status[i] != kType4Ok) continue;
        std::vector<Vec3>& force = slots_[static_cast<size_t>(point_slot_[mb.q[i]])].force;
        for (size_t s = 0; s < force.size(); ++s)
          force[s] = Vec3(result.force[s][0][i], result.force[s][1][i], result.force[s][2][i]);
      }
    }
  });
  for (size_t k = 0; k < status.size(); ++k)
    if (status[k] != kType4Ok) cell_failed[cell_of(mls_batches_[k / kType4Lanes].q[k % kType4Lanes])] = static_cast<unsigned char>(status[k]);
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
