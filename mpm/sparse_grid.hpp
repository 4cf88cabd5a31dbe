#pragma once
#include <array>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

#include "mpm/bspline_weights.hpp"
#include "mpm/particle_set.hpp"
#include "mpm/phantom_nodes.hpp"

namespace shellfrac::mpm {

// A particle the grid cannot place: non-finite position, or too far out for the grid spacing.
class GridError : public std::domain_error {
 public:
  GridError(const std::string& what, size_t set, size_t particle)
      : std::domain_error(what), set_(set), particle_(particle) {}
  size_t set() const { return set_; }
  size_t particle() const { return particle_; }

 private:
  size_t set_, particle_;
};

// A block-sparse background grid: nodes exist only in 4x4x4 blocks that particles touch, so memory
// follows the particles, not the bounding box. Nodes sit at integer multiples of dx.
//
// Transfers are deterministic and thread-count independent: particles are binned per block in a fixed
// order, and blocks scatter in 8 parity colours; two blocks of one colour never write the same node, so a
// colour runs in parallel without atomics and every node sums its contributions in the same order.
class SparseGrid {
 public:
  static constexpr int kBlock = 4;
  static constexpr int kBlockNodes = kBlock * kBlock * kBlock;

  explicit SparseGrid(double dx);
  double dx() const { return dx_; }

  // Activates the blocks the particles' quadratic stencils touch, bins the particles, caches every
  // particle's weights and stencil nodes, and zeroes every node. Call once per step before the transfers,
  // with the sets the transfers will use; the transfers use the cached weights, so positions must not
  // change between rebuild() and transfer_to_particles() (velocities, masses, forces and stresses may).
  void rebuild(const std::vector<ParticleSet>& sets);
  // Steps rebuild() keeps a block layout while it still holds every particle's stencil, before it builds
  // one afresh (0: afresh every step, as before; the results are the same bits either way).
  static constexpr int kDefaultLayoutReuse = 16;
  void set_layout_reuse(int steps) { layout_reuse_ = steps; }
  // How rebuild() went, counted over the grid's life: the kept layout with the bins of the step before
  // (nobody changed block); the kept layout with the particles binned again (some did); the kept layout
  // binned from scratch (the particle sets changed); a new layout.
  struct RebuildCounts {
    size_t kept_bins = 0, rebinned = 0, kept_layout_rebinned_afresh = 0, fresh_layouts = 0;
  };
  const RebuildCounts& rebuild_counts() const { return counts_; }

  // Particle to grid: mass and momentum (thesis Eq. 2.15, 2.16; APIC Eq. 2.23 when a set has affine).
  void transfer_mass_momentum(const std::vector<ParticleSet>& sets);
  // Adds Lagrangian particle forces (w_ip f_p) and Eulerian stress terms (-S_p grad w_ip) to the nodes.
  void transfer_forces(const std::vector<ParticleSet>& sets);
  // v_i = ((m v)_i + dt f_i) / m_i + dt g on every node with mass (thesis Eq. 2.19).
  void update_velocities(double dt, const Vec3& gravity);
  // Grid to particle: PIC velocity (Eq. 2.20), APIC affine (Eq. 2.25) and velocity gradient if asked.
  // `dt` is the step the particles are then advected over with their grid velocity (v_p minus its FLIP
  // part); with FLIP shares that differ, the correction that keeps momentum uses it (see the .cpp).
  void transfer_to_particles(const std::vector<ParticleSet>& sets, double dt = 0) const;

  // Phantom copies (thesis sec. 4.7.1): after rebuild(), before the transfers. Copies are appended to the
  // node storage (indices >= num_grid_nodes()), so velocity updates and colliders treat them like nodes;
  // the transfers send a particle's contribution to the copy its stencil row names. See phantom_nodes.hpp.
  void set_phantom_copies(const PhantomLayout& layout);
  size_t num_grid_nodes() const { return grid_nodes_; }
  size_t num_phantom_copies() const { return mass_.size() - grid_nodes_; }
  // The grid node a copy belongs to; the node itself for ordinary nodes.
  size_t parent_node(size_t node) const { return node < grid_nodes_ ? node : copy_parent_[node - grid_nodes_]; }
  // Per copy: sum of w m x (centre of mass times mass) and sum of m grad w (mass gradient), for the
  // contact normals of thesis Eq. 4.22.
  const Vec3& copy_mass_position(size_t copy) const { return copy_mass_position_[copy]; }
  const Vec3& copy_mass_gradient(size_t copy) const { return copy_mass_gradient_[copy]; }
  Vec3& node_momentum_mut(size_t node) { return momentum_[node]; }
  // Node indices of the 27 stencil nodes of a particle at x, in the order i + 3 j + 9 k (after rebuild).
  std::array<uint32_t, 27> stencil_nodes(const Vec3& x) const;
  // The same for particle p of set s as rebuild() found it, from the per-particle cache (grid nodes only:
  // phantom redirections are not applied). Valid until the next rebuild.
  const uint32_t* particle_stencil(size_t set, size_t p) const {
    return stencil_[entry_of_[set_first_[set] + p]].node;
  }

  // The particles whose stencils may reach a node of one of `blocks` (block = node / kBlockNodes), as
  // set << 32 | index in ascending order: those binned in each block or the block before it along any
  // axis, since a stencil spans its base node's block and the next one per axis. A superset: callers test
  // the stencils themselves. Valid until the next rebuild.
  std::vector<uint64_t> particles_near_blocks(const std::vector<uint32_t>& blocks) const;
  // Changes whenever a rebuild activates other blocks than the rebuild before it (and differs between
  // grids): while it stays the same, node indices mean the same nodes, and a particle on the same base
  // node has the same stencil.
  uint64_t layout_version() const { return layout_version_; }

