// The sparse grid's layout: active blocks, particle bins and the per-particle stencil cache rebuilt every
// step; the transfers that use them are in sparse_grid_transfers.cpp.
#include "mpm/sparse_grid.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
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

void SparseGrid::build_layout(const std::vector<uint64_t>& particle_keys) {
  std::vector<uint64_t> occupied = particle_keys;
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
  if (active_keys_ != previous_keys_) {
    static std::atomic<uint64_t> versions{0};  // unique across grids, so no other grid's number matches
    layout_version_ = ++versions;
    previous_keys_ = active_keys_;
  }
  const size_t num_blocks = active_keys_.size();
  block_coords_.resize(num_blocks);
  forward_neighbours_.resize(num_blocks);
  tbb::parallel_for(size_t{0}, num_blocks, [&](size_t b) {
    const BlockCoord c = unpack(active_keys_[b]);
    block_coords_[b] = c;
    for (int d = 0; d < 8; ++d)
      forward_neighbours_[b][static_cast<size_t>(d)] = find_block(pack(c.x() + (d & 1), c.y() + ((d >> 1) & 1), c.z() + (d >> 2)));
  });
}

bool SparseGrid::base_key(const Vec3& x, uint64_t& key) const {
  constexpr double kLimit = 4.0 * static_cast<double>(kKeyOffset - 2);  // nodes per axis half-range
  if (!x.allFinite()) return false;
  int base[3];
  for (int d = 0; d < 3; ++d) {
    const double b = std::floor(x[d] * inv_dx_ - 0.5);
    if (std::abs(b) > kLimit) return false;
    base[d] = static_cast<int>(b);
  }
  key = pack(floor_div4(base[0]), floor_div4(base[1]), floor_div4(base[2]));
  return true;
}

bool SparseGrid::well_inside_range(const Vec3& x) const {
  constexpr double kLimit = 4.0 * static_cast<double>(kKeyOffset - 4);  // a margin inside base_key's limit
  return x.allFinite() && std::abs(x.x() * inv_dx_) < kLimit && std::abs(x.y() * inv_dx_) < kLimit &&
         std::abs(x.z() * inv_dx_) < kLimit;
}

bool SparseGrid::holds_stencils_of(int32_t block) const {
  return block >= 0 && std::none_of(forward_neighbours_[static_cast<size_t>(block)].begin(),
                                    forward_neighbours_[static_cast<size_t>(block)].end(), [](int32_t n) { return n < 0; });
}

void SparseGrid::rebuild(const std::vector<ParticleSet>& sets) {
  std::vector<size_t> first(sets.size() + 1, 0);
  for (size_t si = 0; si < sets.size(); ++si) first[si + 1] = first[si] + sets[si].count;
  // Particles move a small part of a cell per step, so the block layout of the step before nearly always
  // still holds every particle's block and its forward neighbours (stencils reach base + 2). It is then
  // kept, for at most layout_reuse_ steps; after that it is built afresh, which drops blocks no particle
  // reaches any more. Kept blocks that no stencil reaches get no mass, so the transfers and every sum over
  // blocks give the same bits as a fresh layout.
  const bool keep = reused_layouts_ < layout_reuse_ && !active_keys_.empty();
  if (keep && first == set_first_) {
    if (refresh_kept_layout(sets))
      ++reused_layouts_;
    else
      rebuild_afresh(sets, first, false);  // a particle left the layout (or cannot be placed: reported there)
  } else {
    rebuild_afresh(sets, first, keep);
  }
  zero_nodes();
}

