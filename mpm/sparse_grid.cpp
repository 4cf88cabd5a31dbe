#include "mpm/sparse_grid.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <stdexcept>
#include <string>

namespace shellfrac::mpm {

namespace {

constexpr int kKeyBits = 21;
constexpr int64_t kKeyOffset = int64_t{1} << (kKeyBits - 1);
constexpr uint64_t kKeyMask = (uint64_t{1} << kKeyBits) - 1;

int floor_div4(int v) { return v >= 0 ? v / 4 : -((-v + 3) / 4); }

Eigen::Vector3i unpack(uint64_t key) {
  return {static_cast<int>(static_cast<int64_t>((key >> (2 * kKeyBits)) & kKeyMask) - kKeyOffset),
          static_cast<int>(static_cast<int64_t>((key >> kKeyBits) & kKeyMask) - kKeyOffset),
          static_cast<int>(static_cast<int64_t>(key & kKeyMask) - kKeyOffset)};
}

// Axis offset d in {0,1,2} of a stencil node, relative to a base node at local coordinate l in [0,4):
// which block along the axis (0 = same, 1 = next) and the local coordinate there.
struct AxisSlot {
  int next_block;
  int local;
};

AxisSlot slot(int local_base, int d) {
  const int l = local_base + d;
  return l < SparseGrid::kBlock ? AxisSlot{0, l} : AxisSlot{1, l - SparseGrid::kBlock};
}

}  // namespace

SparseGrid::SparseGrid(double dx) : dx_(dx), inv_dx_(1.0 / dx) {
  if (!(dx > 0)) throw std::invalid_argument("grid spacing must be > 0");
}

uint64_t SparseGrid::pack(int bx, int by, int bz) {
  auto field = [](int v) {
    const int64_t s = int64_t{v} + kKeyOffset;
    if (s < 0 || s > static_cast<int64_t>(kKeyMask))
      throw std::domain_error("grid block coordinate out of range: the scene extends too far for the grid spacing");
    return static_cast<uint64_t>(s);
  };
  return (field(bx) << (2 * kKeyBits)) | (field(by) << kKeyBits) | field(bz);
}

Vec3 SparseGrid::node_position(size_t node) const {
  node = parent_node(node);
  const size_t b = node / kBlockNodes;
  const int l = static_cast<int>(node % kBlockNodes);
  const BlockCoord& c = block_coords_[b];
  return Vec3(c.x() * kBlock + (l & 3), c.y() * kBlock + ((l >> 2) & 3), c.z() * kBlock + (l >> 4)) * dx_;
}

long SparseGrid::node_index(int i, int j, int k) const {
  const int bx = floor_div4(i), by = floor_div4(j), bz = floor_div4(k);
  const int32_t b = find_block(pack(bx, by, bz));
  if (b < 0) return -1;
  const int local = (i - bx * kBlock) + kBlock * ((j - by * kBlock) + kBlock * (k - bz * kBlock));
  return static_cast<long>(b) * kBlockNodes + local;
}

void SparseGrid::rebuild(const std::vector<ParticleSet>& sets) {
  // 1. Block of every particle's base node (parallel; the first bad particle is reported, in order).
  std::vector<size_t> first(sets.size() + 1, 0);
  for (size_t si = 0; si < sets.size(); ++si) first[si + 1] = first[si] + sets[si].count;
  const size_t total = first.back();
  std::vector<uint64_t> keys(total);
  std::vector<unsigned char> bad(total, 0);
  entries_.resize(total);
  for (uint32_t si = 0; si < sets.size(); ++si) {
    const ParticleSet& s = sets[si];
    tbb::parallel_for(tbb::blocked_range<size_t>(0, s.count, 1024), [&](const tbb::blocked_range<size_t>& r) {
      constexpr double kLimit = 4.0 * static_cast<double>(kKeyOffset - 2);  // nodes per axis half-range
      for (size_t p = r.begin(); p != r.end(); ++p) {
        const size_t e = first[si] + p;
        entries_[e] = {si, static_cast<uint32_t>(p)};
        const Vec3& x = s.position[p];
        if (!x.allFinite()) {
          bad[e] = 1;
          continue;
        }
        int base[3];
        for (int d = 0; d < 3; ++d) {
          const double b = std::floor(x[d] * inv_dx_ - 0.5);
          if (std::abs(b) > kLimit) bad[e] = 2;
          base[d] = bad[e] ? 0 : static_cast<int>(b);
        }
        keys[e] = bad[e] ? 0 : pack(floor_div4(base[0]), floor_div4(base[1]), floor_div4(base[2]));
      }
    });
  }
  for (size_t e = 0; e < total; ++e)
    if (bad[e])
      throw GridError(bad[e] == 1 ? "non-finite particle position" : "particle position out of the grid's range",
                      entries_[e].set, entries_[e].index);

  // 2. Active blocks: particle blocks and their forward neighbours (stencils reach base + 2), as a
  //    sorted key list: the block order is deterministic and spatially coherent, and a binary search
  //    replaces a hash map.
  std::vector<uint64_t> occupied = keys;
  tbb::parallel_sort(occupied.begin(), occupied.end());
  occupied.erase(std::unique(occupied.begin(), occupied.end()), occupied.end());
  active_keys_.clear();
  active_keys_.reserve(occupied.size() * 8);
  for (uint64_t k : occupied) {
    const Eigen::Vector3i c = unpack(k);
    for (int d = 0; d < 8; ++d) active_keys_.push_back(pack(c.x() + (d & 1), c.y() + ((d >> 1) & 1), c.z() + (d >> 2)));
  }
  tbb::parallel_sort(active_keys_.begin(), active_keys_.end());
  active_keys_.erase(std::unique(active_keys_.begin(), active_keys_.end()), active_keys_.end());
  const size_t num_blocks = active_keys_.size();

  block_coords_.resize(num_blocks);
  forward_neighbours_.resize(num_blocks);
  tbb::parallel_for(size_t{0}, num_blocks, [&](size_t b) {
    const BlockCoord c = unpack(active_keys_[b]);
    block_coords_[b] = c;
    for (int d = 0; d < 8; ++d)
      forward_neighbours_[b][static_cast<size_t>(d)] = find_block(pack(c.x() + (d & 1), c.y() + ((d >> 1) & 1), c.z() + (d >> 2)));
  });

  // 3. Bin particles per block (stable counting sort keeps set/particle order inside a block).
  std::vector<uint32_t> block_of_entry(total);
  tbb::parallel_for(size_t{0}, total, [&](size_t i) { block_of_entry[i] = static_cast<uint32_t>(find_block(keys[i])); });
  bin_offsets_.assign(num_blocks + 1, 0);
  for (size_t i = 0; i < total; ++i) ++bin_offsets_[block_of_entry[i] + 1];
  for (size_t b = 0; b < num_blocks; ++b) bin_offsets_[b + 1] += bin_offsets_[b];
  std::vector<Entry> sorted(total);
  std::vector<uint32_t> cursor(bin_offsets_.begin(), bin_offsets_.end() - 1);
  for (size_t i = 0; i < total; ++i) sorted[cursor[block_of_entry[i]]++] = entries_[i];
  entries_.swap(sorted);

  // 4. Parity colours of the blocks that hold particles.
  colour_blocks_.assign(8, {});
  for (uint32_t b = 0; b < num_blocks; ++b) {
    if (bin_offsets_[b + 1] == bin_offsets_[b]) continue;
    const BlockCoord& c = block_coords_[b];
    colour_blocks_[static_cast<size_t>((c.x() & 1) | ((c.y() & 1) << 1) | ((c.z() & 1) << 2))].push_back(b);
  }

  // 5. Zeroed node storage (parallel: it is the largest memory traffic of the rebuild), no phantoms yet.
  const size_t n = num_blocks * kBlockNodes;
  grid_nodes_ = n;
  copy_parent_.clear();
  copy_mass_position_.clear();
  copy_mass_gradient_.clear();
  phantom_row_.clear();
  phantom_stencil_.clear();
  mass_.resize(n);
  momentum_.resize(n);
  force_.resize(n);
  velocity_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    std::fill(mass_.begin() + static_cast<long>(r.begin()), mass_.begin() + static_cast<long>(r.end()), 0.0);
    for (size_t i = r.begin(); i != r.end(); ++i) {
      momentum_[i].setZero();
      force_[i].setZero();
      velocity_[i].setZero();
    }
  });
}

