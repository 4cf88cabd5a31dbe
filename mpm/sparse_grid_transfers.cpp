// The sparse grid's transfers (thesis sec. 2.3): particle to grid, forces, the grid update and grid to
// particle, over the stencils rebuild() cached (sparse_grid.cpp).
#include "mpm/sparse_grid.hpp"

#include "core/rigid_rotation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>
#include <type_traits>

namespace shellfrac::mpm {

template <class Fn>
void SparseGrid::for_blocks_coloured(Fn&& fn) const {
  for (const auto& blocks : colour_blocks_)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.size(), 4), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) fn(blocks[i]);
    });
}

// Calls fn(std::bool_constant<a>, ...) for runtime flags, so that a transfer loop is compiled once per
// combination of the optional terms with the unused ones removed.
template <class Fn>
void with_flag(bool a, Fn&& fn) {
  if (a)
    fn(std::true_type{});
  else
    fn(std::false_type{});
}

// The cached axis weights of a particle, copied to locals.
inline void load_weights(const double (&w)[3][3], const double (&dw)[3][3], double* wx, double* wy, double* wz,
                         double* dwx, double* dwy, double* dwz) {
  for (int i = 0; i < 3; ++i) {
    wx[i] = w[0][i];
    wy[i] = w[1][i];
    wz[i] = w[2][i];
    dwx[i] = dw[0][i];
    dwy[i] = dw[1][i];
    dwz[i] = dw[2][i];
  }
}

// The transfers below run over the 3 x 3 x 3 stencil as k (z), j (y), i (x) loops and factor the dyadic
// weight w_ijk = wx_i wy_j wz_k (thesis Eq. 2.14): whatever depends on (j, k) only is formed once per row of
// three nodes. Affine and MLS terms are linear in the node position, x_i - x_p = d0 + dx (i, j, k), so they
// are carried as a particle vector plus one increment per axis instead of a matrix product per node.

// Node arrays are reached through local pointers: Eigen's vector stores may alias anything, which would
// otherwise make the compiler reload every member pointer after each store.

void SparseGrid::transfer_mass_momentum(const std::vector<ParticleSet>& sets) {
  double* const mass = mass_.data();
  Vec3* const momentum = momentum_.data();
  for_blocks_coloured([&, mass, momentum](uint32_t b) {
    for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
      const ParticleSet& s = sets[entries_[e].set];
      const uint32_t p = entries_[e].index;
      const ParticleStencil& st = stencil_[e];
      double wx[3], wy[3], wz[3], dwx[3], dwy[3], dwz[3];  // locals: the node stores cannot change them
      load_weights(st.w, st.dw, wx, wy, wz, dwx, dwy, dwz);
      const uint32_t* nodes = entry_nodes(e);
      const double mp = s.mass[p];
      with_flag(s.affine != nullptr, [&](auto affine) {
        // Momentum sent to node (i, j, k): m v + m C (x_i - x_p) = a0 + i ax + j ay + k az (APIC, Eq. 2.23).
        Vec3 a0 = mp * s.velocity[p], ax, ay, az;
        if (affine) {
          const Mat3 mC = mp * s.affine[p];
          a0 += mC * Vec3(st.d0[0], st.d0[1], st.d0[2]);
          ax = dx_ * mC.col(0);
          ay = dx_ * mC.col(1);
          az = dx_ * mC.col(2);
        }
        for (int k = 0; k < 3; ++k) {
          const Vec3 ak = affine ? Vec3(a0 + static_cast<double>(k) * az) : a0;
          for (int j = 0; j < 3; ++j) {
            const double wyz = wy[j] * wz[k];
            const double mq = wyz * mp;
            const uint32_t* row = nodes + 3 * j + 9 * k;
            if (affine) {
              const Vec3 q = wyz * (ak + static_cast<double>(j) * ay), r = wyz * ax;  // row (j, k), per unit wx
              for (int i = 0; i < 3; ++i) {
                mass[row[i]] += wx[i] * mq;
                momentum[row[i]] += wx[i] * (q + static_cast<double>(i) * r);
              }
            } else {
              const Vec3 q = wyz * a0;
              for (int i = 0; i < 3; ++i) {
                mass[row[i]] += wx[i] * mq;
                momentum[row[i]] += wx[i] * q;
              }
            }
          }
        }
      });
      if (nodes == st.node) continue;
      // Phantom copies: centre-of-mass and mass-gradient sums for the contact normal (thesis Eq. 4.22).
      const Vec3& xp = s.position[p];
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i) {
            const size_t node = nodes[i + 3 * j + 9 * k];
            if (node < grid_nodes_) continue;
            const double w = wx[i] * wy[j] * wz[k];
            copy_mass_position_[node - grid_nodes_] += (w * mp) * xp;
            copy_mass_gradient_[node - grid_nodes_] +=
                mp * Vec3(dwx[i] * wy[j] * wz[k], wx[i] * dwy[j] * wz[k],
                          wx[i] * wy[j] * dwz[k]);
          }
    }
  });
}

