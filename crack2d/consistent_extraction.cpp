#include "crack2d/consistent_extraction.hpp"

#include "crack2d/crack_closure.hpp"
#include "crack2d/damage_closing.hpp"
#include "crack2d/damage_field.hpp"
#include "crack2d/medial_spurs.hpp"
#include "crack2d/sample_clearance.hpp"
#include "crack2d/sample_grid.hpp"
#include "core/union_find.hpp"
#include "crack2d/voronoi_medial_axis.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>

namespace shellfrac::crack2d {

using core::UnionFind;

namespace {

// All distances below are multiples of the sample spacing h (see docs/crack-extraction.md).
constexpr double kBoundaryRadius = 1.5;      // a damaged sample with an undamaged one this close is a seed
constexpr double kOppositeCos = -0.5;        // seed normals more than 120 degrees apart face each other
constexpr double kDamageProbeStep = 0.5;     // probe spacing along an edge for "inside the damaged region"
constexpr double kNearestSampleRadius = 3.0; // farther than this from every sample counts as undamaged
constexpr double kCoveredByHistory = 0.25;   // a separating edge whose midpoint is this close to L duplicates L
constexpr double kSnapRadius = 0.25;         // a Voronoi node this close to an old crack vertex is that vertex
constexpr double kLinkRadius = 0.75;         // old crack vertices join Voronoi nodes this close
constexpr double kTipLinkRadius = 2.0;       // old tips join Voronoi nodes this close (tip bridging, Fig. 4.8b)
constexpr double kTipPreference = 4.0;       // a bridge to an old tip may be this much longer than the shortest
constexpr double kMaxBridgeLength = 6.0;     // longest Voronoi path accepted as a bridge
constexpr double kExtensionStep = 0.25;      // march step of a tip extension
constexpr double kExtensionPiece = 0.5;      // longest segment of a tip extension
constexpr double kEdgeLigament = 4.0;        // longest damaged ligament from an old tip to the edge
constexpr double kMinFragment = 1.5;         // shorter isolated medial pieces are noise; shorter tips are not extended
constexpr double kTipDirectionLength = 3.0;  // crack length behind a tip that sets the extension direction
constexpr double kSampleClearance = 1e-6;    // shift that moves a new segment off a sample lying on it
// Closure thresholds, in simulation cells c (see docs/crack-extraction.md).
constexpr double kClosingRadius = 0.45;      // closing disc radius: fills speckle and notches up to ~a cell
                                             // (not a lattice distance of a 4 x 4 sampling: 1.8 h)
constexpr double kJoinReach = 1.0;           // tips this close to a crack, cut or the border join it
constexpr double kParallelCover = 1.0;       // a new line beside the crack in the same damaged band duplicates it
constexpr double kSpurProtrusion = 1.0;      // medial branches sticking out of the band by less are spurs
constexpr double kContinuationReach = 4.0;   // tips inside damage continue through it this far
constexpr double kLoopSearch = 16.0;         // ways back through the crack longer than this count as no loop

uint64_t pair_key(int a, int b) {
  const auto lo = static_cast<uint64_t>(static_cast<uint32_t>(std::min(a, b)));
  const auto hi = static_cast<uint64_t>(static_cast<uint32_t>(std::max(a, b)));
  return (lo << 32) | hi;
}

struct Seed {
  Point position;
  Point normal;        // unit outward normal of the damaged region, or zero when undefined
  bool current;        // in D^c (boundary of this extraction's damaged region)
  int historical = -1; // index in LS, or -1
};

// Boundary of the damaged region, D^c (thesis Table 4.2), in sample order: a damaged sample with an
// undamaged one within `radius`; its outward normal is the mean direction to those undamaged samples.
std::vector<Seed> boundary_seeds(const DamageField& field) {
  std::vector<Seed> seeds;
  const std::vector<Point>& points = field.points();
  const std::vector<unsigned char>& damaged = field.flags();
  for (size_t i = 0; i < points.size(); ++i) {
    if (!damaged[i]) continue;
    Point outward = Point::Zero();
    bool boundary = false;
    field.neighbours().for_each(i, [&](int j) {
      if (damaged[j]) return;
      const Point d = points[j] - points[i];
      const double len = d.norm();
      if (len > 0.0) outward += d / len;
      boundary = true;
    });
    if (!boundary) continue;
    const double n = outward.norm();
    seeds.push_back({points[i], n > 1e-12 ? Point(outward / n) : Point(Point::Zero()), true, -1});
  }
  return seeds;
}

// Seeds on opposite sides of the damaged band: their outward normals point apart by more than 120
// degrees and each seed lies behind the other's outward normal, i.e. the damaged band is between them.
// Seeds along one side (normals alike), around a convex corner (normals ~90 degrees apart) or across an
// undamaged notch (each in front of the other) fail this test.
bool on_opposite_sides(const Seed& s, const Seed& t) {
  if (s.normal.isZero() || t.normal.isZero()) return false;
  const Point d = t.position - s.position;
  return s.normal.dot(t.normal) < kOppositeCos && d.dot(s.normal) < 0.0 && d.dot(t.normal) > 0.0;
}

// Walks from a tip along its chain of degree-2 vertices until the walked length reaches `length` or a
// junction/end is met. The chord from there to the tip is the crack direction at the tip, which on a
// staircase-like medial axis of a digitised band is far more faithful than the last Voronoi edge.
int trace_back(const CrackGraph& g, int tip, double length) {
  int previous = tip, current = g.other_end(g.incident_edges(tip)[0], tip);
  double walked = (g.vertices()[current] - g.vertices()[tip]).norm();
  while (walked < length && g.degree(current) == 2) {
    const auto& inc = g.incident_edges(current);
    const int next = g.other_end(inc[0], current) == previous ? g.other_end(inc[1], current) : g.other_end(inc[0], current);
    walked += (g.vertices()[next] - g.vertices()[current]).norm();
    previous = current;
    current = next;
    if (current == tip) break;  // a closed loop
  }
  return current;
}

// Working graph for one extraction: Voronoi nodes [0, n) followed by crack-graph vertices [n, n + m).
struct WorkingEdge {
  int to;
  double length;
  int voronoi_edge;  // index into VoronoiGraph::edges, or -1 for a straight link to an old vertex
};

}  // namespace

ConsistentCrackExtractor::ConsistentCrackExtractor(const Box& domain, double spacing)
    : ConsistentCrackExtractor(domain, spacing, kDefaultSamplesPerCell * spacing) {}

ConsistentCrackExtractor::ConsistentCrackExtractor(const Box& domain, double spacing, double cell)
    : domain_(domain), spacing_(spacing), cell_(cell), index_(domain) {
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw std::invalid_argument("ConsistentCrackExtractor: spacing must be positive and finite, got " +
                                std::to_string(spacing));
  if (!(cell >= spacing) || !std::isfinite(cell))
    throw std::invalid_argument("ConsistentCrackExtractor: cell size must be finite and at least the sample spacing " +
                                std::to_string(spacing) + ", got " + std::to_string(cell));
  if (!(domain.hi.x() > domain.lo.x()) || !(domain.hi.y() > domain.lo.y()))
    throw std::invalid_argument("ConsistentCrackExtractor: domain must have positive extent");
}

void ConsistentCrackExtractor::add_prescribed_cut(const std::vector<Point>& polyline, bool closed) {
  append_cut(graph_, polyline, closed, domain_);
  index_.add_edges(graph_, index_.num_segments());
}

int ConsistentCrackExtractor::historical_seed_id(const Point& p, const Point& normal) {
  const SeedLattice lattice(domain_);
  const uint64_t key = SeedLattice::key(lattice.quantise(p));
  auto [it, inserted] = line_seed_by_key_.emplace(key, static_cast<int>(line_seeds_.size()));
  if (inserted) line_seeds_.push_back({p, normal});
  return it->second;
}

ExtractionStats ConsistentCrackExtractor::extract(const std::vector<Point>& points,
                                                  const std::vector<unsigned char>& damaged) {
  if (points.size() != damaged.size())
    throw std::invalid_argument("ConsistentCrackExtractor::extract: " + std::to_string(points.size()) +
                                " points but " + std::to_string(damaged.size()) + " damage flags");
  ExtractionStats stats;
  const double h = spacing_;
  const CrackGraph previous = graph_;
  const size_t old_vertices = graph_.num_vertices();
  const size_t old_edges = graph_.num_edges();
  const SampleCache& cache = samples_for(points);
  // 0. Regularise the damaged set at the cell scale (closing, pocket filling; crack2d/damage_closing.hpp).
  const std::vector<unsigned char> regular =
      close_damage(damaged, &cache.disc, cache.adjacency, samples_per_cell(), cache.at_edge);
  const DamageField field(cache.points, regular, *cache.grid, cache.adjacency, kNearestSampleRadius * h,
                          kDamageProbeStep * h);
  const SeedLattice lattice(domain_);

  // 1. D' = D^c plus LS (thesis sec. 4.4.2): current boundary seeds first, then historical ones not present.
  std::vector<Seed> seeds = boundary_seeds(field);
  stats.seeds = seeds.size();
  {
    std::vector<char> historical_present(line_seeds_.size(), 0);
    for (Seed& s : seeds) {
      auto it = line_seed_by_key_.find(SeedLattice::key(lattice.quantise(s.position)));
      if (it != line_seed_by_key_.end()) {
        s.historical = it->second;
        historical_present[it->second] = 1;
      }
    }
    for (size_t k = 0; k < line_seeds_.size(); ++k)
      if (!historical_present[k]) seeds.push_back({line_seeds_[k].position, line_seeds_[k].normal, false, static_cast<int>(k)});
  }
  if (seeds.size() < 2) {
    close_graph(field, stats);
    stats.new_edges = graph_.num_edges() - old_edges;
    stats.subset_violations = graph_.contains(previous) ? 0 : 1;
    total_subset_violations_ += stats.subset_violations;
    return stats;
  }
  std::vector<Point> seed_points(seeds.size());
  for (size_t i = 0; i < seeds.size(); ++i) seed_points[i] = seeds[i].position;

  // 2. Voronoi diagram of D', clipped to the patch (Fig. 4.7b).
  const VoronoiGraph voronoi = build_voronoi_graph(seed_points, domain_);
  const int n = static_cast<int>(voronoi.nodes.size());
  const int m = static_cast<int>(old_vertices);

  // 3. Classify Voronoi edges: usable (inside the damaged region) and new medial lines (Fig. 4.8a).
  std::vector<char> usable(voronoi.edges.size(), 0), new_line(voronoi.edges.size(), 0);
  for (size_t e = 0; e < voronoi.edges.size(); ++e) {
    const auto& ve = voronoi.edges[e];
    const Point& a = voronoi.nodes[ve.node_a];
    const Point& b = voronoi.nodes[ve.node_b];
    if (!field.damaged_along(a, b)) continue;
    usable[e] = 1;
    const Seed& s = seeds[ve.seed_a];
    const Seed& t = seeds[ve.seed_b];
    if (!s.current || !t.current || !on_opposite_sides(s, t)) continue;
    // The edge must pass between its seeds: its midpoint sees them under at least 90 degrees (it lies in
    // the disc on the diameter st). Two neighbours on one flank whose noisy normals happen to diverge
    // (non-uniform Gauss samples) have a long bisector far from both and fail this.
    if ((0.5 * (a + b) - 0.5 * (s.position + t.position)).norm() > 0.5 * (s.position - t.position).norm()) continue;
    if (s.historical >= 0 && t.historical >= 0 && line_seed_pairs_.count(pair_key(s.historical, t.historical))) continue;
    if (covered_by_crack(0.5 * (a + b), field)) continue;
    new_line[e] = 1;
  }

  // Voronoi nodes that coincide with old crack vertices are the same node (exact tip continuation).
  const double weld = 1e-9 * std::max(domain_.hi.x() - domain_.lo.x(), domain_.hi.y() - domain_.lo.y());
  std::vector<int> alias(n + m);
  std::iota(alias.begin(), alias.end(), 0);
  std::vector<std::vector<WorkingEdge>> adjacency(n + m);
  {
    const SampleGrid node_grid(voronoi.nodes, kLinkRadius * h);
    for (int v = 0; v < m; ++v) {
      if (graph_.degree(v) == 0) continue;
      const Point& p = graph_.vertices()[v];
      const bool tip = graph_.degree(v) == 1;
      const double radius = (tip ? kTipLinkRadius : kLinkRadius) * h;
      node_grid.for_each_within(p, radius, [&](int k) {
        const double len = (voronoi.nodes[k] - p).norm();
        // A node this close to an old vertex is that vertex: a link of a fraction of a spacing would
        // only add a sliver of a segment at a junction.
        if (len <= kSnapRadius * h) {
          if (alias[k] == k) alias[k] = n + v;
          return;
        }
        if (!field.damaged_along(p, voronoi.nodes[k])) return;
        // A longer tip link must not cut through the crack (its own edges touch it at p only).
        if (len > kLinkRadius * h && index_.crosses(p + (voronoi.nodes[k] - p) * 1e-9, voronoi.nodes[k])) return;
        adjacency[n + v].push_back({k, len, -1});
        adjacency[k].push_back({n + v, len, -1});
      });
    }
  }
  auto node_of = [&](int k) { return alias[k]; };
  // Links attached to an aliased Voronoi node move to its crack vertex.
  for (int k = 0; k < n; ++k) {
    if (alias[k] == k) continue;
    for (const WorkingEdge& w : adjacency[k]) adjacency[alias[k]].push_back(w);
    adjacency[k].clear();
  }
  for (size_t e = 0; e < voronoi.edges.size(); ++e) {
    if (!usable[e]) continue;
    const int a = node_of(voronoi.edges[e].node_a), b = node_of(voronoi.edges[e].node_b);
    if (a == b) continue;
    const double len = (voronoi.nodes[voronoi.edges[e].node_a] - voronoi.nodes[voronoi.edges[e].node_b]).norm();
    adjacency[a].push_back({b, len, static_cast<int>(e)});
    adjacency[b].push_back({a, len, static_cast<int>(e)});
  }
  for (auto& list : adjacency)  // links were appended in node-grid order; fix an order independent of it
    for (auto& w : list) w.to = node_of(w.to);

  // Medial fragments shorter than kMinFragment with no contact to the old crack are sampling noise (they
  // appear at band caps and where the sample spacing jumps); dropping them keeps spurs out of the graph.
  {
    UnionFind fragments(n + m);
    for (const auto& ed : graph_.edges()) fragments.unite(n + ed[0], n + ed[1]);
    std::vector<double> fragment_length(n + m, 0.0);
    std::vector<char> touches_old(n + m, 0);
    for (size_t e = 0; e < voronoi.edges.size(); ++e)
      if (new_line[e]) fragments.unite(node_of(voronoi.edges[e].node_a), node_of(voronoi.edges[e].node_b));
    for (size_t e = 0; e < voronoi.edges.size(); ++e)
      if (new_line[e])
        fragment_length[fragments.find(node_of(voronoi.edges[e].node_a))] +=
            (voronoi.nodes[voronoi.edges[e].node_a] - voronoi.nodes[voronoi.edges[e].node_b]).norm();
    for (int v = 0; v < m; ++v)
      if (graph_.degree(v) > 0) touches_old[fragments.find(n + v)] = 1;
    for (size_t e = 0; e < voronoi.edges.size(); ++e) {
      if (!new_line[e]) continue;
      const int root = fragments.find(node_of(voronoi.edges[e].node_a));
      if (!touches_old[root] && fragment_length[root] < kMinFragment * h) new_line[e] = 0;
    }
  }

  const std::vector<Point> boundary_points = [&] {
    std::vector<Point> pts;
    for (const Seed& s : seeds)
      if (s.current) pts.push_back(s.position);
    return pts;
  }();
  const SampleGrid seed_grid(boundary_points, 2.0 * h);

  // Groups: old crack components and new-line pieces.
  UnionFind groups(n + m);
  std::vector<char> active(n + m, 0), has_old(n + m, 0);
  for (const auto& ed : graph_.edges()) groups.unite(n + ed[0], n + ed[1]);
  for (int v = 0; v < m; ++v)
    if (graph_.degree(v) > 0) active[n + v] = 1;
  std::vector<int> added_voronoi_edges;
  for (size_t e = 0; e < voronoi.edges.size(); ++e) {
    if (!new_line[e]) continue;
    const int a = node_of(voronoi.edges[e].node_a), b = node_of(voronoi.edges[e].node_b);
    if (a == b) continue;
    groups.unite(a, b);
    active[a] = active[b] = 1;
    added_voronoi_edges.push_back(static_cast<int>(e));
  }
  for (int v = 0; v < m; ++v)
    if (active[n + v]) has_old[groups.find(n + v)] = 1;

  // 4. Bridges (Fig. 4.8b, c): connect each new group to its nearest other group along Voronoi edges.
  struct Link {
    int from, to;
    int voronoi_edge;
  };
  std::vector<Link> bridge_links;
  std::vector<double> dist(n + m, std::numeric_limits<double>::infinity());
  std::vector<int> came_from(n + m, -1), came_by(n + m, -1);
  std::vector<int> touched;
  auto bridge_from = [&](std::size_t root) -> bool {
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (int k = 0; k < n + m; ++k)
      if (active[k] && groups.find(k) == root) {
        dist[k] = 0.0;
        touched.push_back(k);
        queue.push({0.0, k});
      }
    // The nearest other group wins, unless an old tip of another group is reachable within
    // kTipPreference spacings more: a crack grows from its tip (Fig. 4.8b), and joining the stem
    // behind the tip would leave the last stretch as a dangling tongue beside the new line.
    int target = -1, tip_target = -1;
    double target_dist = 0.0;
    auto is_old_tip = [&](int k) {
      return k >= n && graph_.degree(k - n) == 1 && !on_box_boundary(graph_.vertices()[k - n], domain_, weld);
    };
    while (!queue.empty()) {
      const auto [d, k] = queue.top();
      queue.pop();
      if (d > dist[k]) continue;
      if (target >= 0 && d > target_dist + kTipPreference * h) break;
      if (active[k] && groups.find(k) != root) {
        if (target < 0) {
          target = k;
          target_dist = d;
        }
        if (is_old_tip(k)) {
          tip_target = k;
          break;
        }
        continue;  // other groups are targets, not ways through
      }
      for (const WorkingEdge& w : adjacency[k]) {
        const double nd = d + w.length;
        if (nd > kMaxBridgeLength * h || nd >= dist[w.to]) continue;
        if (std::isinf(dist[w.to])) touched.push_back(w.to);
        dist[w.to] = nd;
        came_from[w.to] = k;
        came_by[w.to] = w.voronoi_edge;
        queue.push({nd, w.to});
      }
    }
    if (tip_target >= 0) target = tip_target;
    if (target >= 0) {
      const int target_root = groups.find(target);
      const bool to_old = has_old[target_root];
      const bool to_tip = target >= n && graph_.degree(target - n) == 1;
      for (int k = target; dist[k] > 0.0; k = came_from[k]) {
        bridge_links.push_back({came_from[k], k, came_by[k]});
        active[k] = 1;
        groups.unite(k, came_from[k]);
      }
      const int merged = groups.unite(root, target_root);
      has_old[merged] = has_old[merged] || to_old;
      if (to_old && to_tip)
        ++stats.tip_bridges;
      else
        ++stats.branch_links;
    }
    for (int k : touched) {
      dist[k] = std::numeric_limits<double>::infinity();
      came_from[k] = came_by[k] = -1;
    }
    touched.clear();
    return target >= 0;
  };
  // A new group keeps linking while another group is reachable through the damaged region, so a crack
  // that runs into two older ones (merging, Fig. 4.8c) joins both. Every success merges two groups, so
  // this terminates.
  for (int e : added_voronoi_edges) {
    const int start = node_of(voronoi.edges[e].node_a);
    while (bridge_from(groups.find(start))) {
    }
  }

  // Spurs (crack2d/medial_spurs.hpp): short branches into bumps of the band's flank, also those made of
  // a short fragment and the bridge that attached it. Pruned repeatedly: removing a spur can leave the
  // branch it hung from as a spur.
  std::vector<char> keep_line(added_voronoi_edges.size(), 1), keep_link(bridge_links.size(), 1);
  {
    std::vector<std::array<int, 2>> edge_nodes;
    std::vector<double> edge_length;
    auto position = [&](int k) -> const Point& { return k < n ? voronoi.nodes[k] : graph_.vertices()[k - n]; };
    for (int e : added_voronoi_edges) edge_nodes.push_back({node_of(voronoi.edges[e].node_a), node_of(voronoi.edges[e].node_b)});
    for (const Link& l : bridge_links) edge_nodes.push_back({l.from, l.to});
    for (const auto& en : edge_nodes) edge_length.push_back((position(en[0]) - position(en[1])).norm());
    std::vector<char> anchored(n + m, 0);
    std::vector<double> radius(n + m, 0.0);
    for (int k = 0; k < n + m; ++k) {
      anchored[k] = k >= n;
      const int nearest = seed_grid.nearest(position(k), 10.0 * h);
      radius[k] = nearest >= 0 ? (boundary_points[nearest] - position(k)).norm() : 10.0 * h;
    }
    std::vector<char> keep(edge_nodes.size(), 1);
    for (int pass = 0; pass < 8; ++pass) {
      const int pruned = prune_spurs(edge_nodes, edge_length, keep, anchored, radius, kSpurProtrusion * cell_);
      stats.pruned_spurs += static_cast<size_t>(pruned);
      if (pruned == 0) break;
    }
    for (size_t k = 0; k < keep_line.size(); ++k) keep_line[k] = keep[k];
    for (size_t k = 0; k < keep_link.size(); ++k) keep_link[k] = keep[keep_line.size() + k];
  }

  // Keep the new segments off the sample points (crack2d/sample_clearance.hpp): only new Voronoi nodes
  // inside the patch move, by kSampleClearance spacings.
  std::vector<Point> node_position(n + m);
  for (int k = 0; k < n + m; ++k) node_position[k] = k < n ? voronoi.nodes[k] : graph_.vertices()[k - n];
  {
    std::vector<std::array<int, 2>> kept;
    for (size_t k = 0; k < added_voronoi_edges.size(); ++k)
      if (keep_line[k])
        kept.push_back({node_of(voronoi.edges[added_voronoi_edges[k]].node_a), node_of(voronoi.edges[added_voronoi_edges[k]].node_b)});
    for (size_t k = 0; k < bridge_links.size(); ++k)
      if (keep_link[k]) kept.push_back({bridge_links[k].from, bridge_links[k].to});
    std::vector<char> movable(n + m, 0);
    for (int k = 0; k < n; ++k) movable[k] = alias[k] == k && !on_box_boundary(voronoi.nodes[k], domain_, weld);
    clear_samples_off_edges(node_position, kept, movable, cache.points, *cache.grid, kSampleClearance * h);
  }

  // Materialise: new-line edges, then bridges, in discovery order (deterministic).
  std::vector<int> vertex_of(n + m, -1);
  for (int v = 0; v < m; ++v) vertex_of[n + v] = v;
  auto vertex_for = [&](int k) {
    if (vertex_of[k] < 0) vertex_of[k] = graph_.add_vertex(node_position[k]);
    return vertex_of[k];
  };
  auto remember_seeds = [&](int e) {
    const auto& ve = voronoi.edges[e];
    const int a = historical_seed_id(seeds[ve.seed_a].position, seeds[ve.seed_a].normal);
    const int b = historical_seed_id(seeds[ve.seed_b].position, seeds[ve.seed_b].normal);
    line_seed_pairs_.insert(pair_key(a, b));
  };
  for (size_t k = 0; k < added_voronoi_edges.size(); ++k) {
    if (!keep_line[k]) continue;
    const int e = added_voronoi_edges[k];
    graph_.add_edge(vertex_for(node_of(voronoi.edges[e].node_a)), vertex_for(node_of(voronoi.edges[e].node_b)));
    remember_seeds(e);
  }
  for (size_t k = 0; k < bridge_links.size(); ++k) {
    if (!keep_link[k]) continue;
    const Link& l = bridge_links[k];
    graph_.add_edge(vertex_for(l.from), vertex_for(l.to));
    if (l.voronoi_edge >= 0) remember_seeds(l.voronoi_edge);
  }
  index_.add_edges(graph_, old_edges);

  // 5. Extend new tips straight through the remaining damaged region (clipped to the domain). An older
  //    tip is extended only when a short, fully damaged ligament joins it to the patch edge: the band
  //    often reaches the edge after its tip was extracted, and no new medial line forms there.
  const size_t vertices_before_extension = graph_.num_vertices();
  for (size_t v = 0; v < vertices_before_extension; ++v) {
    const int tip = static_cast<int>(v);
    const bool old_tip = v < old_vertices;
    if (graph_.degree(tip) != 1) continue;
    const Point p = graph_.vertices()[tip];
    if (on_box_boundary(p, domain_, weld)) continue;
    // The end of an earlier join that landed inside a segment is no tip (crack2d/crack_closure.hpp).
    bool landed = false;
    for (const uint32_t id : index_.segments_near({p - Point::Constant(weld), p + Point::Constant(weld)}))
      landed = landed || (graph_.edges()[id][0] != tip && graph_.edges()[id][1] != tip &&
                          point_segment_distance(p, index_.segment(id)) <= weld);
    if (landed) continue;
    const Point from = graph_.vertices()[trace_back(graph_, tip, kTipDirectionLength * h)];
    // Only a crack with an established direction is extended; a short stub would point anywhere.
    if ((p - from).norm() < kMinFragment * h) continue;
    const Point dir = (p - from).normalized();
    const int nearest_seed = seed_grid.nearest(p, 10.0 * h);
    const double radius = nearest_seed >= 0 ? (boundary_points[nearest_seed] - p).norm() : 0.0;
    const double max_length = old_tip ? kEdgeLigament * h : 1.5 * radius + h;
    double reached = 0.0;
    bool hit_edge = false;
    for (double t = kExtensionStep * h; t <= max_length + 1e-12; t += kExtensionStep * h) {
      Segment step{p + dir * reached, p + dir * t};
      const bool inside = box_contains(domain_, step.b);
      if (!inside) {
        if (!clip_segment_to_box(step, domain_)) break;
      }
      if (!field.damaged_at(step.b)) break;
      if (index_.crosses(step.a + dir * (1e-6 * h), step.b)) break;
      reached = (step.b - p).norm();
      if (!inside) {
        hit_edge = true;
        break;
      }
    }
    if (reached <= 0.0 || (old_tip && !hit_edge)) continue;
    const int pieces = std::max(1, static_cast<int>(std::ceil(reached / (kExtensionPiece * h))));
    int last = tip;
    for (int k = 1; k <= pieces; ++k) {
      Point q = p + dir * (reached * k / pieces);
      if (hit_edge && k == pieces) {  // land exactly on the patch edge
        Segment s{p, q + dir * (1e-9 * h)};
        clip_segment_to_box(s, domain_);
        q = s.b;
      } else if (segment_hits_sample(graph_.vertices()[last], q, cache.points, *cache.grid)) {
        q += kSampleClearance * h * Point(-dir.y(), dir.x());
      }
      const int next = graph_.add_vertex(q);
      graph_.add_edge(last, next);
      last = next;
    }
    ++stats.tip_extensions;
    index_.add_edges(graph_, index_.num_segments());
  }

  // 6. Closure: separate intact pieces linked by damaged material, join tips to nearby cracks and edges.
  close_graph(field, stats);

  stats.new_edges = graph_.num_edges() - old_edges;
  // 7. Consistency check (thesis Fig. 4.8): the previous crack must survive exactly.
  stats.subset_violations = graph_.contains(previous) ? 0 : 1;
  total_subset_violations_ += stats.subset_violations;
  return stats;
}

bool ConsistentCrackExtractor::covered_by_crack(const Point& p, const DamageField& field) const {
  const CrackIndex::Nearest near = index_.nearest(p, kParallelCover * cell_);
  if (near.segment < 0) return false;
  // Closer than a link radius: a duplicate beside the crack, or a start that overlaps an old tip (which
  // would make a Z-shaped hook); the bridge from the tip covers that stretch instead.
  if (near.distance < kLinkRadius * spacing_) return true;
  // Beside the crack (not ahead of one of its tips) and joined to it through damaged material: the same
  // damaged band already holds a crack line, and a second one would leave a thin tongue or lens of
  // material between the two (issue 12: near-parallel branches merge).
  const auto& ed = graph_.edges()[near.segment];
  for (int k = 0; k < 2; ++k)
    if (near.point == graph_.vertices()[ed[k]] && graph_.degree(ed[k]) == 1) return false;
  return field.damaged_along(p, near.point);
}

const ConsistentCrackExtractor::SampleCache& ConsistentCrackExtractor::samples_for(const std::vector<Point>& points) {
  const bool same = samples_ && samples_->points.size() == points.size() &&
                    (points.empty() || std::memcmp(samples_->points.data(), points.data(), points.size() * sizeof(Point)) == 0);
  if (!same) {
    auto cache = std::make_unique<SampleCache>();
    cache->points = points;
    cache->grid = std::make_unique<SampleGrid>(cache->points, kBoundaryRadius * spacing_);
    cache->adjacency = SampleNeighbours(cache->points, *cache->grid, kBoundaryRadius * spacing_);
    cache->disc = SampleNeighbours(cache->points, *cache->grid, kClosingRadius * cell_);
    cache->at_edge.resize(points.size());
    for (size_t i = 0; i < points.size(); ++i) cache->at_edge[i] = on_box_boundary(points[i], domain_, kClosingRadius * cell_);
    samples_ = std::move(cache);
  }
  return *samples_;
}

size_t ConsistentCrackExtractor::samples_per_cell() const {
  const double per_side = cell_ / spacing_;
  return static_cast<size_t>(std::llround(per_side * per_side));
}

void ConsistentCrackExtractor::close_graph(const DamageField& field, ExtractionStats& stats) {
  ClosureSettings settings;
  settings.spacing = spacing_;
  settings.cell = kJoinReach * cell_;
  settings.neighbour_radius = kBoundaryRadius * spacing_;
  settings.covered = kCoveredByHistory * spacing_;
  settings.loop_search = kLoopSearch * cell_;
  settings.continuation_reach = kContinuationReach * cell_;
  settings.sample_clearance = kSampleClearance * spacing_;
  settings.min_piece = samples_per_cell();
  settings.weld = 1e-9 * std::max(domain_.hi.x() - domain_.lo.x(), domain_.hi.y() - domain_.lo.y());
  ClosureStats closure;
  // Joins first (most gaps are a tip short of a crack or the border), then separation where damaged
  // material still links two intact pieces, then joins again for the ends of the separating lines.
  join_tips(graph_, index_, field, domain_, settings, closure);
  continue_tips(graph_, index_, field, domain_, settings, closure);
  const size_t before = closure.separating_edges;
  separate_intact_pieces(graph_, index_, field, domain_, settings, closure);
  if (closure.separating_edges > before) join_tips(graph_, index_, field, domain_, settings, closure);
  stats.separating_edges = closure.separating_edges;
  stats.crack_joins = closure.crack_joins;
  stats.border_joins = closure.border_joins;
  stats.continuations = closure.continuations;
}

}  // namespace shellfrac::crack2d