bool SparseGrid::refresh_kept_layout(const std::vector<ParticleSet>& sets) {
  // One pass in entry order, block by block in parallel: a particle still in the block it is binned in gets
  // its new stencil in place; one that left it is marked. Most steps nobody leaves, and the bins, the
  // entry order and the colours stay as they are.
  const size_t total = entries_.size();
  const size_t num_blocks = active_keys_.size();
  moved_.assign(total, 0);
  std::atomic<bool> placeable{true};
  std::atomic<size_t> movers{0};
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_blocks, 8), [&](const tbb::blocked_range<size_t>& r) {
    size_t left = 0;
    for (size_t b = r.begin(); b != r.end(); ++b)
      for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
        const Vec3& x = sets[entries_[e].set].position[entries_[e].index];
        if (!well_inside_range(x)) {
          placeable = false;  // the fresh path reports it, or places it if it is just inside the range
          return;
        }
        const StencilWeights sw = stencil_weights(x, inv_dx_);  // the key comes with the weights
        if (pack(floor_div4(sw.ax[0].base), floor_div4(sw.ax[1].base), floor_div4(sw.ax[2].base)) == active_keys_[b]) {
          fill_stencil(static_cast<uint32_t>(b), sw, x, stencil_[e]);
        } else {
          moved_[e] = 1;
          ++left;
        }
      }
    movers += left;
  });
  if (!placeable) return false;
  if (movers == 0) {
    ++counts_.kept_bins;
    return true;
  }

  // Some particles changed block: they need a block of the layout with all its forward neighbours, or the
  // layout is built afresh. Then the particles are binned again in the order a fresh layout bins them
  // (block, then set and index), the others' stencils are carried over and the movers' filled.
  std::vector<uint32_t> block_of_particle(total);
  for (size_t b = 0; b < num_blocks; ++b)
    for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
      const size_t flat = set_first_[entries_[e].set] + entries_[e].index;
      int32_t to = static_cast<int32_t>(b);
      if (moved_[e]) {
        uint64_t key = 0;
        base_key(sets[entries_[e].set].position[entries_[e].index], key);
        to = find_block(key);
        if (!holds_stencils_of(to)) return false;
      }
      block_of_particle[flat] = static_cast<uint32_t>(to);
    }
  ++counts_.rebinned;
  previous_entry_of_.swap(entry_of_);
  previous_stencil_.swap(stencil_);
  bin_particles(block_of_particle);
  stencil_.resize(total);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, num_blocks, 8), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b)
      for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
        const Entry& en = entries_[e];
        const uint32_t before = previous_entry_of_[set_first_[en.set] + en.index];
        if (moved_[before])
          fill_stencil(static_cast<uint32_t>(b), sets[en.set].position[en.index], stencil_[e]);
        else
          stencil_[e] = previous_stencil_[before];
      }
  });
  return true;
}

void SparseGrid::rebuild_afresh(const std::vector<ParticleSet>& sets, const std::vector<size_t>& first, bool keep) {
  // 1. Block of every particle's base node (parallel; the first bad particle is reported, in order).
  const size_t total = first.back();
  std::vector<uint64_t> keys(total);
  std::vector<unsigned char> bad(total, 0);
  for (uint32_t si = 0; si < sets.size(); ++si) {
    const ParticleSet& s = sets[si];
    tbb::parallel_for(tbb::blocked_range<size_t>(0, s.count, 1024), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t p = r.begin(); p != r.end(); ++p) {
        const size_t e = first[si] + p;
        if (!base_key(s.position[p], keys[e])) bad[e] = s.position[p].allFinite() ? 2 : 1;
      }
    });
  }
  for (size_t e = 0; e < total; ++e)
    if (bad[e]) {
      const size_t si = static_cast<size_t>(std::upper_bound(first.begin(), first.end(), e) - first.begin()) - 1;
      throw GridError(bad[e] == 1 ? "non-finite particle position" : "particle position out of the grid's range", si,
                      e - first[si]);
    }

  // 2. Active blocks: particle blocks and their forward neighbours, as a sorted key list: the block order
  //    is deterministic and spatially coherent, and a binary search replaces a hash map. The layout of the
  //    step before is kept if it holds every particle (the set sizes changed, or a particle left it on a
  //    kept layout, and `keep` still allows it).
  std::vector<uint32_t> block_of_particle(total);
  if (keep) {
    std::atomic<bool> fits{true};
    tbb::parallel_for(tbb::blocked_range<size_t>(0, total, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end() && fits.load(std::memory_order_relaxed); ++i) {
        const int32_t b = find_block(keys[i]);
        if (!holds_stencils_of(b)) {
          fits = false;
          return;
        }
        block_of_particle[i] = static_cast<uint32_t>(b);
      }
    });
    keep = fits;
  }
  if (keep) {
    ++reused_layouts_;
    ++counts_.kept_layout_rebinned_afresh;
  } else {
    reused_layouts_ = 0;
    ++counts_.fresh_layouts;
    build_layout(keys);
    tbb::parallel_for(size_t{0}, total, [&](size_t i) { block_of_particle[i] = static_cast<uint32_t>(find_block(keys[i])); });
  }

  // 3. Bins, then the per-particle cache of weights and stencil nodes in entry order (the transfers read
  //    it in that order).
  set_first_.assign(first.begin(), first.end());
  bin_particles(block_of_particle);
  stencil_.resize(total);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, active_keys_.size(), 8), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t b = r.begin(); b != r.end(); ++b)
      for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
        const Entry& en = entries_[e];
        fill_stencil(static_cast<uint32_t>(b), sets[en.set].position[en.index], stencil_[e]);
      }
  });
}