void SparseGrid::transfer_forces(const std::vector<ParticleSet>& sets) {
  const double inv_d = apic_inverse_d(dx_);
  Vec3* const force = force_.data();
  for_blocks_coloured([&, force](uint32_t b) {
    for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
      const ParticleSet& s = sets[entries_[e].set];
      if (!s.force && !s.stress) continue;
      const uint32_t p = entries_[e].index;
      const ParticleStencil& st = stencil_[e];
      double wx[3], wy[3], wz[3], dwx[3], dwy[3], dwz[3];  // locals: the node stores cannot change them
      load_weights(st.w, st.dw, wx, wy, wz, dwx, dwy, dwz);
      const uint32_t* nodes = entry_nodes(e);
      const Vec3 f = s.force ? s.force[p] : Vec3::Zero();
      if (s.stress && !s.mls_force) {
        // Node (i, j, k) receives w f - S grad w = wx_i E_jk + dwx_i F_jk with
        // E_jk = wy wz f - wz dwy S_1 - dwz wy S_2 and F_jk = -wy wz S_0 (S_c: column c of S; Eq. 2.17).
        const Mat3& S = s.stress[p];
        for (int k = 0; k < 3; ++k)
          for (int j = 0; j < 3; ++j) {
            const double wyz = wy[j] * wz[k];
            const Vec3 E = wyz * f - (dwy[j] * wz[k]) * S.col(1) - (wy[j] * dwz[k]) * S.col(2);
            const Vec3 F = -wyz * S.col(0);
            const uint32_t* row = nodes + 3 * j + 9 * k;
            for (int i = 0; i < 3; ++i) force[row[i]] += wx[i] * E + dwx[i] * F;
          }
        continue;
      }
      if (!s.stress) {  // Lagrangian force alone: w f (the generalized control-point force, Eq. 4.8)
        for (int k = 0; k < 3; ++k)
          for (int j = 0; j < 3; ++j) {
            const Vec3 q = (wy[j] * wz[k]) * f;
            const uint32_t* row = nodes + 3 * j + 9 * k;
            for (int i = 0; i < 3; ++i) force[row[i]] += wx[i] * q;
          }
        continue;
      }
      // With the MLS stress term (Eq. 2.24): node (i, j, k) receives
      // w (f - D^-1 S (x_i - x_p)) = w (b0 + i bx + j by + k bz).
      const Mat3 DS = inv_d * s.stress[p];
      const Vec3 b0 = f - DS * Vec3(st.d0[0], st.d0[1], st.d0[2]), bx = -dx_ * DS.col(0), by = -dx_ * DS.col(1),
                 bz = -dx_ * DS.col(2);
      for (int k = 0; k < 3; ++k) {
        const Vec3 bk = b0 + static_cast<double>(k) * bz;
        for (int j = 0; j < 3; ++j) {
          const double wyz = wy[j] * wz[k];
          const Vec3 q = wyz * (bk + static_cast<double>(j) * by), r = wyz * bx;
          const uint32_t* row = nodes + 3 * j + 9 * k;
          for (int i = 0; i < 3; ++i) force[row[i]] += wx[i] * (q + static_cast<double>(i) * r);
        }
      }
    }
  });
}

