// The shell's force pass (thesis sec. 4.3.2, step 3): Type IV forces of every quadrature point in lanes of
// the batched kernel (MLS points in lanes of their own) or scalar, the Type III shear forces, and the
// deterministic gather onto the control points.
#include "shell/shell_patch.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cstdint>
#include <string>

namespace shellfrac::shell {

namespace {

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

// Each control point's force: its cell slots, then its fallback bases' slots, in a fixed order, so the sum
// does not depend on the threads.
void gather_control_forces(const ForceGather& g, std::vector<Vec3>& force) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, force.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      Vec3 f = Vec3::Zero();
      for (int k = g.offsets[i]; k < g.offsets[i + 1]; ++k) f += g.cell_force[static_cast<size_t>(g.entries[static_cast<size_t>(k)])];
      for (int k = g.slot_offsets[i]; k < g.slot_offsets[i + 1]; ++k)
        f += g.slot_force[static_cast<size_t>(g.slot_entries[static_cast<size_t>(k)])];
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
  d.fracturing = !state_.damage.empty();
  d.monotone = material_.fracture.rule == DamageRule::Monotone;
  d.residual = material_.fracture.residual_stiffness;
  d.layers = num_layers();
  d.xi3 = quad_.layers.xi3.data();
  d.x = x.data();
  d.ref = quad_.ref.data();
  d.volume = quad_.volume.data();
  d.plastic_strain = state_.plastic_strain.data();
  d.damage = state_.damage.data();
  d.damage_history = state_.damage_history.data();
  d.failure_stress = state_.failure_stress.data();
  d.brittleness = state_.brittleness.data();
  return d;
}

ForceFailure ShellPatch::compute_forces() {
  const Type4Data data = type4_data();
  const bool with_director = material_.stress_model == StressModel::DirectorF2D;
  const bool batched = force_kernel_ != ForceKernel::Scalar && num_layers() <= kType4MaxLayers;
  const bool lane_volume = force_kernel_ == ForceKernel::Batched || force_kernel_ == ForceKernel::BatchedScalarMls;
  // A plastic patch's rest metric changes, so its lanes are gathered from quad_.ref (lay_out_basis_lanes).
  const bool lane_ref = lane_volume && !material_.plasticity.enabled;
  const bool mls_lanes = batched && force_kernel_ != ForceKernel::BatchedScalarMls;
  const size_t n = static_cast<size_t>(quad_.support_size);
  std::vector<unsigned char> cell_failed(quad_.num_cells, 0);
  std::fill(gather_.slot_force.begin(), gather_.slot_force.end(), Vec3::Zero());

  // Per cell: the Type IV forces of its points (cell slots for NURBS points, MLS supports' own slots
  // otherwise), then its Type III force. Each cell's slots are summed in point order, whichever kernel runs,
  // and no lane depends on the others, so the forces do not depend on the partition into threads.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, quad_.num_cells, 16), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c)
      for (size_t s = 0; s < n; ++s) gather_.cell_force[c * n + s].setZero();
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
      const int32_t slot = cut_.point_slot[q];
      const MlsSupport* ms = slot >= 0 ? &cut_.slots[static_cast<size_t>(slot)] : nullptr;
      if (ms && ms->level >= BasisLevel::Rigid) return;
      const BasisView b = point_basis(q);
      // A linear basis has no curvature: every layer sees the mid-surface metric (membrane only).
      const bool membrane = ms && ms->order == 1;
      const Type4Status st = type4_point_force(data, q, {b.n, b.index, b.basis}, membrane, r33_of(c), point_force_target(q));
      if (st != kType4Ok) cell_failed[c] = static_cast<unsigned char>(st);
    };
    const size_t q_begin = r.begin() * quad_.points_per_cell, q_end = r.end() * quad_.points_per_cell;
    if (!batched) {
      for (size_t q = q_begin; q < q_end; ++q)
        if (!cell_failed[cell_of(q)]) scalar_point(q);
    } else {
      Type4Batch batch;
      batch.n = quad_.support_size;
      Type4BatchResult result;
      // Batches of the fixed grouping (8 consecutive points); one that straddles the range's ends runs
      // only the lanes inside it.
      for (size_t first = q_begin - q_begin % kType4Lanes; first < q_end; first += kType4Lanes) {
        batch.basis = &lanes_.basis[first / kType4Lanes * n * 5 * kType4Lanes];
        const size_t L = static_cast<size_t>(num_layers());
        batch.ref_lanes = lane_ref ? &lanes_.ref[first / kType4Lanes * L * 4 * kType4Lanes] : nullptr;
        batch.volume_lanes = lane_volume ? &lanes_.volume[first / kType4Lanes * L * kType4Lanes] : nullptr;
        size_t lane_cell[kType4Lanes];
        assign_lanes(*this, cut_.point_slot.data(), first, q_begin, q_end, batch, lane_cell);
        if (!batch.active) continue;
        if (with_director)
          for (int i = 0; i < kType4Lanes; ++i) batch.r33[i] = r33_of(lane_cell[i]);
        type4_force_batch(data, batch, result);
        scatter_batch(result, batch.active, lane_cell, n, gather_.cell_force.data(), cell_failed.data());
      }
      for (size_t q = q_begin; q < q_end; ++q)
        if (cut_.point_slot[q] >= 0 && !(mls_lanes && mls_lanes_.batched[q]) && !cell_failed[cell_of(q)]) scalar_point(q);
    }
    for (size_t c = r.begin(); c != r.end(); ++c)
      if (!cell_failed[c] && !add_shear_force(c)) cell_failed[c] = 2;
  });

  if (mls_lanes) mls_batch_forces(data, with_director, cell_failed);

  for (size_t c = 0; c < quad_.num_cells; ++c)
    if (cell_failed[c]) return cell_failure(c, cell_failed[c], c * quad_.points_per_cell, quad_.param[c * quad_.points_per_cell]);
  gather_control_forces(gather_, force);
  return {};
}

