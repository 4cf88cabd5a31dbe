#include "mpm/phantom_nodes.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <tuple>

#include "mpm/partition_memo.hpp"
#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {

namespace {

struct NodeParticle {
  NodeParticle() {}  // left unset: the bucketing writes every entry
  NodeParticle(uint32_t n, uint32_t s, uint32_t p, uint32_t k) : node(n), set(s), particle(p), stencil(k) {}
  uint32_t node, set, particle, stencil;  // stencil entry i + 3 j + 9 k of the node for this particle
};

// Slot + 1 of each flagged node, 0 for the others, kept only for the grid blocks that hold flagged nodes:
// a table over the whole grid would be cleared every step for a thousand or so entries.
class NodeSlots {
 public:
  explicit NodeSlots(size_t blocks) : block_base_(blocks, -1) {}
  uint32_t operator[](uint32_t node) const {
    const int32_t base = block_base_[node / SparseGrid::kBlockNodes];
    return base < 0 ? 0 : slots_[static_cast<size_t>(base) + node % SparseGrid::kBlockNodes];
  }
  // The entry of `node`, its block's entries added (as 0) on first use.
  uint32_t& entry(uint32_t node) {
    int32_t& base = block_base_[node / SparseGrid::kBlockNodes];
    if (base < 0) {
      base = static_cast<int32_t>(slots_.size());
      slots_.resize(slots_.size() + SparseGrid::kBlockNodes, 0);
    }
    return slots_[static_cast<size_t>(base) + node % SparseGrid::kBlockNodes];
  }