std::array<uint32_t, 27> SparseGrid::stencil_nodes(const Vec3& x) const {
  const StencilWeights sw = stencil_weights(x, inv_dx_);
  const int32_t b = find_block(pack(floor_div4(sw.ax[0].base), floor_div4(sw.ax[1].base), floor_div4(sw.ax[2].base)));
  if (b < 0) throw std::logic_error("stencil_nodes: position outside the active grid (rebuild first)");
  std::array<uint32_t, 27> nodes{};
  for_stencil(static_cast<uint32_t>(b), sw,
              [&](size_t node, int i, int j, int k) { nodes[static_cast<size_t>(i + 3 * j + 9 * k)] = static_cast<uint32_t>(node); });
  return nodes;
}

void SparseGrid::set_phantom_copies(const PhantomLayout& layout) {
  const size_t copies = layout.copy_parent.size();
  copy_parent_ = layout.copy_parent;
  copy_mass_position_.assign(copies, Vec3::Zero());
  copy_mass_gradient_.assign(copies, Vec3::Zero());
  mass_.resize(grid_nodes_ + copies, 0.0);
  momentum_.resize(grid_nodes_ + copies, Vec3::Zero());
  force_.resize(grid_nodes_ + copies, Vec3::Zero());
  velocity_.resize(grid_nodes_ + copies, Vec3::Zero());
  phantom_row_ = layout.particle_row;
  phantom_stencil_.resize(layout.stencil_copy.size());
  // Rows name copies by number; store final node indices (a grid node for -1, else grid_nodes_ + copy).
  for (size_t r = 0; r < layout.stencil_copy.size() / 27; ++r)
    for (size_t k = 0; k < 27; ++k) {
      const int32_t c = layout.stencil_copy[r * 27 + k];
      phantom_stencil_[r * 27 + k] = c < 0 ? layout.stencil_node[r * 27 + k] : static_cast<uint32_t>(grid_nodes_ + static_cast<size_t>(c));
    }
}

