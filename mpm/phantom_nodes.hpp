#pragma once
#include <cstdint>
#include <functional>
#include <vector>

#include "mpm/particle_set.hpp"

namespace shellfrac::mpm {

class SparseGrid;
class PartitionMemo;

// What kind of material a phantom copy holds; it decides the contact normal (thesis Eq. 4.22).
enum class FieldKind : uint8_t { Shell = 0, Solid = 1 };

// Phantom copies of grid nodes near cracks (thesis sec. 4.7.1): one copy per disconnected fragment side
// among the particles a node's stencil reaches. Copies of one node are contiguous.
struct PhantomLayout {
  std::vector<uint32_t> copy_parent;               // grid node of each copy
  std::vector<FieldKind> copy_kind;                // material of each copy
  std::vector<std::vector<int32_t>> particle_row;  // [set][particle] -> stencil row, or -1; empty = none
  std::vector<int32_t> stencil_copy;               // rows x 27: copy number, or -1 for the grid node
  std::vector<uint32_t> stencil_node;              // rows x 27: the grid node of each stencil entry
  size_t split_nodes = 0;                          // grid nodes that received copies
};

// The role of a particle set in the partition.
struct PartitionRole {
  FieldKind kind = FieldKind::Shell;
  // Per particle, non-zero when it takes part in an MLS (crack-affected) basis; null = none of them.
  // Nodes whose stencil reaches such a particle are partitioned (sec. 4.7.1).
  const unsigned char* near_crack = nullptr;
};

// connected(set_a, particle_a, set_b, particle_b): true when two particles that share a node lie on the
// same side of every crack (same fragment locally), e.g. their parameter-space segment crosses no crack.
using Connectivity = std::function<bool(uint32_t, uint32_t, uint32_t, uint32_t)>;

// Optional shortcut for a whole node: one_component(sets, particles, n) true only when the n particles
// (set and index arrays) are certainly pairwise connected, e.g. no crack meets the box around their
// parameters; the node then needs no pair tests. False when unsure.
using GroupConnectivity = std::function<bool(const uint32_t*, const uint32_t*, int)>;

// Groups, at every node reached by a near-crack particle, all particles that reach the node into
// connected components of `connected` (union-find); two or more components give the node one copy per
// component. Deterministic: components are numbered by their first particle in (set, index) order.
// With a memo, nodes the previous call saw with the same particles reuse its components, and the memo
// then holds this call's nodes and what decided its layout (a caller may skip the call while
// memo->unchanged(grid); mpm/partition_memo.hpp). The caller clears the memo when `connected` or the
// near-crack flags change. Call after grid.rebuild(sets).
PhantomLayout partition_nodes(const SparseGrid& grid, const std::vector<ParticleSet>& sets,
                              const std::vector<PartitionRole>& roles, const Connectivity& connected,
                              const GroupConnectivity& one_component = {}, PartitionMemo* memo = nullptr);

struct ContactStats {
  size_t nodes = 0;           // split nodes visited
  size_t pairs_resolved = 0;  // pairwise contact resolutions (Eq. 4.23-4.26)
  size_t max_iterations = 0;  // at a single node
  double max_residual = 0;    // largest approaching normal velocity left (<= tolerance unless capped)
};

// Contact between the copies of each split node, after the grid velocity update (thesis sec. 4.7.2):
// normal per Eq. 4.22, adhesive normal and tangential forces (Eq. 4.23-4.24), Coulomb sliding (Eq. 4.25)
// and equal and opposite totals (Eq. 4.26). With three or more copies the pair with the largest
// approaching normal velocity is resolved first, repeatedly, until every approaching velocity is below
// `tolerance`. Momentum at each node is conserved to round-off.
ContactStats resolve_phantom_contact(SparseGrid& grid, const std::vector<FieldKind>& copy_kind, double dt,
                                     double friction, double tolerance = 1e-4);

}  // namespace shellfrac::mpm