 private:
  std::vector<int32_t> block_base_;  // per grid block: first entry in slots_, or -1
  std::vector<uint32_t> slots_;
};

int find_root(std::vector<int>& parent, int i) {
  while (parent[static_cast<size_t>(i)] != i) {
    parent[static_cast<size_t>(i)] = parent[static_cast<size_t>(parent[static_cast<size_t>(i)])];
    i = parent[static_cast<size_t>(i)];
  }
  return i;
}

// Per-thread scratch of node_components.
struct ComponentScratch {
  std::vector<int> parent, label;
  std::vector<uint32_t> sets, particles;
};

// The components of one flagged node, whose particles are pairs[begin, begin + n): writes each pair's
// component (numbered by first member) to component[0, n) and returns how many there are. With a memo,
// keys[0, n) and *hash get the node's particle list and its hash, and a list the memo knows takes the
// components found for it before.
int node_components(const std::vector<NodeParticle>& pairs, size_t begin, int n, const Connectivity& connected,
                    const GroupConnectivity& one_component, const PartitionMemo* memo, uint64_t* keys, uint64_t* hash,
                    int32_t* component, ComponentScratch& scratch) {
  const auto count = static_cast<size_t>(n);
  if (memo) {
    for (size_t i = 0; i < count; ++i) keys[i] = PartitionMemo::key(pairs[begin + i].set, pairs[begin + i].particle);
    *hash = PartitionMemo::hash(keys, count);
    const int known = memo->find(keys, count, *hash, component);
    if (known >= 0) return known;
  }
  if (one_component) {  // component[] of the node's pairs is still 0
    scratch.sets.resize(count);
    scratch.particles.resize(count);
    for (size_t a = 0; a < count; ++a) {
      scratch.sets[a] = pairs[begin + a].set;
      scratch.particles[a] = pairs[begin + a].particle;
    }
    if (one_component(scratch.sets.data(), scratch.particles.data(), n)) return 1;
  }
  std::vector<int>& parent = scratch.parent;
  parent.resize(count);
  std::iota(parent.begin(), parent.end(), 0);
  // Once every particle is in one component no test can change the partition: stop (most flagged nodes
  // are away from the crack itself, where the first particle sees all the others).
  int groups = n;
  for (int a = 0; a < n && groups > 1; ++a)
    for (int b = a + 1; b < n && groups > 1; ++b) {
      const int ra = find_root(parent, a), rb = find_root(parent, b);
      if (ra == rb) continue;
      const NodeParticle &pa = pairs[begin + static_cast<size_t>(a)], &pb = pairs[begin + static_cast<size_t>(b)];
      if (connected(pa.set, pa.particle, pb.set, pb.particle)) {
        parent[static_cast<size_t>(std::max(ra, rb))] = std::min(ra, rb);
        --groups;
      }
    }
  scratch.label.assign(count, -1);
  int found = 0;
  for (int a = 0; a < n; ++a) {
    const int root = find_root(parent, a);  // roots are the smallest members: first-member order
    if (scratch.label[static_cast<size_t>(root)] < 0) scratch.label[static_cast<size_t>(root)] = found++;
    component[a] = scratch.label[static_cast<size_t>(root)];
  }
  return found;
}

// The stencil rows of the particles that use a copy: their 27 nodes, and the copy each entry uses (-1: the
// node itself).
void add_stencil_rows(const SparseGrid& grid, const std::vector<ParticleSet>& sets, const std::vector<NodeParticle>& pairs,
                      const std::vector<int32_t>& pair_copy, PhantomLayout& layout) {
  layout.particle_row.resize(sets.size());
  for (size_t i = 0; i < pairs.size(); ++i) {
    if (pair_copy[i] < 0) continue;
    const NodeParticle& np = pairs[i];
    auto& rows = layout.particle_row[np.set];
    if (rows.empty()) rows.assign(sets[np.set].count, -1);
    int32_t& row = rows[np.particle];
    if (row < 0) {
      row = static_cast<int32_t>(layout.stencil_copy.size() / 27);
      layout.stencil_copy.insert(layout.stencil_copy.end(), 27, -1);
      const uint32_t* st = grid.particle_stencil(np.set, np.particle);
      layout.stencil_node.insert(layout.stencil_node.end(), st, st + 27);
    }
    layout.stencil_copy[static_cast<size_t>(row) * 27 + np.stencil] = pair_copy[i];
  }
}

// Step 1: the nodes reached by near-crack particles, in index order (the slot order); node_slot gets
// slot + 1 for each.
std::vector<uint32_t> flag_nodes(const SparseGrid& grid, const std::vector<ParticleSet>& sets,
                                 const std::vector<PartitionRole>& roles, NodeSlots& node_slot) {
  std::vector<uint32_t> slot_node;
  for (size_t s = 0; s < sets.size() && s < roles.size(); ++s) {
    if (!roles[s].near_crack) continue;
    for (size_t p = 0; p < sets[s].count; ++p)
      if (roles[s].near_crack[p])
        for (const uint32_t* n = grid.particle_stencil(s, p), *end = n + 27; n != end; ++n) {
          uint32_t& slot = node_slot.entry(*n);
          if (!slot) {
            slot = 1;
            slot_node.push_back(*n);
          }
        }
  }
  std::sort(slot_node.begin(), slot_node.end());
  for (size_t slot = 0; slot < slot_node.size(); ++slot) node_slot.entry(slot_node[slot]) = static_cast<uint32_t>(slot + 1);
  return slot_node;
}

// Step 2's result: every (node, particle) pair at a flagged node, bucketed by node (pairs of slot s at
// slot_count[s] .. slot_count[s + 1]); the flagged nodes' blocks and, for the memo, the particles binned
// next to them.
struct NodePairs {
  std::vector<NodeParticle> pairs;
  std::vector<uint32_t> slot_count;
  std::vector<uint32_t> blocks;
  std::vector<uint64_t> near;
};

// Step 2: a counting sort by node (particles in (set, index) order inside a node): deterministic,
// O(pairs). Only particles binned next to the flagged nodes' blocks can reach them, so only those are
// looked at; their stencils come from the grid's per-particle cache (filled by rebuild).
NodePairs bucket_pairs(const SparseGrid& grid, const std::vector<uint32_t>& slot_node, const NodeSlots& node_slot,
                       bool keep_near) {
  NodePairs out;
  out.blocks.resize(slot_node.size());
  for (size_t slot = 0; slot < slot_node.size(); ++slot) out.blocks[slot] = static_cast<uint32_t>(slot_node[slot] / SparseGrid::kBlockNodes);
  out.blocks.erase(std::unique(out.blocks.begin(), out.blocks.end()), out.blocks.end());  // slot_node is sorted
  std::vector<uint64_t> touching = grid.particles_near_blocks(out.blocks);
  if (keep_near) out.near = touching;
  std::vector<uint32_t> reached(touching.size());  // per kept particle: bit k set when stencil entry k is flagged
  out.slot_count.assign(slot_node.size() + 1, 0);
  size_t kept = 0;
  for (const uint64_t sp : touching) {
    const uint32_t* st = grid.particle_stencil(sp >> 32, sp & 0xFFFFFFFFu);
    uint32_t bits = 0;
    for (uint32_t k = 0; k < 27; ++k)
      if (const uint32_t slot = node_slot[st[k]]) {
        ++out.slot_count[slot];
        bits |= 1u << k;
      }
    if (!bits) continue;
    reached[kept] = bits;
    touching[kept++] = sp;
  }
  touching.resize(kept);
  for (size_t k = 0; k + 1 < out.slot_count.size(); ++k) out.slot_count[k + 1] += out.slot_count[k];
  out.pairs.resize(out.slot_count.back());
  std::vector<uint32_t> cursor(out.slot_count.begin(), out.slot_count.end() - 1);
  for (size_t t = 0; t < touching.size(); ++t) {
    const auto s = static_cast<uint32_t>(touching[t] >> 32), p = static_cast<uint32_t>(touching[t] & 0xFFFFFFFFu);
    const uint32_t* st = grid.particle_stencil(s, p);
    for (uint32_t bits = reached[t]; bits; bits &= bits - 1) {
      const auto k = static_cast<uint32_t>(__builtin_ctz(bits));
      out.pairs[cursor[node_slot[st[k]] - 1]++] = NodeParticle(st[k], s, p, k);
    }
  }
  return out;
}

// Step 4: one copy per component of every node with two or more; per pair, the copy its particle uses
// (-1: the node itself).
std::vector<int32_t> assign_copies(const std::vector<uint32_t>& slot_node, const NodePairs& np,
                                   const std::vector<int32_t>& components, const std::vector<int32_t>& component,
                                   const std::vector<PartitionRole>& roles, PhantomLayout& layout) {
  std::vector<int32_t> pair_copy(np.pairs.size(), -1);
  for (size_t slot = 0; slot < slot_node.size(); ++slot) {
    if (components[slot] < 2) continue;
    ++layout.split_nodes;
    const auto first_copy = static_cast<int32_t>(layout.copy_parent.size());
    for (int32_t c = 0; c < components[slot]; ++c) {
      layout.copy_parent.push_back(slot_node[slot]);
      layout.copy_kind.push_back(FieldKind::Shell);
    }
    for (size_t i = np.slot_count[slot]; i < np.slot_count[slot + 1]; ++i) {
      pair_copy[i] = first_copy + component[i];
      const uint32_t set = np.pairs[i].set;
      layout.copy_kind[static_cast<size_t>(pair_copy[i])] = set < roles.size() ? roles[set].kind : FieldKind::Shell;
    }
  }
  return pair_copy;
}

}  // namespace