void SparseGrid::update_velocities(double dt, const Vec3& gravity) {
  const double* const mass = mass_.data();
  const Vec3* const momentum = momentum_.data();
  const Vec3* const force = force_.data();
  Vec3* const velocity = velocity_.data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mass_.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t n = r.begin(); n != r.end(); ++n) {
      if (mass[n] > 0)
        velocity[n] = (momentum[n] + dt * force[n]) / mass[n] + dt * gravity;
      else
        velocity[n].setZero();
    }
  });
}

namespace {

// True when the FLIP shares are not one value for every particle: per-particle shares, or sets that differ.
bool shares_vary(const std::vector<ParticleSet>& sets) {
  for (const ParticleSet& s : sets)
    if (s.flip_share || s.flip != sets.front().flip) return true;
  return false;
}

// One block's sums for the momentum correction of FLIP shares that differ, with w_p = m_p (1 - r_p) the
// weight of a dissipating particle: sum w_p delta_p and sum w_p; the first and second moments of the
// weights about the origin, sum w_p x_p and sum w_p x_p x_p^T; and the angular momentum the kept FLIP parts
// carry at the advected positions, sum m_p (x_p + dt v_PIC) x r_p delta_p.
struct ResidualSum {
  Vec3 residual = Vec3::Zero();
  double weight = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  Vec3 angular = Vec3::Zero();

