#include "crack2d/consistent_extraction.hpp"

#include "crack2d/sample_grid.hpp"
#include "crack2d/voronoi_medial_axis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <queue>
#include <stdexcept>
#include <string>

namespace shellfrac::crack2d {

namespace {

// All distances below are multiples of the sample spacing h (see docs/crack-extraction.md).
constexpr double kBoundaryRadius = 1.5;      // a damaged sample with an undamaged one this close is a seed
constexpr double kOppositeCos = -0.5;        // seed normals more than 120 degrees apart face each other
constexpr double kDamageProbeStep = 0.5;     // probe spacing along an edge for "inside the damaged region"
constexpr double kNearestSampleRadius = 3.0; // farther than this from every sample counts as undamaged
constexpr double kCoveredByHistory = 0.25;   // a new edge whose midpoint is this close to L duplicates L
constexpr double kLinkRadius = 0.75;         // old crack vertices join Voronoi nodes this close
constexpr double kMaxBridgeLength = 6.0;     // longest Voronoi path accepted as a bridge
constexpr double kExtensionStep = 0.25;      // march step of a tip extension
constexpr double kExtensionPiece = 0.5;      // longest segment of a tip extension
constexpr double kEdgeLigament = 4.0;        // longest damaged ligament from an old tip to the edge
constexpr double kMinFragment = 1.5;         // shorter isolated medial pieces are noise; shorter tips are not extended
constexpr double kTipDirectionLength = 3.0;  // crack length behind a tip that sets the extension direction

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

// "Inside the fully damaged region": the nearest sample point is damaged (thesis sec. 4.4.2).
class DamageField {
 public:
  DamageField(const std::vector<Point>& points, const std::vector<unsigned char>& damaged, double h)
      : points_(points), damaged_(damaged), grid_(points, kBoundaryRadius * h), h_(h) {}

  const SampleGrid& grid() const { return grid_; }

  bool damaged_at(const Point& p) const {
    const int i = grid_.nearest(p, kNearestSampleRadius * h_);
    return i >= 0 && damaged_[i] != 0;
  }
  bool damaged_along(const Point& a, const Point& b) const {
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (kDamageProbeStep * h_))));
    for (int k = 0; k <= steps; ++k)
      if (!damaged_at(a + (b - a) * (static_cast<double>(k) / steps))) return false;
    return true;
  }

  // Boundary of the damaged region, D^c (thesis Table 4.2), in sample order.
  std::vector<Seed> boundary_seeds() const {
    std::vector<Seed> seeds;
    const double radius = kBoundaryRadius * h_;
    for (size_t i = 0; i < points_.size(); ++i) {
      if (!damaged_[i]) continue;
      Point outward = Point::Zero();
      bool boundary = false;
      grid_.for_each_within(points_[i], radius, [&](int j) {
        if (damaged_[j]) return;
        const Point d = points_[j] - points_[i];
        const double len = d.norm();
        if (len > 0.0) outward += d / len;
        boundary = true;
      });
      if (!boundary) continue;
      const double n = outward.norm();
      seeds.push_back({points_[i], n > 1e-12 ? Point(outward / n) : Point(Point::Zero()), true, -1});
    }
    return seeds;
  }

 private:
  const std::vector<Point>& points_;
  const std::vector<unsigned char>& damaged_;
  SampleGrid grid_;
  double h_;
};

// Seeds on opposite sides of the damaged band: their outward normals point apart by more than 120
// degrees and each seed lies behind the other's outward normal, i.e. the damaged band is between them.
// Seeds along one side (normals alike), around a convex corner (normals ~90 degrees apart) or across an
// undamaged notch (each in front of the other) fail this test.
bool on_opposite_sides(const Seed& s, const Seed& t) {
  if (s.normal.isZero() || t.normal.isZero()) return false;
  const Point d = t.position - s.position;
  return s.normal.dot(t.normal) < kOppositeCos && d.dot(s.normal) < 0.0 && d.dot(t.normal) > 0.0;
}

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), 0); }
  int find(int x) {
    while (parent_[x] != x) x = parent_[x] = parent_[parent_[x]];
    return x;
  }
  // The smaller root wins so that labels do not depend on union order.
  int unite(int a, int b) {
    a = find(a);
    b = find(b);
    if (a == b) return a;
    if (b < a) std::swap(a, b);
    parent_[b] = a;
    return a;
  }

 private:
  std::vector<int> parent_;
};