PhantomLayout partition_nodes(const SparseGrid& grid, const std::vector<ParticleSet>& sets,
                              const std::vector<PartitionRole>& roles, const Connectivity& connected,
                              const GroupConnectivity& one_component, PartitionMemo* memo) {
  PhantomLayout layout;
  NodeSlots node_slot(grid.num_blocks());
  const std::vector<uint32_t> slot_node = flag_nodes(grid, sets, roles, node_slot);
  if (slot_node.empty()) {
    if (memo) memo->clear();
    return layout;
  }
  NodePairs np = bucket_pairs(grid, slot_node, node_slot, memo != nullptr);

  // 3. Components per node (in parallel: nodes are independent). component[i] numbers the components
  //    of pair i's node by first member; a node with two or more gets one copy per component. A node
  //    whose particle list the memo knows takes the components found for it before.
  std::vector<int32_t> component(np.pairs.size(), 0);
  std::vector<int32_t> components(slot_node.size(), 0);
  std::vector<uint64_t> keys(memo ? np.pairs.size() : 0), hashes(memo ? slot_node.size() : 0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, slot_node.size(), 8), [&](const tbb::blocked_range<size_t>& r) {
    ComponentScratch scratch;
    for (size_t slot = r.begin(); slot != r.end(); ++slot) {
      const size_t begin = np.slot_count[slot];
      const int n = static_cast<int>(np.slot_count[slot + 1] - begin);
      components[slot] = node_components(np.pairs, begin, n, connected, one_component, memo,
                                         memo ? &keys[begin] : nullptr, memo ? &hashes[slot] : nullptr,
                                         &component[begin], scratch);
    }
  });
  if (memo) memo->store_nodes(std::move(keys), component, np.slot_count, components, hashes);
  const std::vector<int32_t> pair_copy = assign_copies(slot_node, np, components, component, roles, layout);
  // 5. Stencil rows for the particles that use a copy.
  if (!layout.copy_parent.empty()) add_stencil_rows(grid, sets, np.pairs, pair_copy, layout);
  if (memo) memo->store_inputs(grid, std::move(np.blocks), np.near);
  return layout;
}

