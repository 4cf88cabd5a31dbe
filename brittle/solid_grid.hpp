#pragma once
#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "mpm/colliders.hpp"

namespace shellfrac::brittle {

using GVec3 = Eigen::Vector3d;
using GMat3 = Eigen::Matrix3d;

// Per particle: which of the two velocity fields it belongs to at each of its 27 stencil nodes; bit
// (i + 3 j + 9 k) set means field 1 (thesis sec. 3.4.1). Zero for particles away from cracks.
using FieldMask = uint32_t;

// Mass and momentum of one field at one node; after update_velocities the momentum slot holds the
// velocity. 32-byte aligned: a node is one AVX register and never straddles a cache line.
struct alignas(32) GridNode {
  double m;
  double p[3];
};

// The particle arrays a transfer reads and writes (structure of arrays, owned by the caller).
struct SolidView {
  size_t count = 0;
  GVec3* x = nullptr;
  GVec3* v = nullptr;
  const double* m = nullptr;
  GMat3* C = nullptr;             // APIC / MLS affine velocity
  GMat3* F = nullptr;             // deformation gradient
  const GMat3* stress = nullptr;  // V^0 J sigma (Eq. 2.24)
  const FieldMask* mask = nullptr;         // null: single field
  const int32_t* near_slot = nullptr;      // index into near_normal, or -1 (only with mask)
  const GVec3* near_normal = nullptr;      // unit vector from the crack to the particle, material space
};

namespace detail {
template <class Node, class Real>
struct TransferGridOf;
using TransferGrid = TransferGridOf<GridNode, double>;
using ConstTransferGrid = TransferGridOf<const GridNode, const double>;
struct TransferKernels;
}  // namespace detail

struct FieldContactStats {
  size_t two_field_nodes = 0;  // nodes where both fields have mass
  size_t contact_nodes = 0;    // of those, nodes where the fields approached (Eq. 3.7)
};

// A dense background grid over the bounding box of one solid (brittle solids stay compact during a
// fracture run, so a box costs little and makes every stencil a fixed stride), with a second velocity
// field per node for the two sides of a crack (thesis sec. 3.4). Quadratic B-spline MLS-MPM transfers
// (thesis sec. 2.2.3) with the internal force folded into the momentum scatter.
//
// Deterministic for any thread count: particles are binned into slabs four nodes thick along the longest
// axis and scattered slab-parallel in two colours (slabs of one colour never write the same node);
// within a slab particles go in index order.
class SolidGrid {
 public:
  explicit SolidGrid(double dx);
  double dx() const { return dx_; }

  // Instruction set of the transfer kernels (brittle/solid_transfer.hpp). Auto, the default, takes AVX2
  // with FMA when the processor has both, else the build's baseline. Results differ between the two by
  // round-off only; for one choice they are the same for any thread count.
  enum class TransferIsa { Auto, Generic, Avx2 };
  // Returns false, keeping the current kernels, when the processor (or the build) lacks the set.
  bool set_transfer_isa(TransferIsa isa);
  const char* transfer_isa() const;

  // Sizes the node box to cover the stencils of the positions (and of `extra` points, e.g. ghost
  // particles), zeroes it and bins the particles. Throws NumericalError naming a particle with a
  // non-finite position, or when the box would exceed memory_limit bytes (with the estimate).
  void rebuild(const GVec3* x, size_t n, const std::vector<GVec3>& extra, bool two_fields, size_t memory_limit);

  // p2g (thesis Eq. 2.23, 2.24 as in Eq. 3.3-3.5 per field): node mass, and momentum
  // sum w (m v + (m C - dt D^-1 V^0 J sigma)(x_i - x_p)), i.e. (m v)_i + dt f_i^int in one pass. Near a
  // crack each particle also adds w m n_p (sign by field) to its nodes' crack normal.
  void transfer_to_grid(const SolidView& s, double dt);
  // External point forces through ghost particles (thesis Eq. 3.12): momentum += dt w_ig f_g, into the
  // field given per point (0 or 1).
  void add_point_forces(const std::vector<GVec3>& x, const std::vector<GVec3>& f, const std::vector<int>& field, double dt);
  // v = (m v)_i / m_i + dt g for both fields (Eq. 2.19).
  void update_velocities(double dt, const GVec3& gravity);
  // Eq. 3.6-3.7: where both fields have mass and approach along the crack normal, each field's normal
  // velocity is replaced by the centre-of-mass one; tangential motion is left free. Conserves momentum.
  FieldContactStats resolve_field_contact();
  void apply_colliders(const std::vector<mpm::Collider>& colliders, double t);
  // g2p: v_p = sum w v_i, C_p = D^-1 sum w v_i (x_i - x_p)^T (Eq. 2.20, 2.25), F <- (I + dt C) F
  // (Eq. 2.26), x <- x + dt v (Eq. 2.21).
  void transfer_to_particles(const SolidView& s, double dt) const;

