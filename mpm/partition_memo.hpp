#pragma once
// What the previous phantom-node partition found, kept for the next one. Which particles at a node are
// connected depends only on the particles (their parameters) and the cracks, not on where the node is.
// So, while the cracks stay as they are:
//  - a node reached by exactly the particle list of a node of the previous partition has exactly its
//    components (no pair tests), and
//  - when the grid numbers its nodes as before and every particle near the previous partition's nodes
//    is the same particle on the same base node, every node sees the particles it saw and the whole
//    layout is the previous one (unchanged(): the caller keeps the layout it has).
// Particles cross cell boundaries rarely, so most steps take one of the two. The owner clears the memo
// whenever the connectivity or the near-crack flags can have changed (a crack grew).
#include <cstddef>
#include <cstdint>
#include <vector>


namespace shellfrac::mpm {

class SparseGrid;

class PartitionMemo {
 public:
  // A node's particle key: set << 32 | particle.
  static uint64_t key(uint32_t set, uint32_t particle) { return uint64_t{set} << 32 | particle; }
  // Hash of a node's particle list (order matters).
  static uint64_t hash(const uint64_t* keys, size_t n);

  // Looks up the node whose particle list is keys[0..n) with hash h: writes its component number per
  // particle to labels[0..n) and returns the number of components, or returns -1 when no node of the
  // stored partition had that list.
  int find(const uint64_t* keys, size_t n, uint64_t h, int32_t* labels) const;
  // Replaces the stored nodes. Node i has the particles keys[offsets[i] .. offsets[i + 1]) with
  // components labels[...] (numbered from 0 by first member), counts[i] of them, and list hash hashes[i].
  void store_nodes(std::vector<uint64_t> keys, std::vector<int32_t> labels, std::vector<uint32_t> offsets,
                   std::vector<int32_t> counts, const std::vector<uint64_t>& hashes);

  // True when the layout of the last partition stored here still holds for `grid` (see above).
  bool unchanged(const SparseGrid& grid) const;
  // Records what decided the layout just found on `grid`: the blocks of its flagged nodes and the
  // particles near them (SparseGrid::particles_near_blocks of those blocks).
  void store_inputs(const SparseGrid& grid, std::vector<uint32_t> blocks, const std::vector<uint64_t>& near);

  void clear();

 private:
  // Node components.
  std::vector<uint64_t> keys_;
  std::vector<int32_t> labels_;
  std::vector<uint32_t> offsets_;
  std::vector<int32_t> counts_;
  // Open addressing (linear probing, power-of-two size, at most half full): node number + 1, 0 = empty.
  std::vector<uint64_t> table_hash_;
  std::vector<uint32_t> table_node_;

  // What decided the last layout.
  bool has_layout_ = false;
  const SparseGrid* grid_ = nullptr;
  uint64_t grid_layout_ = 0;       // SparseGrid::layout_version() then
  std::vector<uint32_t> blocks_;   // blocks of the flagged nodes
  std::vector<uint64_t> near_;     // particles near them
  std::vector<uint32_t> base_;     // their base nodes (stencil entry 0)
};

}  // namespace shellfrac::mpm
