#pragma once
#include <cstdint>
#include <vector>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// Node sets of thesis Table 3.1 (sec. 3.3) as bit flags. A node can be in several.
enum NodeSet : uint16_t {
  kActive = 1 << 0,     // rasterised particle weight > 0 (the domain on the grid)
  kDamaged = 1 << 1,    // rasterised weight of fully damaged particles > 0 (the damaged region)
  kSetD = 1 << 2,       // D: boundary nodes of the damaged region (a 6-neighbour outside it)
  kSetB = 1 << 3,       // B: boundary nodes of the domain
  kSetBd = 1 << 4,      // B': the dilated domain boundary, inactive nodes next to the domain
  kSetS = 1 << 5,       // S = D n B: damaged domain boundary
  kSetV = 1 << 6,       // V = D \ S: Voronoi input inside the object
  kSetN = 1 << 7,       // N: neighbours of S
  kSetE = 1 << 8,       // E = V n N: mid-surface extension nodes
  kSetI = 1 << 9,       // I = V \ E: interior mid-surface nodes
  kInterior = 1 << 10,  // damaged nodes not in D: the inside of the damaged region ("damage == 1")
  kSetBdNear = 1 << 11, // B' nodes near S, oriented like E so the crack also splits the outer cells
  kSetBdExit = 1 << 12, // B' nodes in front of the middle of a crack's exit: left out of the sites
  kIsland = 1 << 13,    // intact nodes of a clump the damaged region swallowed (not in the thesis, see below)
};

struct CrackGridOptions {
  double spacing = 0;            // h_v (> mean particle spacing; the MPM h is a good choice)
  double damage_threshold = 1.0; // c_his at or above this counts as fully damaged
  int neighbour_radius = 1;      // N: nodes within this many steps (in each axis) of S
  size_t memory_limit = size_t{2} << 30;
};

// The grid of spacing h_v the crack is extracted on (thesis sec. 3.3.1): particle weights and fully
// damaged particle weights rasterised with the MPM quadratic kernel in material space (Eq. 3.1), and the
// node sets of Table 3.1.
//
// Islands (not in the thesis): a node is damaged when any fully damaged particle reaches it (u_i > 0,
// sec. 3.3.1), which dilates the damaged region by the kernel radius 1.5 h_v. In a shattered object the
// intact particles are left in clumps smaller than 3 h_v, and the dilation swallows them: no node stays
// intact, D holds only surface nodes (all in S), V is empty and the object comes out whole. So intact
// material the dilation hid is restored: damaged nodes where intact particles hold at least half of the
// rasterised weight, grouped by 26-connectivity, become intact again (kIsland) when a group touches no
// intact node of the thesis's rule (a group that does is the flank of an ordinary crack band and is
// left alone, so thin cracks are extracted as before). Their damaged neighbours then enter D and V, and
// Algorithm 1 puts the medial surface between the clumps. Throws InputError, before allocating, when h_v is not positive or the grid
// would exceed the memory limit (with the estimate).
class CrackGrid {
 public:
  CrackGrid(const std::vector<Vec3>& rest, const std::vector<double>& damage_history, const CrackGridOptions& options);

  double spacing() const { return h_; }
  const Eigen::Vector3i& dims() const { return dims_; }
  size_t num_nodes() const { return flags_.size(); }
  uint16_t flags(size_t n) const { return flags_[n]; }
  bool in(size_t n, uint16_t set) const { return (flags_[n] & set) != 0; }
  Vec3 position(size_t n) const;
  Eigen::Vector3i coords(size_t n) const;
  long index(int i, int j, int k) const;  // local coordinates; -1 outside
  size_t count(uint16_t set) const;
  // Trilinear interpolation of the interior indicator at x: >= 1/2 means x lies inside the fully damaged
  // region (our reading of "damage == 1" in Algorithm 1 line 12).
  double interior_fraction(const Vec3& x) const;
  // Nearest node of I to node n (Algorithm 2): among its 26 neighbours if any is in I, else by a
  // breadth-first search over the grid up to max_steps rings; -1 if none.
  long nearest_in_I(size_t n, int max_steps = 6) const { return nearest_in(n, kSetI, max_steps); }
  // The same search for any set of nodes.
  long nearest_in(size_t n, uint16_t set, int max_steps = 6) const;
  // Unit outward normal of the damaged region at node n: minus the central-difference gradient of the
  // damaged fraction of the rasterised weight (well defined on D, where it falls off); zero if flat.
  Vec3 damage_normal(size_t n) const;
  // Intact clump (island) a node belongs to, -1 for none; islands are numbered from 0.
  int island(size_t n) const { return island_.empty() ? -1 : island_[n]; }
  // The island all intact 26-neighbours of node n belong to: -1 when it has none, -2 when they belong
  // to different islands or to the thesis's intact region.
  int bordering_island(size_t n) const;
  size_t island_count() const { return islands_; }
  // Estimated bytes for a grid covering [lo, hi] at spacing h (for the refusal message and callers).
  static double memory_estimate(const Vec3& lo, const Vec3& hi, double h);

 private:
  double h_;
  Eigen::Vector3i lo_, dims_;
  std::vector<uint16_t> flags_;
  std::vector<float> damaged_weight_;
  // The box of nodes around the particles (lo_, dims_); refuses one that would not fit in memory.
  void place_box(const std::vector<Vec3>& rest, const CrackGridOptions& o);
  // Eq. 3.1 for u = 1 and u = [c_his >= threshold]: the weights, and the active and damaged flags.
  void rasterise(const std::vector<Vec3>& rest, const std::vector<double>& c_his, double threshold,
                 std::vector<double>& weight, std::vector<double>& damaged);
  void restore_islands(const std::vector<double>& weight, const std::vector<double>& damaged);
  // The sets of sec. 3.3.1 (B, B', D, S, V, N, E, I and the exits) from the active and damaged flags.
  void classify(int neighbour_radius);
  std::vector<int> island_;  // per node, empty when there is no island
  size_t islands_ = 0;
};

}  // namespace shellfrac::brittle