void SparseGrid::bin_particles(const std::vector<uint32_t>& block_of_particle) {
  // Stable counting sort of the particles (flat set/index order) by block, the inverse map from
  // (set, particle) to entry, and the parity colours of the blocks that hold particles.
  const size_t total = block_of_particle.size();
  const size_t num_blocks = active_keys_.size();
  bin_offsets_.assign(num_blocks + 1, 0);
  for (size_t i = 0; i < total; ++i) ++bin_offsets_[block_of_particle[i] + 1];
  for (size_t b = 0; b < num_blocks; ++b) bin_offsets_[b + 1] += bin_offsets_[b];
  entries_.resize(total);
  entry_of_.resize(total);
  std::vector<uint32_t> cursor(bin_offsets_.begin(), bin_offsets_.end() - 1);
  size_t set = 0;
  for (size_t i = 0; i < total; ++i) {
    while (i >= set_first_[set + 1]) ++set;
    const uint32_t e = cursor[block_of_particle[i]]++;
    entries_[e] = {static_cast<uint32_t>(set), static_cast<uint32_t>(i - set_first_[set])};
    entry_of_[i] = e;
  }
  colour_blocks_.assign(8, {});
  for (uint32_t b = 0; b < num_blocks; ++b) {
    if (bin_offsets_[b + 1] == bin_offsets_[b]) continue;
    const BlockCoord& c = block_coords_[b];
    colour_blocks_[static_cast<size_t>((c.x() & 1) | ((c.y() & 1) << 1) | ((c.z() & 1) << 2))].push_back(b);
  }
}

void SparseGrid::zero_nodes() {
  // Mass, momentum and force are sums the transfers add to; velocities are not zeroed, because
  // update_velocities() writes every node's. Parallel: this is the largest memory traffic of the rebuild.
  const size_t n = active_keys_.size() * kBlockNodes;
  grid_nodes_ = n;
  copy_parent_.clear();
  copy_mass_position_.clear();
  copy_mass_gradient_.clear();
  entry_phantom_row_.clear();
  phantom_stencil_.clear();
  mass_.resize(n);
  momentum_.resize(n);
  force_.resize(n);
  velocity_.resize(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    const auto from = static_cast<long>(r.begin()), to = static_cast<long>(r.end());
    std::fill(mass_.begin() + from, mass_.begin() + to, 0.0);
    std::fill(momentum_.begin() + from, momentum_.begin() + to, Vec3::Zero());
    std::fill(force_.begin() + from, force_.begin() + to, Vec3::Zero());
  });
}

std::vector<uint64_t> SparseGrid::particles_near_blocks(const std::vector<uint32_t>& blocks) const {
  std::vector<uint32_t> bins;  // blocks whose binned particles can reach one of `blocks`
  bins.reserve(blocks.size() * 8);
  for (uint32_t b : blocks) {
    const BlockCoord& c = block_coords_[b];
    for (int d = 0; d < 8; ++d) {
      const int32_t back = find_block(pack(c.x() - (d & 1), c.y() - ((d >> 1) & 1), c.z() - (d >> 2)));
      if (back >= 0) bins.push_back(static_cast<uint32_t>(back));
    }
  }
  std::sort(bins.begin(), bins.end());
  bins.erase(std::unique(bins.begin(), bins.end()), bins.end());
  // A bit per particle in flat (set, index) numbering: reading the bits in order gives the particles
  // sorted without a sort.
  const size_t total = set_first_.back();
  std::vector<uint64_t> bits((total + 63) / 64, 0);
  for (uint32_t b : bins)
    for (uint32_t e = bin_offsets_[b]; e < bin_offsets_[b + 1]; ++e) {
      const size_t flat = set_first_[entries_[e].set] + entries_[e].index;
      bits[flat / 64] |= uint64_t{1} << (flat % 64);
    }
  std::vector<uint64_t> particles;
  size_t set = 0;
  for (size_t w = 0; w < bits.size(); ++w)
    for (uint64_t word = bits[w]; word; word &= word - 1) {
      const size_t flat = 64 * w + static_cast<size_t>(__builtin_ctzll(word));
      while (flat >= set_first_[set + 1]) ++set;
      particles.push_back(uint64_t{set} << 32 | (flat - set_first_[set]));
    }
  return particles;
}