  void add(const ResidualSum& o) {
    residual += o.residual;
    weight += o.weight;
    first += o.first;
    second += o.second;
    angular += o.angular;
  }
};

// What one particle's gather reads besides its stencil.
struct GatherInputs {
  const Vec3* velocity;  // after the grid update
  const Vec3* momentum;  // p2g momentum, with the mass: the node's velocity before the update, for FLIP
  const double* mass;
  double dx, inv_d;      // grid spacing, APIC D^-1 (Eq. 2.24)
  double dt;             // the step the particles are advected over
  bool varying;          // FLIP shares differ: gather the dissipated residual into `sum`
};

// Sums over one particle's stencil, built row by row (x), then over y, then z:
//   v = sum w v_i; M_c = sum w v_i (offset along axis c: i, j or k) for the APIC affine velocity;
//   G_c = sum (d w / d x_c) v_i for the velocity gradient; v_old = sum w v_i^old for FLIP.
struct StencilSums {
  Vec3 v = Vec3::Zero(), Mx = Vec3::Zero(), My = Vec3::Zero(), Mz = Vec3::Zero();
  Vec3 Gx = Vec3::Zero(), Gy = Vec3::Zero(), Gz = Vec3::Zero(), v_old = Vec3::Zero();
};

// Both are forced inline into the gather loop: as calls, the sums went through memory and the unused
// ones were no longer dropped (the tear's g2p stage took 1.2x as long).
template <class Stencil, class Flip, class Affine, class Grad>
[[gnu::always_inline]] inline StencilSums sum_stencil(const Stencil& st, const uint32_t* nodes, const GatherInputs& g, Flip flip, Affine affine,
                        Grad grad) {
  double wx[3], wy[3], wz[3], dwx[3], dwy[3], dwz[3];
  load_weights(st.w, st.dw, wx, wy, wz, dwx, dwy, dwz);
  const Vec3* const velocity = g.velocity;
  const Vec3* const momentum = g.momentum;
  const double* const mass = g.mass;
  StencilSums o;
  for (int k = 0; k < 3; ++k) {
    Vec3 Pk = Vec3::Zero(), Qk = Vec3::Zero(), Rk = Vec3::Zero(), Bk = Vec3::Zero(), Ck = Vec3::Zero(),
         Ok = Vec3::Zero();
    for (int j = 0; j < 3; ++j) {
      const uint32_t* row = nodes + 3 * j + 9 * k;
      const Vec3 &v0 = velocity[row[0]], &v1 = velocity[row[1]], &v2 = velocity[row[2]];
      const Vec3 t1 = wx[1] * v1, t2 = wx[2] * v2;
      const Vec3 P = wx[0] * v0 + t1 + t2;  // sum_i wx_i v_i
      const double wyj = wy[j];
      Pk += wyj * P;
      if (affine) {
        Qk += wyj * (t1 + 2.0 * t2);  // sum_i i wx_i v_i
        Rk += (static_cast<double>(j) * wyj) * P;
      }
      if (grad) {
        Bk += wyj * (dwx[0] * v0 + dwx[1] * v1 + dwx[2] * v2);
        Ck += dwy[j] * P;
      }
      if (flip) {
        // The node's velocity before this step's forces, colliders and contact: its p2g momentum / mass.
        Vec3 O = Vec3::Zero();
        for (int i = 0; i < 3; ++i)
          if (mass[row[i]] > 0) O += (wx[i] / mass[row[i]]) * momentum[row[i]];
        Ok += wyj * O;
      }
    }
    const double wzk = wz[k];
    o.v += wzk * Pk;
    if (affine) {
      o.Mx += wzk * Qk;
      o.My += wzk * Rk;
      o.Mz += (static_cast<double>(k) * wzk) * Pk;
    }
    if (grad) {
      o.Gx += wzk * Bk;
      o.Gy += wzk * Ck;
      o.Gz += dwz[k] * Pk;
    }
    if (flip) o.v_old += wzk * Ok;
  }
  return o;
}

// One particle's gather from its cached stencil `st` and node list: velocity (PIC plus its FLIP share of
// the residual), affine velocity, velocity gradient; compiled per combination of the optional outputs.
template <class Stencil, class Flip, class Affine, class Grad>
[[gnu::always_inline]] inline void gather_particle(const Stencil& st, const uint32_t* nodes, const GatherInputs& g, const ParticleSet& s, uint32_t p,
                     double share, ResidualSum& sum, Flip flip, Affine affine, Grad grad) {
  const StencilSums o = sum_stencil(st, nodes, g, flip, affine, grad);
  const Vec3& v = o.v;
  if (flip) {
    const Vec3 residual = s.velocity[p] - o.v_old;  // delta_p: the particle's velocity the grid did not carry
    if (g.varying && s.mass[p] > 0) {
      const double w = s.mass[p] * (1 - share);
      sum.residual += w * residual;
      sum.weight += w;
      sum.first += w * s.position[p];
      sum.second += w * s.position[p] * s.position[p].transpose();
      sum.angular += (s.mass[p] * share) * (s.position[p] + g.dt * v).cross(residual);
    }
    s.velocity[p] = v + share * residual;
    if (s.flip_part) s.flip_part[p] = share * residual;
  } else {
    if (s.flip_part) s.flip_part[p].setZero();
    s.velocity[p] = v;
  }
  if (affine) {
    // C = D^-1 sum w v_i (x_i - x_p)^T with x_i - x_p = d0 + dx (i, j, k) (thesis Eq. 2.25).
    Mat3 C;
    C.col(0) = g.inv_d * (st.d0[0] * v + g.dx * o.Mx);
    C.col(1) = g.inv_d * (st.d0[1] * v + g.dx * o.My);
    C.col(2) = g.inv_d * (st.d0[2] * v + g.dx * o.Mz);
    if (s.rigid_affine) C = (0.5 * (C - C.transpose())).eval();
    s.affine[p] = C;
  }
  if (grad) {
    Mat3 G;
    G.col(0) = o.Gx;
    G.col(1) = o.Gy;
    G.col(2) = o.Gz;
    s.velocity_gradient[p] = G;
  }
}

}  // namespace