  // Index of the node with integer coordinates (i, j, k), or -1 outside the box.
  long node_index(int i, int j, int k) const;
  GVec3 node_position(size_t index) const;
  size_t num_nodes() const { return field_[0].size(); }
  bool two_fields() const { return two_fields_; }
  const GridNode& node(int field, size_t index) const { return field_[field][index]; }
  GridNode& node(int field, size_t index) { return field_[field][index]; }
  GVec3 crack_normal(size_t index) const { return GVec3(normal_[index].n[0], normal_[index].n[1], normal_[index].n[2]); }
  const Eigen::Vector3i& lower() const { return lo_; }
  const Eigen::Vector3i& dims() const { return dims_; }
  // Index distance between neighbouring nodes along an axis (1, dims.x, dims.x dims.y).
  long stride(int axis) const { return axis == 0 ? 1 : axis == 1 ? stride_y_ : stride_z_; }
  // The node index of a particle's stencil corner (its base node), valid after rebuild.
  long base_index(const GVec3& x) const;
  // Index of the node nearest to x, or -1 outside the box.
  long nearest_node(const GVec3& x) const;
  // Runs fn(particle) over every binned particle, slab colour by colour, slabs of a colour in parallel
  // (the scatter order). Use for scatters of per-node quantities. Defined in brittle/solid_grid_impl.hpp.
  template <class Fn>
  void for_particles_coloured(Fn&& fn) const;
  // The same order a slab at a time: fn(slab) with the slab's particles at
  // slab_order_[slab_offsets_[slab], slab_offsets_[slab + 1]).
  template <class Fn>
  void for_slabs_coloured(Fn&& fn) const;
  // Slab s's particles (index order) as [slab_begin(s), slab_end(s)).
  const uint32_t* slab_begin(size_t slab) const { return slab_order_.data() + slab_offsets_[slab]; }
  const uint32_t* slab_end(size_t slab) const { return slab_order_.data() + slab_offsets_[slab + 1]; }
  // The per-particle kernels of the chosen instruction set (brittle/solid_transfer.hpp), for loops over
  // this grid that live elsewhere (the phase field's operator).
  const detail::TransferKernels& kernels() const { return *kernels_; }

 private:
  // rebuild's steps: the node box over [lo, hi] (refused above memory_limit) with zeroed nodes, and the
  // particles' slab order.
  void allocate_box(const GVec3& lo, const GVec3& hi, bool two_fields, size_t memory_limit);
  void bin_into_slabs(const GVec3* x, size_t n);
  // The crack normal of a node padded to four doubles (one vector in the kernels).
  struct alignas(32) NodeNormal {
    double n[4];
  };
  // The kernels' view of the grid: writable nodes for the scatter, read-only ones for the gather.
  detail::TransferGrid raw();
  detail::ConstTransferGrid raw() const;
  template <class Grid, class Fields, class Normals>
  Grid raw_of(Fields& field, Normals& normal) const;
  double dx_, inv_dx_;
  const detail::TransferKernels* kernels_;
  Eigen::Vector3i lo_ = Eigen::Vector3i::Zero(), dims_ = Eigen::Vector3i::Zero();
  long stride_y_ = 0, stride_z_ = 0;
  bool two_fields_ = false;
  int slab_axis_ = 0;
  std::vector<GridNode> field_[2];
  std::vector<NodeNormal> normal_;
  std::vector<uint32_t> slab_offsets_, slab_order_;
};

}  // namespace shellfrac::brittle

// The template member is defined in brittle/solid_grid_impl.hpp, included only by the .cpp files that
// call it: it uses TBB, which the public headers must not pull in.