namespace {

// Contact normal from copy a towards copy b (thesis Eq. 4.22). A solid's outward normal is its mass
// gradient sum m grad w (it points from the material to the node); a shell has no volume, so shell-shell
// contact uses the direction between the centres of mass. Zero when undefined.
Vec3 contact_normal(const SparseGrid& grid, size_t a, size_t b, FieldKind ka, FieldKind kb) {
  const size_t g = grid.num_grid_nodes();
  auto normalized = [](const Vec3& v) { const double n = v.norm(); return n > 0 ? Vec3(v / n) : Vec3(Vec3::Zero()); };
  if (ka == FieldKind::Solid && kb == FieldKind::Solid)
    return normalized(normalized(grid.copy_mass_gradient(a - g)) - normalized(grid.copy_mass_gradient(b - g)));
  if (ka == FieldKind::Solid) return normalized(grid.copy_mass_gradient(a - g));
  if (kb == FieldKind::Solid) return -normalized(grid.copy_mass_gradient(b - g));
  const Vec3 com_a = grid.copy_mass_position(a - g) / grid.node_mass(a);
  const Vec3 com_b = grid.copy_mass_position(b - g) / grid.node_mass(b);
  return normalized(com_b - com_a);
}

}  // namespace

ContactStats resolve_phantom_contact(SparseGrid& grid, const std::vector<FieldKind>& copy_kind, double dt,
                                     double friction, double tolerance) {
  ContactStats stats;
  const size_t g = grid.num_grid_nodes(), copies = grid.num_phantom_copies();
  if (copies == 0) return stats;
  // Copies of one node are contiguous; each node is independent.
  std::vector<size_t> starts;
  for (size_t c = 0; c < copies; ++c)
    if (c == 0 || grid.parent_node(g + c) != grid.parent_node(g + c - 1)) starts.push_back(c);
  starts.push_back(copies);
  std::vector<ContactStats> per_node(starts.size() - 1);
  tbb::parallel_for(size_t{0}, starts.size() - 1, [&](size_t s) {
    const size_t begin = g + starts[s], end = g + starts[s + 1];
    ContactStats& st = per_node[s];
    st.nodes = 1;
    // Normals depend only on the transferred mass data, not on the velocities: compute them once.
    const size_t n = end - begin;
    std::vector<Vec3> normal(n * n, Vec3::Zero());
    for (size_t a = 0; a < n; ++a)
      for (size_t b = a + 1; b < n; ++b)
        if (grid.node_mass(begin + a) > 0 && grid.node_mass(begin + b) > 0)
          normal[a * n + b] = contact_normal(grid, begin + a, begin + b, copy_kind[starts[s] + a], copy_kind[starts[s] + b]);
    const size_t max_iterations = 20 * n * n;
    for (size_t it = 0;; ++it) {
      // The pair with the largest approaching normal velocity (v_a - v_b) . n > 0.
      double worst = tolerance;
      size_t wa = 0, wb = 0;
      for (size_t a = 0; a < n; ++a)
        for (size_t b = a + 1; b < n; ++b) {
          const Vec3& nab = normal[a * n + b];
          if (nab.isZero()) continue;
          const double approach = (grid.node_velocity(begin + a) - grid.node_velocity(begin + b)).dot(nab);
          if (approach > worst) {
            worst = approach;
            wa = a;
            wb = b;
          }
        }
      if (worst <= tolerance || it >= max_iterations) {
        st.max_iterations = it;
        st.max_residual = worst > tolerance ? worst : 0.0;
        break;
      }
      const size_t a = begin + wa, b = begin + wb;
      const Vec3& nab = normal[wa * n + wb];
      const double ma = grid.node_mass(a), mb = grid.node_mass(b), mu = ma * mb / (ma + mb);
      const Vec3 dv = grid.node_velocity(b) - grid.node_velocity(a);
      const double fn = -mu * dv.dot(nab) / dt;  // thesis Eq. 4.23 (> 0 when approaching)
      // Tangent: normalised tangential part of the relative velocity (the misprint fix of Eq. 4.24).
      const Vec3 dv_t = dv - dv.dot(nab) * nab;
      const double t_norm = dv_t.norm();
      Vec3 tangent = Vec3::Zero();
      double ft = 0.0;
      if (t_norm > 1e-14 * (1.0 + dv.norm())) {
        tangent = dv_t / t_norm;
        ft = -mu * dv.dot(tangent) / dt;                                   // thesis Eq. 4.24 (sticking)
        if (std::abs(ft) > friction * std::abs(fn)) ft = -friction * std::abs(fn);  // Eq. 4.25, dv.t > 0
      }
      const Vec3 fa = -(fn * nab + ft * tangent);  // thesis Eq. 4.26; copy b receives -fa
      const Vec3 impulse = dt * fa;
      grid.node_velocity(a) += impulse / ma;
      grid.node_velocity(b) -= impulse / mb;
      ++st.pairs_resolved;
    }
  });
  for (const ContactStats& st : per_node) {
    stats.nodes += st.nodes;
    stats.pairs_resolved += st.pairs_resolved;
    stats.max_iterations = std::max(stats.max_iterations, st.max_iterations);
    stats.max_residual = std::max(stats.max_residual, st.max_residual);
  }
  return stats;
}

}  // namespace shellfrac::mpm