std::array<uint32_t, 27> SparseGrid::stencil_nodes(const Vec3& x) const {
  const StencilWeights sw = stencil_weights(x, inv_dx_);
  const int32_t b = find_block(pack(floor_div4(sw.ax[0].base), floor_div4(sw.ax[1].base), floor_div4(sw.ax[2].base)));
  if (b < 0) throw std::logic_error("stencil_nodes: position outside the active grid (rebuild first)");
  ParticleStencil st;
  fill_stencil(static_cast<uint32_t>(b), x, st);
  std::array<uint32_t, 27> nodes{};
  std::copy(st.node, st.node + 27, nodes.begin());
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
  phantom_stencil_.resize(layout.stencil_copy.size());
  // Rows name copies by number; store final node indices (a grid node for -1, else grid_nodes_ + copy).
  for (size_t r = 0; r < layout.stencil_copy.size() / 27; ++r)
    for (size_t k = 0; k < 27; ++k) {
      const int32_t c = layout.stencil_copy[r * 27 + k];
      phantom_stencil_[r * 27 + k] = c < 0 ? layout.stencil_node[r * 27 + k] : static_cast<uint32_t>(grid_nodes_ + static_cast<size_t>(c));
    }
  // Which entries use a row.
  entry_phantom_row_.clear();
  for (size_t set = 0; set < layout.particle_row.size(); ++set) {
    const std::vector<int32_t>& rows = layout.particle_row[set];
    for (size_t p = 0; p < rows.size(); ++p) {
      if (rows[p] < 0) continue;
      if (entry_phantom_row_.empty()) entry_phantom_row_.assign(entries_.size(), -1);
      entry_phantom_row_[entry_of_[set_first_[set] + p]] = rows[p];
    }
  }
}

int32_t SparseGrid::find_block(uint64_t key) const {
  const auto it = std::lower_bound(active_keys_.begin(), active_keys_.end(), key);
  return it != active_keys_.end() && *it == key ? static_cast<int32_t>(it - active_keys_.begin()) : -1;
}

void SparseGrid::fill_stencil(uint32_t block, const Vec3& x, ParticleStencil& st) const {
  fill_stencil(block, stencil_weights(x, inv_dx_), x, st);
}

void SparseGrid::fill_stencil(uint32_t block, const StencilWeights& sw, const Vec3& x, ParticleStencil& st) const {
  const BlockCoord& c = block_coords_[block];
  int local[3];  // base node in its block
  for (int d = 0; d < 3; ++d) {
    const AxisWeights& a = sw.ax[d];
    for (int i = 0; i < 3; ++i) {
      st.w[d][i] = a.w[i];
      st.dw[d][i] = a.dw[i];
    }
    st.d0[d] = a.base * dx_ - x[d];
    local[d] = a.base - c[d] * kBlock;
  }
  const uint32_t first = block * kBlockNodes + static_cast<uint32_t>(local[0] + kBlock * (local[1] + kBlock * local[2]));
  if (local[0] + 2 < kBlock && local[1] + 2 < kBlock && local[2] + 2 < kBlock) {  // inside the block
    for (uint32_t k = 0; k < 3; ++k)
      for (uint32_t j = 0; j < 3; ++j)
        for (uint32_t i = 0; i < 3; ++i) st.node[i + 3 * j + 9 * k] = first + i + kBlock * (j + kBlock * k);
    return;
  }
  // Reaching into the forward neighbours: per axis and offset the neighbour bit and the local offset.
  uint32_t base[8];
  for (size_t n = 0; n < 8; ++n) base[n] = static_cast<uint32_t>(forward_neighbours_[block][n]) * kBlockNodes;
  uint32_t bit[3][3], offset[3][3];
  constexpr uint32_t stride[3] = {1, kBlock, kBlock * kBlock};
  for (int d = 0; d < 3; ++d)
    for (int i = 0; i < 3; ++i) {
      const AxisSlot sl = slot(local[d], i);
      bit[d][i] = static_cast<uint32_t>(sl.next_block) << d;
      offset[d][i] = static_cast<uint32_t>(sl.local) * stride[d];
    }
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j) {
      const uint32_t bjk = bit[1][j] | bit[2][k], ojk = offset[1][j] + offset[2][k];
      for (int i = 0; i < 3; ++i) st.node[i + 3 * j + 9 * k] = base[bit[0][i] | bjk] + offset[0][i] + ojk;
    }
}

}  // namespace shellfrac::mpm