void ShellPatch::mls_batch_forces(const Type4Data& data, bool with_director, std::vector<unsigned char>& cell_failed) {
  // Each lane writes only its own support's forces and its own point's state, so batches run in any
  // order and the forces do not depend on the threads; statuses are folded into the cells afterwards.
  std::vector<int> status(mls_lanes_.batches.size() * kType4Lanes, kType4Ok);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mls_lanes_.batches.size(), 4), [&](const tbb::blocked_range<size_t>& r) {
    Type4Batch batch;
    Type4BatchResult result;
    for (size_t b = r.begin(); b != r.end(); ++b) {
      const MlsLaneBatch& mb = mls_lanes_.batches[b];
      batch.n = mb.n;
      batch.active = mb.active;
      batch.basis = mls_lanes_.basis.data() + 5 * mb.first;
      for (int i = 0; i < kType4Lanes; ++i) {
        batch.q[i] = mb.q[i];
        batch.support[i] = mls_lanes_.support.data() + mb.first + static_cast<size_t>(i * mb.n);
        batch.r33[i] = with_director ? director_stretch(cell_of(mb.q[i])) : 1.0;
      }
      type4_force_batch(data, batch, result);
      for (int i = 0; i < kType4Lanes; ++i) {
        if (!((mb.active >> i) & 1u)) continue;
        status[b * kType4Lanes + static_cast<size_t>(i)] = result.status[i];
        if (result.status[i] != kType4Ok) continue;
        const MlsSupport& m = cut_.slots[static_cast<size_t>(cut_.point_slot[mb.q[i]])];
        Vec3* force = gather_.forces_of(m);
        for (size_t s = 0; s < m.index.size(); ++s)
          force[s] = Vec3(result.force[s][0][i], result.force[s][1][i], result.force[s][2][i]);
      }
    }
  });
  for (size_t k = 0; k < status.size(); ++k)
    if (status[k] != kType4Ok) cell_failed[cell_of(mls_lanes_.batches[k / kType4Lanes].q[k % kType4Lanes])] = static_cast<unsigned char>(status[k]);
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

}  // namespace shellfrac::shell
