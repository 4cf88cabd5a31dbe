// The phantom-node partition (thesis sec. 4.7.1) against a brute-force one built node by node from
// stencil_nodes(), with and without the memo of node components; and the grid's list of particles near
// a set of blocks.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <map>
#include <random>
#include <set>

#include "mpm/partition_memo.hpp"
#include "mpm/phantom_nodes.hpp"
#include "mpm/sparse_grid.hpp"

namespace shellfrac::mpm {
namespace {

constexpr double kDx = 0.03;

// One particle set: positions, unit masses and velocities, and the near-crack flags.
struct Cloud {
  std::vector<Vec3> x, v;
  std::vector<double> m;
  std::vector<unsigned char> near;
  ParticleSet set() {
    ParticleSet s;
    s.count = x.size();
    s.position = x.data();
    s.velocity = v.data();
    s.mass = m.data();
    return s;
  }
};

// Particles scattered in a thin slab around z = 0.5; those within 0.15 of the plane x = 0.5 are near the crack.
Cloud scatter(int count, unsigned seed) {
  Cloud c;
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.1, 0.9), z(0.47, 0.53);
  for (int i = 0; i < count; ++i) {
    c.x.emplace_back(u(rng), u(rng), z(rng));
    c.v.push_back(Vec3::Zero());
    c.m.push_back(1.0);
    c.near.push_back(std::abs(c.x.back().x() - 0.5) < 0.15 ? 1 : 0);
  }
  return c;
}

// The crack: the segment x = 0.5, y in [0.2, 0.7], in the xy plane. Two particles are connected when the
// segment between their rest positions does not cross it (strict orientation tests; random points are
// never collinear with it). Rest positions stay put when the particles move, like shell parameters.
bool crosses_crack(const Vec3& a, const Vec3& b) {
  auto orient = [](double px, double py, double qx, double qy, double rx, double ry) {
    return (qx - px) * (ry - py) - (qy - py) * (rx - px);
  };
  const double c0x = 0.5, c0y = 0.2, c1x = 0.5, c1y = 0.7;
  const double o1 = orient(c0x, c0y, c1x, c1y, a.x(), a.y()), o2 = orient(c0x, c0y, c1x, c1y, b.x(), b.y());
  const double o3 = orient(a.x(), a.y(), b.x(), b.y(), c0x, c0y), o4 = orient(a.x(), a.y(), b.x(), b.y(), c1x, c1y);
  return (o1 > 0) != (o2 > 0) && (o3 > 0) != (o4 > 0);
}

// Per split node: its copies' first index and, per (set, particle) reaching it, its copy number.
struct SplitNodes {
  std::map<uint32_t, std::map<std::pair<uint32_t, uint32_t>, int>> copy_of;  // node -> particle -> copy
};

// Brute force: every node any near particle's stencil reaches, all particles reaching it (stencil_nodes
// from the positions), components by flood fill over all pairs, numbered by first member in (set, index)
// order; copies numbered node by node in index order.
SplitNodes brute_force(const SparseGrid& grid, const std::vector<Cloud*>& clouds,
                       const std::vector<std::vector<Vec3>>& rest) {
  std::map<uint32_t, std::vector<std::pair<uint32_t, uint32_t>>> reaching;  // node -> particles, (set, index) order
  std::set<uint32_t> flagged;
  for (uint32_t s = 0; s < clouds.size(); ++s)
    for (uint32_t p = 0; p < clouds[s]->x.size(); ++p)
      for (uint32_t n : grid.stencil_nodes(clouds[s]->x[p])) {
        reaching[n].emplace_back(s, p);
        if (clouds[s]->near[p]) flagged.insert(n);
      }
  SplitNodes out;
  int next_copy = 0;
  for (uint32_t n : flagged) {
    const auto& list = reaching[n];
    std::vector<int> label(list.size(), -1);
    int count = 0;
    for (size_t a = 0; a < list.size(); ++a) {
      if (label[a] >= 0) continue;
      label[a] = count;
      std::vector<size_t> stack{a};
      while (!stack.empty()) {
        const size_t i = stack.back();
        stack.pop_back();
        for (size_t j = 0; j < list.size(); ++j)
          if (label[j] < 0 && !crosses_crack(rest[list[i].first][list[i].second], rest[list[j].first][list[j].second])) {
            label[j] = count;
            stack.push_back(j);
          }
      }
      ++count;
    }
    if (count < 2) continue;
    for (size_t a = 0; a < list.size(); ++a) out.copy_of[n][list[a]] = next_copy + label[a];
    next_copy += count;
  }
  return out;
}

// The same table read from a layout: for every particle row and stencil entry naming a copy.
SplitNodes from_layout(const PhantomLayout& layout, const SparseGrid& grid, const std::vector<Cloud*>& clouds) {
  SplitNodes out;
  for (uint32_t s = 0; s < layout.particle_row.size(); ++s)
    for (uint32_t p = 0; p < layout.particle_row[s].size(); ++p) {
      const int32_t row = layout.particle_row[s][p];
      if (row < 0) continue;
      const std::array<uint32_t, 27> nodes = grid.stencil_nodes(clouds[s]->x[p]);
      for (size_t k = 0; k < 27; ++k) {
        const int32_t copy = layout.stencil_copy[static_cast<size_t>(row) * 27 + k];
        if (copy >= 0) out.copy_of[nodes[k]][{s, p}] = copy;
      }
    }
  return out;
}

struct Scene {
  Cloud a = scatter(700, 11), b = scatter(500, 12);
  std::vector<std::vector<Vec3>> rest{a.x, b.x};
  std::vector<Cloud*> clouds{&a, &b};
  std::atomic<long> queries{0};
  Connectivity connected() {
    return [this](uint32_t sa, uint32_t pa, uint32_t sb, uint32_t pb) {
      ++queries;
      return !crosses_crack(rest[sa][pa], rest[sb][pb]);
    };
  }
  std::vector<ParticleSet> sets() { return {a.set(), b.set()}; }
  std::vector<PartitionRole> roles() { return {{FieldKind::Shell, a.near.data()}, {FieldKind::Shell, b.near.data()}}; }
};

void expect_same_layout(const PhantomLayout& x, const PhantomLayout& y) {
  EXPECT_EQ(x.copy_parent, y.copy_parent);
  EXPECT_EQ(x.particle_row, y.particle_row);
  EXPECT_EQ(x.stencil_copy, y.stencil_copy);
  EXPECT_EQ(x.stencil_node, y.stencil_node);
  EXPECT_EQ(x.split_nodes, y.split_nodes);
}

TEST(PhantomPartition, EqualsBruteForceComponentsPerNode) {
  Scene sc;
  std::vector<ParticleSet> sets = sc.sets();
  SparseGrid grid(kDx);
  grid.rebuild(sets);
  const PhantomLayout layout = partition_nodes(grid, sets, sc.roles(), sc.connected());
  const SplitNodes want = brute_force(grid, sc.clouds, sc.rest);
  ASSERT_GT(want.copy_of.size(), 50u);  // the crack splits a good number of nodes
  EXPECT_EQ(layout.split_nodes, want.copy_of.size());
  std::vector<uint32_t> parents;  // copy_parent lists each split node once per copy, nodes ascending
  for (const auto& [node, particles] : want.copy_of) {
    std::set<int> copies;
    for (const auto& entry : particles) copies.insert(entry.second);
    parents.insert(parents.end(), copies.size(), node);
  }
  EXPECT_EQ(layout.copy_parent, parents);
  EXPECT_EQ(from_layout(layout, grid, sc.clouds).copy_of, want.copy_of);  // every particle at its copy, exactly
}

TEST(PhantomPartition, MemoReusesComponentsAndMatchesAFreshPartition) {
  Scene sc;
  std::vector<ParticleSet> sets = sc.sets();
  SparseGrid grid(kDx);
  grid.rebuild(sets);
  PartitionMemo memo;
  const PhantomLayout first = partition_nodes(grid, sets, sc.roles(), sc.connected(), {}, &memo);
  const long first_queries = sc.queries.exchange(0);
  EXPECT_GT(first_queries, 0);
  // Unchanged particles: every node is known, no pair is tested, and the layout is the same.
  EXPECT_TRUE(memo.unchanged(grid));
  const PhantomLayout again = partition_nodes(grid, sets, sc.roles(), sc.connected(), {}, &memo);
  EXPECT_EQ(sc.queries.exchange(0), 0);
  expect_same_layout(again, first);
  // Moves inside the cells (a quarter of the distance to the nearest base-node boundary): every stencil
  // stays, the memo says the layout holds, and it is what a fresh partition finds.
  for (Cloud* c : sc.clouds)
    for (Vec3& x : c->x) {
      const double f = x.y() / kDx - 0.5 - std::floor(x.y() / kDx - 0.5);  // in [0, 1)
      x.y() += 0.25 * std::min(f, 1.0 - f) * kDx * (f < 0.5 ? -1.0 : 1.0);
    }
  grid.rebuild(sets);
  EXPECT_TRUE(memo.unchanged(grid));
  expect_same_layout(partition_nodes(grid, sets, sc.roles(), sc.connected()), first);
  sc.queries = 0;
  // Move every 25th particle by half a cell: their nodes' lists change, the rest are reused.
  for (size_t p = 0; p < sc.a.x.size(); p += 25) sc.a.x[p].y() += 0.5 * kDx;
  for (size_t p = 0; p < sc.b.x.size(); p += 25) sc.b.x[p].x() -= 0.5 * kDx;
  grid.rebuild(sets);
  EXPECT_FALSE(memo.unchanged(grid));
  const PhantomLayout moved = partition_nodes(grid, sets, sc.roles(), sc.connected(), {}, &memo);
  const long moved_queries = sc.queries.exchange(0);
  const PhantomLayout fresh = partition_nodes(grid, sets, sc.roles(), sc.connected());
  EXPECT_GT(moved_queries, 0);
  EXPECT_LT(moved_queries, first_queries / 2);  // 18K pair tests at first, 2.6K after the move
  expect_same_layout(moved, fresh);
  EXPECT_EQ(from_layout(moved, grid, sc.clouds).copy_of, brute_force(grid, sc.clouds, sc.rest).copy_of);
}

TEST(PhantomPartition, ParticlesNearBlocksHoldEveryParticleReachingThem) {
  Cloud c = scatter(2000, 5);
  std::vector<ParticleSet> sets{c.set(), c.set()};  // a second set: keys carry the set number
  SparseGrid grid(kDx);
  grid.rebuild(sets);
  std::vector<uint32_t> blocks;
  for (uint32_t b = 0; b < grid.num_blocks(); b += 3) blocks.push_back(b);
  const std::vector<uint64_t> near = grid.particles_near_blocks(blocks);
  EXPECT_TRUE(std::is_sorted(near.begin(), near.end()));
  EXPECT_EQ(std::adjacent_find(near.begin(), near.end()), near.end());
  const std::set<uint32_t> chosen(blocks.begin(), blocks.end());
  size_t reaching = 0, missing = 0;
  for (uint32_t s = 0; s < 2; ++s)
    for (uint32_t p = 0; p < c.x.size(); ++p) {
      bool reaches = false;
      for (uint32_t n : grid.stencil_nodes(c.x[p])) reaches = reaches || chosen.count(n / SparseGrid::kBlockNodes) > 0;
      if (!reaches) continue;
      ++reaching;
      missing += !std::binary_search(near.begin(), near.end(), uint64_t{s} << 32 | p);
    }
  EXPECT_GT(reaching, 100u);
  EXPECT_EQ(missing, 0u);
  EXPECT_LE(near.size(), sets.size() * c.x.size());
}

}  // namespace
}  // namespace shellfrac::mpm