bool on_domain_boundary(const Point& p, const Box& box, double tol) {
  return p.x() <= box.lo.x() + tol || p.x() >= box.hi.x() - tol || p.y() <= box.lo.y() + tol || p.y() >= box.hi.y() - tol;
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
    : domain_(domain), spacing_(spacing), index_(domain) {
  if (!(spacing > 0.0) || !std::isfinite(spacing))
    throw std::invalid_argument("ConsistentCrackExtractor: spacing must be positive and finite, got " +
                                std::to_string(spacing));
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
  const DamageField field(points, damaged, h);
  const SeedLattice lattice(domain_);

  // 1. D' = D^c plus LS (thesis sec. 4.4.2): current boundary seeds first, then historical ones not present.
  std::vector<Seed> seeds = field.boundary_seeds();
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
    total_subset_violations_ += graph_.contains(previous) ? 0 : 1;
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
    if (s.historical >= 0 && t.historical >= 0 && line_seed_pairs_.count(pair_key(s.historical, t.historical))) continue;
    const double covered = kCoveredByHistory * h;
    if (index_.distance(0.5 * (a + b), covered) < covered) continue;
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
      node_grid.for_each_within(p, kLinkRadius * h, [&](int k) {
        if ((voronoi.nodes[k] - p).norm() <= weld) {
          if (alias[k] == k) alias[k] = n + v;
          return;
        }
        if (!field.damaged_along(p, voronoi.nodes[k])) return;
        const double len = (voronoi.nodes[k] - p).norm();
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
  auto bridge_from = [&](int root) -> bool {
    using Item = std::pair<double, int>;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    for (int k = 0; k < n + m; ++k)
      if (active[k] && groups.find(k) == root) {
        dist[k] = 0.0;
        touched.push_back(k);
        queue.push({0.0, k});
      }
    int target = -1;
    while (!queue.empty()) {
      const auto [d, k] = queue.top();
      queue.pop();
      if (d > dist[k]) continue;
      if (active[k] && groups.find(k) != root) {
        target = k;
        break;
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

  // Materialise: new-line edges, then bridges, in discovery order (deterministic).
  std::vector<int> vertex_of(n + m, -1);
  for (int v = 0; v < m; ++v) vertex_of[n + v] = v;
  auto vertex_for = [&](int k) {
    if (vertex_of[k] < 0) vertex_of[k] = graph_.add_vertex(voronoi.nodes[k]);
    return vertex_of[k];
  };
  auto remember_seeds = [&](int e) {
    const auto& ve = voronoi.edges[e];
    const int a = historical_seed_id(seeds[ve.seed_a].position, seeds[ve.seed_a].normal);
    const int b = historical_seed_id(seeds[ve.seed_b].position, seeds[ve.seed_b].normal);
    line_seed_pairs_.insert(pair_key(a, b));
  };
  for (int e : added_voronoi_edges) {
    graph_.add_edge(vertex_for(node_of(voronoi.edges[e].node_a)), vertex_for(node_of(voronoi.edges[e].node_b)));
    remember_seeds(e);
  }
  for (const Link& l : bridge_links) {
    graph_.add_edge(vertex_for(l.from), vertex_for(l.to));
    if (l.voronoi_edge >= 0) remember_seeds(l.voronoi_edge);
  }
  index_.add_edges(graph_, old_edges);

  // 5. Extend new tips straight through the remaining damaged region (clipped to the domain). An older
  //    tip is extended only when a short, fully damaged ligament joins it to the patch edge: the band
  //    often reaches the edge after its tip was extracted, and no new medial line forms there.
  const std::vector<Point> boundary_points = [&] {
    std::vector<Point> pts;
    for (const Seed& s : seeds)
      if (s.current) pts.push_back(s.position);
    return pts;
  }();
  const SampleGrid seed_grid(boundary_points, 2.0 * h);
  const size_t vertices_before_extension = graph_.num_vertices();
  for (size_t v = 0; v < vertices_before_extension; ++v) {
    const int tip = static_cast<int>(v);
    const bool old_tip = v < old_vertices;
    if (graph_.degree(tip) != 1) continue;
    const Point p = graph_.vertices()[tip];
    if (on_domain_boundary(p, domain_, weld)) continue;
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
      }
      const int next = graph_.add_vertex(q);
      graph_.add_edge(last, next);
      last = next;
    }
    ++stats.tip_extensions;
    index_.add_edges(graph_, index_.num_segments());
  }

  stats.new_edges = graph_.num_edges() - old_edges;
  // 6. Consistency check (thesis Fig. 4.8): the previous crack must survive exactly.
  stats.subset_violations = graph_.contains(previous) ? 0 : 1;
  total_subset_violations_ += stats.subset_violations;
  return stats;
}

}  // namespace shellfrac::crack2d
