#include "mpm/sparse_grid.hpp"

#include "core/rigid_rotation.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_sort.h>

#include <algorithm>
#include <atomic>
#include <stdexcept>
#include <string>
#include <type_traits>

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