int32_t SparseGrid::find_block(uint64_t key) const {
  const auto it = std::lower_bound(active_keys_.begin(), active_keys_.end(), key);
  return it != active_keys_.end() && *it == key ? static_cast<int32_t>(it - active_keys_.begin()) : -1;
}

template <class Fn>
void SparseGrid::for_stencil(uint32_t block, const StencilWeights& sw, Fn&& fn) const {
  const BlockCoord& c = block_coords_[block];
  const int lx = sw.ax[0].base - c.x() * kBlock, ly = sw.ax[1].base - c.y() * kBlock,
            lz = sw.ax[2].base - c.z() * kBlock;
  const auto& nb = forward_neighbours_[block];
  for (int k = 0; k < 3; ++k) {
    const AxisSlot sz = slot(lz, k);
    for (int j = 0; j < 3; ++j) {
      const AxisSlot sy = slot(ly, j);
      for (int i = 0; i < 3; ++i) {
        const AxisSlot sx = slot(lx, i);
        const int32_t b = nb[static_cast<size_t>(sx.next_block | (sy.next_block << 1) | (sz.next_block << 2))];
        const size_t node = static_cast<size_t>(b) * kBlockNodes +
                            static_cast<size_t>(sx.local + kBlock * (sy.local + kBlock * sz.local));
        fn(node, i, j, k);
      }
    }
  }
}

template <class Fn>
void SparseGrid::for_blocks_coloured(Fn&& fn) const {
  for (const auto& blocks : colour_blocks_)
    tbb::parallel_for(tbb::blocked_range<size_t>(0, blocks.size(), 4), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) fn(blocks[i]);
    });
}

void SparseGrid::transfer_mass_momentum(const std::vector<ParticleSet>& sets) {
  for_blocks_coloured([&](uint32_t b) {
    for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
      const ParticleSet& s = sets[entries_[e].set];
      const uint32_t p = entries_[e].index;
      const Vec3& xp = s.position[p];
      const double mp = s.mass[p];
      const Vec3 mv = mp * s.velocity[p];
      const StencilWeights sw = stencil_weights(xp, inv_dx_);
      const Mat3* C = s.affine ? &s.affine[p] : nullptr;
      const uint32_t si = entries_[e].set;
      for_stencil(b, sw, [&](size_t grid_node, int i, int j, int k) {
        const size_t node = target(si, p, grid_node, i, j, k);
        const double w = sw.weight(i, j, k);
        mass_[node] += w * mp;
        if (node >= grid_nodes_) {  // phantom copy: data for its contact normal (thesis Eq. 4.22)
          copy_mass_position_[node - grid_nodes_] += (w * mp) * xp;
          copy_mass_gradient_[node - grid_nodes_] += mp * sw.gradient(i, j, k);
        }
        if (C) {
          const Vec3 xi(sw.ax[0].base + i, sw.ax[1].base + j, sw.ax[2].base + k);
          momentum_[node] += w * (mv + mp * (*C) * (xi * dx_ - xp));
        } else {
          momentum_[node] += w * mv;
        }
      });
    }
  });
}

void SparseGrid::transfer_forces(const std::vector<ParticleSet>& sets) {
  const double inv_d = apic_inverse_d(dx_);
  for_blocks_coloured([&](uint32_t b) {
    for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
      const ParticleSet& s = sets[entries_[e].set];
      if (!s.force && !s.stress) continue;
      const uint32_t p = entries_[e].index;
      const StencilWeights sw = stencil_weights(s.position[p], inv_dx_);
      const Vec3& xp = s.position[p];
      const uint32_t si = entries_[e].set;
      for_stencil(b, sw, [&](size_t grid_node, int i, int j, int k) {
        const size_t node = target(si, p, grid_node, i, j, k);
        if (s.force) force_[node] += sw.weight(i, j, k) * s.force[p];
        if (!s.stress) return;
        if (s.mls_force) {
          const Vec3 xi(sw.ax[0].base + i, sw.ax[1].base + j, sw.ax[2].base + k);
          force_[node] -= (inv_d * sw.weight(i, j, k)) * (s.stress[p] * (xi * dx_ - xp));
        } else {
          force_[node] -= s.stress[p] * sw.gradient(i, j, k);
        }
      });
    }
  });
}