void SparseGrid::transfer_to_particles(const std::vector<ParticleSet>& sets, double dt) const {
  const double inv_d = apic_inverse_d(dx_);
  // With one FLIP share r for every particle, the FLIP part m_p r (v_p - sum_i w_ip v_i^old) sums to zero
  // over all particles (it cancels against the p2g momentum sum_i m_i v_i^old), so linear momentum is
  // exactly that of the PIC update. With shares r_p that differ it does not: the dissipated part
  // m_p (1 - r_p) delta_p of the residual delta_p is gathered per block and its weighted mean added back to
  // the dissipating particles below.
  const bool varying = !sets.empty() && shares_vary(sets);
  std::vector<ResidualSum> block_sums(varying ? block_coords_.size() : 0);
  const GatherInputs inputs{velocity_.data(), momentum_.data(), mass_.data(), dx_, inv_d, dt, varying};
  // Gather: each particle reads its stencil; blocks are independent, so any order gives the same result.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, block_coords_.size(), 2), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b) {
      ResidualSum sum;
      for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
        const ParticleSet& s = sets[entries_[e].set];
        const uint32_t p = entries_[e].index;
        const double share = s.flip_share ? s.flip_share[p] : s.flip;
        with_flag(share > 0 || varying, [&](auto flip) {
          with_flag(s.affine != nullptr, [&](auto affine) {
            with_flag(s.velocity_gradient != nullptr,
                      [&](auto grad) { gather_particle(stencil_[e], entry_nodes(e), inputs, s, p, share, sum, flip, affine, grad); });
          });
        });
      }
      if (varying) block_sums[b] = sum;
    }
  });
  if (!varying) return;
  // Blocks summed in block order: the same result for any thread count.
  ResidualSum total;
  for (const ResidualSum& b : block_sums) total.add(b);
  if (total.weight <= 0) return;
  // v_p <- v_PIC + r_p delta_p + g_p with g_p = (1 - r_p) (mean + omega x (x_p - x_c)) on the dissipating
  // particles, x_c the centre of their weights.
  //  - Linear momentum: sum_p m_p v_p = sum_p m_p v_PIC + sum_p m_p delta_p (the rotation sums to zero about
  //    x_c), and the last sum is zero.
  //  - Angular momentum: APIC keeps it through p2g, the grid update and g2p (Jiang et al. 2015) when the
  //    particles then move with v_PIC. Here they move with v_PIC + g_p, and what is left after the step
  //    is sum m_p (x_p + dt v_PIC) x r_p delta_p + sum m_p x_p x g_p (exact for shares 0 and 1, where
  //    g_p x r_p delta_p vanishes). omega makes it zero: I omega = -(angular + first x mean), I the inertia
  //    of the weights about x_c. Without it a spinning cut sheet lost 4.3e-3 of its angular momentum in
  //    400 steps. Weights on a line or a point have no inertia about it: then no rotation.
  const Vec3 mean = total.residual / total.weight;
  const Vec3 centre = total.first / total.weight;
  const Mat3 spread = total.second - total.weight * centre * centre.transpose();
  const Vec3 omega = core::rotation_for(spread, -(total.angular + total.first.cross(mean)));
  tbb::parallel_for(tbb::blocked_range<size_t>(0, block_coords_.size(), 2), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b)
      for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
        const ParticleSet& s = sets[entries_[e].set];
        const uint32_t p = entries_[e].index;
        const double share = s.flip_share ? s.flip_share[p] : s.flip;
        if (share < 1) s.velocity[p] += (1 - share) * (mean + omega.cross(s.position[p] - centre));
      }
  });
}

}  // namespace shellfrac::mpm