  // Node storage, index = block * 64 + local, then the phantom copies. Velocities are those of
  // update_velocities() (zero on nodes without mass); rebuild() leaves them to it.
  size_t num_nodes() const { return mass_.size(); }
  size_t num_blocks() const { return block_coords_.size(); }
  Vec3 node_position(size_t node) const;
  double node_mass(size_t node) const { return mass_[node]; }
  const Vec3& node_momentum(size_t node) const { return momentum_[node]; }
  const Vec3& node_force(size_t node) const { return force_[node]; }
  Vec3& node_velocity(size_t node) { return velocity_[node]; }
  const Vec3& node_velocity(size_t node) const { return velocity_[node]; }
  // Flat index of node (i, j, k), or -1 when its block is inactive.
  long node_index(int i, int j, int k) const;

 private:
  struct Entry {
    uint32_t set;
    uint32_t index;
  };
  using BlockCoord = Eigen::Vector3i;
  // What every transfer of a step needs of one particle, computed once in rebuild(): the particle does
  // not move between p2g and g2p. Weights per axis (thesis Eq. 2.10, 2.11; the 3-D weight is their product,
  // Eq. 2.14), the offset of stencil node (0,0,0) from the particle, and the 27 node indices.
  struct ParticleStencil {
    double w[3][3];   // [axis][node offset 0..2]
    double dw[3][3];  // derivatives, already divided by dx
    double d0[3];     // x_base - x_p
    uint32_t node[27];  // grid node of entry i + 3 j + 9 k
  };

  static uint64_t pack(int bx, int by, int bz);
  // Weights and grid nodes of a particle at x whose base node lies in block b.
  void fill_stencil(uint32_t block, const Vec3& x, ParticleStencil& st) const;
  void fill_stencil(uint32_t block, const StencilWeights& sw, const Vec3& x, ParticleStencil& st) const;
  // Node list the transfers use for entry e: the cached grid nodes, or the phantom row naming copies.
  const uint32_t* entry_nodes(size_t e) const {
    const int32_t row = entry_phantom_row_.empty() ? -1 : entry_phantom_row_[e];
    return row < 0 ? stencil_[e].node : &phantom_stencil_[static_cast<size_t>(row) * 27];
  }
  // Runs fn(block) over all blocks, colour by colour, blocks of one colour in parallel.
  template <class Fn>
  void for_blocks_coloured(Fn&& fn) const;

  double dx_, inv_dx_;
  // Index of the block with this key, or -1 (binary search in the sorted active keys).
  int32_t find_block(uint64_t key) const;

  // Sorts the particles' block keys into the active blocks (with their forward neighbours), the block
  // coordinates and neighbour table; a new layout version when the keys changed.
  void build_layout(const std::vector<uint64_t>& particle_keys);
  // The key of the block holding the base node of a particle at x; false if x is not finite or out of range.
  bool base_key(const Vec3& x, uint64_t& key) const;
  // A cheaper test than base_key()'s for the common case: finite and well inside the key range.
  bool well_inside_range(const Vec3& x) const;
  // True if `block` is active and so are its forward neighbours, which a stencil based in it reaches.
  bool holds_stencils_of(int32_t block) const;
  // rebuild() on the kept layout with the same particle sets: new stencils in place, and the particles
  // binned again only if some changed block. False if one left the layout or cannot be placed.
  bool refresh_kept_layout(const std::vector<ParticleSet>& sets);
  // rebuild() from the particle keys: on the kept layout if `keep` and it holds them, else a new layout.
  void rebuild_afresh(const std::vector<ParticleSet>& sets, const std::vector<size_t>& first, bool keep);
  // Entries, bins, the (set, particle) -> entry map and the block colours from each particle's block.
  void bin_particles(const std::vector<uint32_t>& block_of_particle);
  void zero_nodes();
  int layout_reuse_ = kDefaultLayoutReuse;
  int reused_layouts_ = 0;
  RebuildCounts counts_;

  std::vector<uint64_t> active_keys_;  // sorted; block b has key active_keys_[b]
  std::vector<uint64_t> previous_keys_;  // active_keys_ of the rebuild before
  uint64_t layout_version_ = 0;
  std::vector<BlockCoord> block_coords_;
  std::vector<std::array<int32_t, 8>> forward_neighbours_;  // block + {0,1}^3, -1 if inactive
  std::vector<uint32_t> bin_offsets_;                        // CSR of particle entries per block
  std::vector<Entry> entries_;
  std::vector<ParticleStencil> stencil_;  // per entry
  std::vector<size_t> set_first_;         // flat number of particle 0 of each set
  std::vector<uint32_t> entry_of_;        // flat (set, particle) number -> entry
  // refresh_kept_layout(): per entry, whether its particle left its block; the map and stencils before.
  std::vector<unsigned char> moved_;
  std::vector<uint32_t> previous_entry_of_;
  std::vector<ParticleStencil> previous_stencil_;
  std::vector<std::vector<uint32_t>> colour_blocks_;
  std::vector<double> mass_;
  std::vector<Vec3> momentum_, force_, velocity_;
  // Phantom copies and the per-particle stencil redirections.
  size_t grid_nodes_ = 0;
  std::vector<uint32_t> copy_parent_;
  std::vector<Vec3> copy_mass_position_, copy_mass_gradient_;
  std::vector<int32_t> entry_phantom_row_;  // per entry: row of phantom_stencil_, or -1; empty = none
  std::vector<uint32_t> phantom_stencil_;   // rows x 27 target node indices
};

}  // namespace shellfrac::mpm
