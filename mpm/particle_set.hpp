#pragma once
#include <cstddef>

#include "mpm/bspline_weights.hpp"

namespace shellfrac::mpm {

// A view of one kind of particles that exchanges mass and momentum with the grid (thesis Types I, II,
// III). The arrays belong to the caller (structure of arrays); optional ones may be null.
struct ParticleSet {
  size_t count = 0;
  const Vec3* position = nullptr;
  Vec3* velocity = nullptr;         // read by p2g, written by g2p
  const double* mass = nullptr;
  // Lagrangian force per particle, spread to the nodes with the transfer weights w_ip
  // (the generalized control-point force of thesis Eq. 4.8).
  const Vec3* force = nullptr;
  // Eulerian stress term per particle: node i receives -S_p grad w_ip (thesis Eq. 2.17 with
  // S_p = V_p^0 P F^T).
  const Mat3* stress = nullptr;
  // With the MLS-MPM force form (thesis Eq. 2.24) node i receives -D^-1 S_p (x_i - x_p) w_ip instead.
  bool mls_force = false;
  // APIC affine velocity C_p (thesis Eq. 2.23, 2.25): read in p2g and written in g2p when non-null.
  Mat3* affine = nullptr;
  // With `affine`: g2p keeps only the skew (rotational) part of C_p, the rigid-body PIC (RPIC) of Jiang
  // et al. 2015. It keeps angular momentum and rigid rotation like APIC, and damps the stretching and
  // shearing affine modes like PIC.
  bool rigid_affine = false;
  // Grid velocity gradient sum_i v_i grad w_ip^T at the particle, written in g2p when non-null.
  Mat3* velocity_gradient = nullptr;
  // FLIP share in [0, 1] of the velocity update in g2p: v_p <- v_PIC + flip (v_p - sum_i w_ip v_i^old),
  // i.e. the particle keeps this share of its own velocity and adds the grid's velocity change
  // (Brackbill's FLIP blended with PIC; with affine set, the affine-FLIP of Fei et al. 2021). 0 = PIC/APIC.
  double flip = 0.0;
  // Per-particle FLIP share, overriding `flip` when set (the adaptive transfer, sim/transfer_shares.hpp).
  // When the shares of the particles differ, g2p adds to each particle (1 - r_p) times the weighted mean
  // residual so that linear momentum stays exactly that of PIC (mpm/sparse_grid.cpp).
  const double* flip_share = nullptr;
  // The FLIP part r_p delta_p of the new velocity (the share of the particle's own velocity that the grid
  // did not carry), written in g2p when non-null; zero for PIC/APIC particles. The caller advects with
  // v_p minus it, i.e. with the grid's velocity (Fei et al. 2021): moved by their own velocity, FLIP
  // particles let the velocity modes the grid cannot see displace them, and those modes grow.
  Vec3* flip_part = nullptr;
};

}  // namespace shellfrac::mpm