void SparseGrid::update_velocities(double dt, const Vec3& gravity) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, mass_.size(), 1024), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t n = r.begin(); n != r.end(); ++n) {
      if (mass_[n] > 0)
        velocity_[n] = (momentum_[n] + dt * force_[n]) / mass_[n] + dt * gravity;
      else
        velocity_[n].setZero();
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

// Mass-weighted sums of one block's dissipated FLIP residual: sum m_p (1 - r_p) delta_p and sum m_p (1 - r_p).
struct ResidualSum {
  Vec3 residual = Vec3::Zero();
  double weight = 0;
};

}  // namespace

void SparseGrid::transfer_to_particles(const std::vector<ParticleSet>& sets) const {
  const double inv_d = apic_inverse_d(dx_);
  // With one FLIP share r for every particle, the FLIP part m_p r (v_p - sum_i w_ip v_i^old) sums to zero
  // over all particles (it cancels against the p2g momentum sum_i m_i v_i^old), so linear momentum is
  // exactly that of the PIC update. With shares r_p that differ it does not: the dissipated part
  // m_p (1 - r_p) delta_p of the residual delta_p is gathered per block and its weighted mean added back to
  // the dissipating particles below.
  const bool varying = !sets.empty() && shares_vary(sets);
  std::vector<ResidualSum> block_sums(varying ? block_coords_.size() : 0);
  // Gather: each particle reads its stencil; blocks are independent, so any order gives the same result.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, block_coords_.size(), 2), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b) {
      ResidualSum sum;
      for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
        const ParticleSet& s = sets[entries_[e].set];
        const uint32_t p = entries_[e].index;
        const Vec3& xp = s.position[p];
        const StencilWeights sw = stencil_weights(xp, inv_dx_);
        Vec3 v = Vec3::Zero(), v_old = Vec3::Zero();
        Mat3 C = Mat3::Zero(), grad = Mat3::Zero();
        const uint32_t si = entries_[e].set;
        const double share = s.flip_share ? s.flip_share[p] : s.flip;
        const bool flip = share > 0 || varying;
        for_stencil(static_cast<uint32_t>(b), sw, [&](size_t grid_node, int i, int j, int k) {
          const size_t node = target(si, p, grid_node, i, j, k);
          const Vec3& vi = velocity_[node];
          const double w = sw.weight(i, j, k);
          v += w * vi;
          // The node's velocity before this step's forces, colliders and contact: its p2g momentum / mass.
          if (flip && mass_[node] > 0) v_old += (w / mass_[node]) * momentum_[node];
          if (s.affine) {
            const Vec3 xi(sw.ax[0].base + i, sw.ax[1].base + j, sw.ax[2].base + k);
            C += (w * inv_d) * vi * (xi * dx_ - xp).transpose();
          }
          if (s.velocity_gradient) grad += vi * sw.gradient(i, j, k).transpose();
        });
        if (flip) {
          const Vec3 residual = s.velocity[p] - v_old;  // delta_p: the particle's velocity the grid did not carry
          if (varying && s.mass[p] > 0) {
            sum.residual += (s.mass[p] * (1 - share)) * residual;
            sum.weight += s.mass[p] * (1 - share);
          }
          s.velocity[p] = v + share * residual;
        } else {
          s.velocity[p] = v;
        }
        if (s.affine) s.affine[p] = C;
        if (s.velocity_gradient) s.velocity_gradient[p] = grad;
      }
      if (varying) block_sums[b] = sum;
    }
  });
  if (!varying) return;
  // Blocks summed in block order: the same result for any thread count.
  ResidualSum total;
  for (const ResidualSum& b : block_sums) {
    total.residual += b.residual;
    total.weight += b.weight;
  }
  if (total.weight <= 0) return;
  // v_p <- v_PIC + r_p delta_p + (1 - r_p) mean: then sum_p m_p v_p = sum_p m_p v_PIC + sum_p m_p delta_p,
  // and the last sum is zero.
  const Vec3 mean = total.residual / total.weight;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, block_coords_.size(), 2), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b)
      for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
        const ParticleSet& s = sets[entries_[e].set];
        const uint32_t p = entries_[e].index;
        const double share = s.flip_share ? s.flip_share[p] : s.flip;
        if (share < 1) s.velocity[p] += (1 - share) * mean;
      }
  });
}

}  // namespace shellfrac::mpm
