#include "mpm/partition_memo.hpp"

#include <algorithm>
#include <utility>

#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {

uint64_t PartitionMemo::hash(const uint64_t* keys, size_t n) {
  uint64_t h = 0x9E3779B97F4A7C15ull ^ n;
  for (size_t i = 0; i < n; ++i) {
    h = (h ^ keys[i]) * 0xFF51AFD7ED558CCDull;
    h ^= h >> 32;
  }
  return h;
}

int PartitionMemo::find(const uint64_t* keys, size_t n, uint64_t h, int32_t* labels) const {
  if (table_node_.empty()) return -1;
  const size_t mask = table_node_.size() - 1;
  for (size_t i = static_cast<size_t>(h) & mask;; i = (i + 1) & mask) {
    const uint32_t slot = table_node_[i];
    if (slot == 0) return -1;
    if (table_hash_[i] != h) continue;
    const size_t node = slot - 1, begin = offsets_[node];
    // Equal hashes need not mean equal lists: compare the lists themselves.
    if (offsets_[node + 1] - begin != n || !std::equal(keys, keys + n, keys_.begin() + static_cast<long>(begin))) continue;
    std::copy(labels_.begin() + static_cast<long>(begin), labels_.begin() + static_cast<long>(begin + n), labels);
    return counts_[node];
  }
}

void PartitionMemo::store_nodes(std::vector<uint64_t> keys, std::vector<int32_t> labels, std::vector<uint32_t> offsets,
                                std::vector<int32_t> counts, const std::vector<uint64_t>& hashes) {
  keys_ = std::move(keys);
  labels_ = std::move(labels);
  offsets_ = std::move(offsets);
  counts_ = std::move(counts);
  size_t size = 16;
  while (size < 2 * counts_.size()) size *= 2;
  table_hash_.assign(size, 0);
  table_node_.assign(size, 0);
  for (size_t node = 0; node < counts_.size(); ++node) {
    size_t i = static_cast<size_t>(hashes[node]) & (size - 1);
    while (table_node_[i] != 0) i = (i + 1) & (size - 1);
    table_hash_[i] = hashes[node];
    table_node_[i] = static_cast<uint32_t>(node + 1);
  }
}

bool PartitionMemo::unchanged(const SparseGrid& grid) const {
  if (!has_layout_ || grid_ != &grid || grid_layout_ != grid.layout_version()) return false;
  // The particles binned near the old flagged nodes: the same ones, each on its old base node. Then the
  // near-crack particles (binned there too) flag the same nodes, and every flagged node is reached by
  // the same particles through the same stencil entries.
  if (grid.particles_near_blocks(blocks_) != near_) return false;
  for (size_t i = 0; i < near_.size(); ++i)
    if (grid.particle_stencil(near_[i] >> 32, near_[i] & 0xFFFFFFFFu)[0] != base_[i]) return false;
  return true;
}

void PartitionMemo::store_inputs(const SparseGrid& grid, std::vector<uint32_t> blocks, const std::vector<uint64_t>& near) {
  has_layout_ = true;
  grid_ = &grid;
  grid_layout_ = grid.layout_version();
  blocks_ = std::move(blocks);
  near_ = near;
  base_.resize(near_.size());
  for (size_t i = 0; i < near_.size(); ++i) base_[i] = grid.particle_stencil(near_[i] >> 32, near_[i] & 0xFFFFFFFFu)[0];
}

void PartitionMemo::clear() { *this = PartitionMemo(); }

}  // namespace shellfrac::mpm
