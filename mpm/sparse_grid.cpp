#include "mpm/sparse_grid.hpp"

#include <tbb/parallel_for.h>

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
  const size_t b = node / kBlockNodes;
  const int l = static_cast<int>(node % kBlockNodes);
  const BlockCoord& c = block_coords_[b];
  return Vec3(c.x() * kBlock + (l & 3), c.y() * kBlock + ((l >> 2) & 3), c.z() * kBlock + (l >> 4)) * dx_;
}

long SparseGrid::node_index(int i, int j, int k) const {
  const int bx = floor_div4(i), by = floor_div4(j), bz = floor_div4(k);
  const auto it = block_of_key_.find(pack(bx, by, bz));
  if (it == block_of_key_.end()) return -1;
  const int local = (i - bx * kBlock) + kBlock * ((j - by * kBlock) + kBlock * (k - bz * kBlock));
  return static_cast<long>(it->second) * kBlockNodes + local;
}

void SparseGrid::rebuild(const std::vector<ParticleSet>& sets) {
  // 1. Block of every particle's base node.
  size_t total = 0;
  for (const auto& s : sets) total += s.count;
  std::vector<uint64_t> keys(total);
  entries_.resize(total);
  size_t e = 0;
  for (uint32_t si = 0; si < sets.size(); ++si) {
    const ParticleSet& s = sets[si];
    for (uint32_t p = 0; p < s.count; ++p, ++e) {
      const Vec3& x = s.position[p];
      if (!x.allFinite()) throw GridError("non-finite particle position", si, p);
      constexpr double kLimit = 4.0 * static_cast<double>(kKeyOffset - 2);  // nodes per axis half-range
      int base[3];
      for (int d = 0; d < 3; ++d) {
        const double b = std::floor(x[d] * inv_dx_ - 0.5);
        if (std::abs(b) > kLimit) throw GridError("particle position out of the grid's range", si, p);
        base[d] = static_cast<int>(b);
      }
      keys[e] = pack(floor_div4(base[0]), floor_div4(base[1]), floor_div4(base[2]));
      entries_[e] = {si, p};
    }
  }

  // 2. Active blocks: particle blocks and their forward neighbours (stencils reach base + 2),
  //    sorted by key so the block order is deterministic and spatially coherent.
  std::vector<uint64_t> occupied = keys;
  std::sort(occupied.begin(), occupied.end());
  occupied.erase(std::unique(occupied.begin(), occupied.end()), occupied.end());
  std::vector<uint64_t> active;
  active.reserve(occupied.size() * 8);
  for (uint64_t k : occupied) {
    const Eigen::Vector3i c = unpack(k);
    for (int d = 0; d < 8; ++d) active.push_back(pack(c.x() + (d & 1), c.y() + ((d >> 1) & 1), c.z() + (d >> 2)));
  }
  std::sort(active.begin(), active.end());
  active.erase(std::unique(active.begin(), active.end()), active.end());

  block_of_key_.clear();
  block_of_key_.reserve(active.size() * 2);
  block_coords_.resize(active.size());
  for (uint32_t b = 0; b < active.size(); ++b) {
    block_of_key_.emplace(active[b], b);
    block_coords_[b] = unpack(active[b]);
  }
  forward_neighbours_.resize(active.size());
  for (uint32_t b = 0; b < active.size(); ++b) {
    const BlockCoord& c = block_coords_[b];
    for (int d = 0; d < 8; ++d) {
      const auto it = block_of_key_.find(pack(c.x() + (d & 1), c.y() + ((d >> 1) & 1), c.z() + (d >> 2)));
      forward_neighbours_[b][static_cast<size_t>(d)] = it == block_of_key_.end() ? -1 : static_cast<int32_t>(it->second);
    }
  }

  // 3. Bin particles per block (stable counting sort keeps set/particle order inside a block).
  std::vector<uint32_t> block_of_entry(total);
  bin_offsets_.assign(active.size() + 1, 0);
  for (size_t i = 0; i < total; ++i) {
    block_of_entry[i] = block_of_key_.find(keys[i])->second;
    ++bin_offsets_[block_of_entry[i] + 1];
  }
  for (size_t b = 0; b < active.size(); ++b) bin_offsets_[b + 1] += bin_offsets_[b];
  std::vector<Entry> sorted(total);
  std::vector<uint32_t> cursor(bin_offsets_.begin(), bin_offsets_.end() - 1);
  for (size_t i = 0; i < total; ++i) sorted[cursor[block_of_entry[i]]++] = entries_[i];
  entries_.swap(sorted);

  // 4. Parity colours of the blocks that hold particles.
  colour_blocks_.assign(8, {});
  for (uint32_t b = 0; b < active.size(); ++b) {
    if (bin_offsets_[b + 1] == bin_offsets_[b]) continue;
    const BlockCoord& c = block_coords_[b];
    colour_blocks_[static_cast<size_t>((c.x() & 1) | ((c.y() & 1) << 1) | ((c.z() & 1) << 2))].push_back(b);
  }

  // 5. Zeroed node storage.
  const size_t n = active.size() * kBlockNodes;
  mass_.assign(n, 0.0);
  momentum_.assign(n, Vec3::Zero());
  force_.assign(n, Vec3::Zero());
  velocity_.assign(n, Vec3::Zero());
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
      for_stencil(b, sw, [&](size_t node, int i, int j, int k) {
        const double w = sw.weight(i, j, k);
        mass_[node] += w * mp;
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
      for_stencil(b, sw, [&](size_t node, int i, int j, int k) {
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

void SparseGrid::transfer_to_particles(const std::vector<ParticleSet>& sets) const {
  const double inv_d = apic_inverse_d(dx_);
  // Gather: each particle reads its stencil; blocks are independent, so any order gives the same result.
  tbb::parallel_for(tbb::blocked_range<size_t>(0, block_coords_.size(), 2), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b) {
      for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
        const ParticleSet& s = sets[entries_[e].set];
        const uint32_t p = entries_[e].index;
        const Vec3& xp = s.position[p];
        const StencilWeights sw = stencil_weights(xp, inv_dx_);
        Vec3 v = Vec3::Zero();
        Mat3 C = Mat3::Zero(), grad = Mat3::Zero();
        for_stencil(static_cast<uint32_t>(b), sw, [&](size_t node, int i, int j, int k) {
          const Vec3& vi = velocity_[node];
          const double w = sw.weight(i, j, k);
          v += w * vi;
          if (s.affine) {
            const Vec3 xi(sw.ax[0].base + i, sw.ax[1].base + j, sw.ax[2].base + k);
            C += (w * inv_d) * vi * (xi * dx_ - xp).transpose();
          }
          if (s.velocity_gradient) grad += vi * sw.gradient(i, j, k).transpose();
        });
        s.velocity[p] = v;
        if (s.affine) s.affine[p] = C;
        if (s.velocity_gradient) s.velocity_gradient[p] = grad;
      }
    }
  });
}

}  // namespace shellfrac::mpm
