#include "crack2d/consistent_extraction.hpp"

#include "crack2d/crack_closure.hpp"
#include "crack2d/damage_closing.hpp"
#include "crack2d/damage_field.hpp"
#include "crack2d/group_bridges.hpp"
#include "crack2d/medial_spurs.hpp"
#include "crack2d/sample_clearance.hpp"
#include "crack2d/sample_grid.hpp"
#include "crack2d/tip_extension.hpp"
#include "core/union_find.hpp"
#include "crack2d/voronoi_medial_axis.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <memory>
#include <numeric>
#include <stdexcept>
#include <string>
#include <utility>

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

}  // namespace

// The working state of one extract() call, with one member function per stage of the header's list.
// Its working graph holds the Voronoi nodes [0, n) followed by the previous crack's vertices [n, n + m);
// a Voronoi node welded to an old vertex is an alias of it. Stages run in the order extract() calls them
// and only materialise() and extend_tips() change the owner's graph.
class ConsistentCrackExtractor::Pass {
 public:
  Pass(ConsistentCrackExtractor& owner, const SampleCache& cache, const DamageField& field);

  bool collect_seeds(ExtractionStats& stats);  // 1; false when D' has fewer than two seeds
  void build_voronoi();                        // 2
  void classify_edges();                       // 3
  void link_old_vertices();                    // 3
  void connect_voronoi_edges();                // 3
  void drop_noise_fragments();                 // 3
  void group_new_lines();                      // 4
  void bridge_groups(ExtractionStats& stats);  // 4
  void drop_spurs(ExtractionStats& stats);     // 4
  void clear_samples();                        // 4
  void materialise();                          // 4
  void extend_tips(ExtractionStats& stats);    // 5

 private:
  int node_of(int k) const { return alias_[k]; }
  const Point& position(int k) const { return k < n_ ? voronoi_.nodes[k] : graph_.vertices()[k - n_]; }
  void remember_seeds(int voronoi_edge);

  ConsistentCrackExtractor& owner_;
  CrackGraph& graph_;  // the owner's
  CrackIndex& index_;  // the owner's
  const Box& domain_;
  const SampleCache& cache_;
  const DamageField& field_;
  const double h_;      // sample spacing
  const double weld_;   // coincidence tolerance of the parameter plane
  const int m_;         // vertices of the previous crack
  const size_t old_edges_;
  int n_ = 0;           // Voronoi nodes

  std::vector<Seed> seeds_;                   // D' = D^c + LS
  std::vector<Point> boundary_points_;        // positions of the D^c seeds
  std::unique_ptr<SampleGrid> boundary_grid_;  // over boundary_points_
  VoronoiGraph voronoi_;
  std::vector<char> usable_;    // per Voronoi edge: inside the damaged region
  std::vector<char> new_line_;  // per Voronoi edge: a new medial line
  std::vector<int> alias_;      // working node -> the node it is welded to
  std::vector<std::vector<WorkingEdge>> adjacency_;
  UnionFind groups_;            // old crack components and new-line pieces
  std::vector<char> active_, has_old_;  // node on a group; group root holding old crack
  std::vector<int> added_voronoi_edges_;  // the new lines, in Voronoi edge order
  std::vector<BridgeLink> bridge_links_;  // in discovery order
  std::vector<char> keep_line_, keep_link_;  // per added edge / bridge link: survived spur pruning
  std::vector<Point> node_position_;         // working node positions after sample clearance
};

ConsistentCrackExtractor::Pass::Pass(ConsistentCrackExtractor& owner, const SampleCache& cache,
                                     const DamageField& field)
    : owner_(owner),
      graph_(owner.graph_),
      index_(owner.index_),
      domain_(owner.domain_),
      cache_(cache),
      field_(field),
      h_(owner.spacing_),
      weld_(1e-9 * std::max(domain_.hi.x() - domain_.lo.x(), domain_.hi.y() - domain_.lo.y())),
      m_(static_cast<int>(graph_.num_vertices())),
      old_edges_(graph_.num_edges()) {}

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
  const CrackGraph previous = graph_;
  const size_t old_edges = graph_.num_edges();
  const SampleCache& cache = samples_for(points);
  // 0. Regularise the damaged set at the cell scale (closing, pocket filling; crack2d/damage_closing.hpp),
  //    so that seeds follow the damaged band and not the speckle and notches of a single cell.
  const std::vector<unsigned char> regular =
      close_damage(damaged, &cache.disc, cache.adjacency, samples_per_cell(), cache.at_edge);
  const DamageField field(cache.points, regular, *cache.grid, cache.adjacency, kNearestSampleRadius * spacing_,
                          kDamageProbeStep * spacing_);
  Pass pass(*this, cache, field);
  if (pass.collect_seeds(stats)) {  // 1. D' = D^c + LS (a Voronoi diagram needs two seeds)
    pass.build_voronoi();           // 2. Voronoi diagram of D'
    pass.classify_edges();          // 3. usable edges and new lines,
    pass.link_old_vertices();       //    the previous crack welded and linked to the Voronoi nodes,
    pass.connect_voronoi_edges();   //    the usable Voronoi edges joined in,
    pass.drop_noise_fragments();    //    short isolated new lines dropped as noise
    pass.group_new_lines();         // 4. groups of new lines,
    pass.bridge_groups(stats);      //    bridged to old tips and other groups,
    pass.drop_spurs(stats);         //    spurs pruned,
    pass.clear_samples();           //    new nodes moved off the samples,
    pass.materialise();             //    and added to the crack graph
    pass.extend_tips(stats);        // 5. tips continued straight through the damage
  }
  // 6. Closure: separate intact pieces linked by damaged material, join tips to nearby cracks and edges.
  close_graph(field, stats);

  stats.new_edges = graph_.num_edges() - old_edges;
  // 7. Consistency check (thesis Fig. 4.8): the previous crack must survive exactly.
  stats.subset_violations = graph_.contains(previous) ? 0 : 1;
  total_subset_violations_ += stats.subset_violations;
  return stats;
}

// 1. D' = D^c plus LS (thesis sec. 4.4.2): the current boundary seeds first, then the historical seeds
//    not among them. With LS in the diagram, the old lines' Voronoi edges reappear between the same seed
//    pairs, which classify_edges() recognises and skips, instead of shifted duplicates of the old lines.
bool ConsistentCrackExtractor::Pass::collect_seeds(ExtractionStats& stats) {
  const SeedLattice lattice(domain_);
  seeds_ = boundary_seeds(field_);
  stats.seeds = seeds_.size();
  std::vector<char> historical_present(owner_.line_seeds_.size(), 0);
  for (Seed& s : seeds_) {
    auto it = owner_.line_seed_by_key_.find(SeedLattice::key(lattice.quantise(s.position)));
    if (it != owner_.line_seed_by_key_.end()) {
      s.historical = it->second;
      historical_present[it->second] = 1;
    }
  }
  for (size_t k = 0; k < owner_.line_seeds_.size(); ++k)
    if (!historical_present[k])
      seeds_.push_back({owner_.line_seeds_[k].position, owner_.line_seeds_[k].normal, false, static_cast<int>(k)});
  if (seeds_.size() < 2) return false;
  // The distance to the nearest D^c seed is the local half-width of the band (spurs, tip extensions).
  for (const Seed& s : seeds_)
    if (s.current) boundary_points_.push_back(s.position);
  boundary_grid_ = std::make_unique<SampleGrid>(boundary_points_, 2.0 * h_);
  return true;
}

// 2. Voronoi diagram of D', clipped to the patch (Fig. 4.7b): its edges are the candidate crack lines.
void ConsistentCrackExtractor::Pass::build_voronoi() {
  std::vector<Point> seed_points(seeds_.size());
  for (size_t i = 0; i < seeds_.size(); ++i) seed_points[i] = seeds_[i].position;
  voronoi_ = build_voronoi_graph(seed_points, domain_);
  n_ = static_cast<int>(voronoi_.nodes.size());
}

// 3. Classify Voronoi edges: usable ones lie inside the damaged region (the ways bridges may take); new
//    medial lines (Fig. 4.8a) separate two current seeds across the band and repeat no crack already there.
void ConsistentCrackExtractor::Pass::classify_edges() {
  usable_.assign(voronoi_.edges.size(), 0);
  new_line_.assign(voronoi_.edges.size(), 0);
  for (size_t e = 0; e < voronoi_.edges.size(); ++e) {
    const auto& ve = voronoi_.edges[e];
    const Point& a = voronoi_.nodes[ve.node_a];
    const Point& b = voronoi_.nodes[ve.node_b];
    if (!field_.damaged_along(a, b)) continue;
    usable_[e] = 1;
    const Seed& s = seeds_[ve.seed_a];
    const Seed& t = seeds_[ve.seed_b];
    if (!s.current || !t.current || !on_opposite_sides(s, t)) continue;
    // The edge must pass between its seeds: its midpoint sees them under at least 90 degrees (it lies in
    // the disc on the diameter st). Two neighbours on one flank whose noisy normals happen to diverge
    // (non-uniform Gauss samples) have a long bisector far from both and fail this.
    if ((0.5 * (a + b) - 0.5 * (s.position + t.position)).norm() > 0.5 * (s.position - t.position).norm()) continue;
    if (s.historical >= 0 && t.historical >= 0 &&
        owner_.line_seed_pairs_.count(pair_key(s.historical, t.historical)))
      continue;
    if (owner_.covered_by_crack(0.5 * (a + b), field_)) continue;
    new_line_[e] = 1;
  }
}

// 3. The previous crack's vertices enter the working graph. Voronoi nodes that coincide with an old
//    vertex become that vertex (exact tip continuation); nearby nodes get a straight link through the
//    damaged region, from old tips over a longer reach (tip bridging, Fig. 4.8b).
void ConsistentCrackExtractor::Pass::link_old_vertices() {
  alias_.resize(n_ + m_);
  std::iota(alias_.begin(), alias_.end(), 0);
  adjacency_.resize(n_ + m_);
  const SampleGrid node_grid(voronoi_.nodes, kLinkRadius * h_);
  for (int v = 0; v < m_; ++v) {
    if (graph_.degree(v) == 0) continue;
    const Point& p = graph_.vertices()[v];
    const bool tip = graph_.degree(v) == 1;
    const double radius = (tip ? kTipLinkRadius : kLinkRadius) * h_;
    node_grid.for_each_within(p, radius, [&](int k) {
      const double len = (voronoi_.nodes[k] - p).norm();
      // A node this close to an old vertex is that vertex: a link of a fraction of a spacing would
      // only add a sliver of a segment at a junction.
      if (len <= kSnapRadius * h_) {
        if (alias_[k] == k) alias_[k] = n_ + v;
        return;
      }
      if (!field_.damaged_along(p, voronoi_.nodes[k])) return;
      // A longer tip link must not cut through the crack (its own edges touch it at p only).
      if (len > kLinkRadius * h_ && index_.crosses(p + (voronoi_.nodes[k] - p) * 1e-9, voronoi_.nodes[k])) return;
      adjacency_[n_ + v].push_back({k, len, -1});
      adjacency_[k].push_back({n_ + v, len, -1});
    });
  }
}

// 3. The usable Voronoi edges join the working graph between their (welded) ends; links attached to a
//    welded Voronoi node move to its crack vertex.
void ConsistentCrackExtractor::Pass::connect_voronoi_edges() {
  for (int k = 0; k < n_; ++k) {
    if (alias_[k] == k) continue;
    for (const WorkingEdge& w : adjacency_[k]) adjacency_[alias_[k]].push_back(w);
    adjacency_[k].clear();
  }
  for (size_t e = 0; e < voronoi_.edges.size(); ++e) {
    if (!usable_[e]) continue;
    const int a = node_of(voronoi_.edges[e].node_a), b = node_of(voronoi_.edges[e].node_b);
    if (a == b) continue;
    const double len = (voronoi_.nodes[voronoi_.edges[e].node_a] - voronoi_.nodes[voronoi_.edges[e].node_b]).norm();
    adjacency_[a].push_back({b, len, static_cast<int>(e)});
    adjacency_[b].push_back({a, len, static_cast<int>(e)});
  }
  for (auto& list : adjacency_)  // links were appended in node-grid order; fix an order independent of it
    for (auto& w : list) w.to = node_of(w.to);
}

// 3. Medial fragments shorter than kMinFragment with no contact to the old crack are sampling noise (they
//    appear at band caps and where the sample spacing jumps); dropping them keeps spurs out of the graph.
void ConsistentCrackExtractor::Pass::drop_noise_fragments() {
  UnionFind fragments(n_ + m_);
  for (const auto& ed : graph_.edges()) fragments.unite(n_ + ed[0], n_ + ed[1]);
  std::vector<double> fragment_length(n_ + m_, 0.0);
  std::vector<char> touches_old(n_ + m_, 0);
  for (size_t e = 0; e < voronoi_.edges.size(); ++e)
    if (new_line_[e]) fragments.unite(node_of(voronoi_.edges[e].node_a), node_of(voronoi_.edges[e].node_b));
  for (size_t e = 0; e < voronoi_.edges.size(); ++e)
    if (new_line_[e])
      fragment_length[fragments.find(node_of(voronoi_.edges[e].node_a))] +=
          (voronoi_.nodes[voronoi_.edges[e].node_a] - voronoi_.nodes[voronoi_.edges[e].node_b]).norm();
  for (int v = 0; v < m_; ++v)
    if (graph_.degree(v) > 0) touches_old[fragments.find(n_ + v)] = 1;
  for (size_t e = 0; e < voronoi_.edges.size(); ++e) {
    if (!new_line_[e]) continue;
    const int root = fragments.find(node_of(voronoi_.edges[e].node_a));
    if (!touches_old[root] && fragment_length[root] < kMinFragment * h_) new_line_[e] = 0;
  }
}

// 4. Groups: the old crack components and the pieces of new lines, the units that bridges join. The
//    surviving new lines become the first edges to add, in Voronoi edge order.
void ConsistentCrackExtractor::Pass::group_new_lines() {
  groups_ = UnionFind(n_ + m_);
  active_.assign(n_ + m_, 0);
  has_old_.assign(n_ + m_, 0);
  for (const auto& ed : graph_.edges()) groups_.unite(n_ + ed[0], n_ + ed[1]);
  for (int v = 0; v < m_; ++v)
    if (graph_.degree(v) > 0) active_[n_ + v] = 1;
  for (size_t e = 0; e < voronoi_.edges.size(); ++e) {
    if (!new_line_[e]) continue;
    const int a = node_of(voronoi_.edges[e].node_a), b = node_of(voronoi_.edges[e].node_b);
    if (a == b) continue;
    groups_.unite(a, b);
    active_[a] = active_[b] = 1;
    added_voronoi_edges_.push_back(static_cast<int>(e));
  }
  for (int v = 0; v < m_; ++v)
    if (active_[n_ + v]) has_old_[groups_.find(n_ + v)] = 1;
}

// 4. Bridges (crack2d/group_bridges.hpp, Fig. 4.8b, c): each new group is joined along damaged Voronoi
//    edges to its nearest other group, preferring an old tip inside the patch.
void ConsistentCrackExtractor::Pass::bridge_groups(ExtractionStats& stats) {
  BridgeSettings settings;
  settings.max_length = kMaxBridgeLength * h_;
  settings.tip_preference = kTipPreference * h_;
  std::vector<char> old_end(n_ + m_, 0), preferred_tip(n_ + m_, 0);
  for (int v = 0; v < m_; ++v) {
    old_end[n_ + v] = graph_.degree(v) == 1;
    preferred_tip[n_ + v] = old_end[n_ + v] && !on_box_boundary(graph_.vertices()[v], domain_, weld_);
  }
  GroupBridges bridges(adjacency_, groups_, active_, has_old_, std::move(old_end), std::move(preferred_tip),
                       settings);
  for (int e : added_voronoi_edges_) bridges.bridge_group_of(node_of(voronoi_.edges[e].node_a), bridge_links_);
  stats.tip_bridges += bridges.tip_bridges();
  stats.branch_links += bridges.branch_links();
}

// 4. Spurs (crack2d/medial_spurs.hpp): short branches into bumps of the band's flank, also those made of
//    a short fragment and the bridge that attached it. Pruned repeatedly: removing a spur can leave the
//    branch it hung from as a spur.
void ConsistentCrackExtractor::Pass::drop_spurs(ExtractionStats& stats) {
  keep_line_.assign(added_voronoi_edges_.size(), 1);
  keep_link_.assign(bridge_links_.size(), 1);
  std::vector<std::array<int, 2>> edge_nodes;
  std::vector<double> edge_length;
  for (int e : added_voronoi_edges_) edge_nodes.push_back({node_of(voronoi_.edges[e].node_a), node_of(voronoi_.edges[e].node_b)});
  for (const BridgeLink& l : bridge_links_) edge_nodes.push_back({l.from, l.to});
  for (const auto& en : edge_nodes) edge_length.push_back((position(en[0]) - position(en[1])).norm());
  std::vector<char> anchored(n_ + m_, 0);
  std::vector<double> radius(n_ + m_, 0.0);
  for (int k = 0; k < n_ + m_; ++k) {
    anchored[k] = k >= n_;
    const int nearest = boundary_grid_->nearest(position(k), 10.0 * h_);
    radius[k] = nearest >= 0 ? (boundary_points_[nearest] - position(k)).norm() : 10.0 * h_;
  }
  std::vector<char> keep(edge_nodes.size(), 1);
  for (int sweep = 0; sweep < 8; ++sweep) {
    const int pruned = prune_spurs(edge_nodes, edge_length, keep, anchored, radius, kSpurProtrusion * owner_.cell_);
    stats.pruned_spurs += static_cast<size_t>(pruned);
    if (pruned == 0) break;
  }
  for (size_t k = 0; k < keep_line_.size(); ++k) keep_line_[k] = keep[k];
  for (size_t k = 0; k < keep_link_.size(); ++k) keep_link_[k] = keep[keep_line_.size() + k];
}

// 4. Keep the new segments off the sample points (crack2d/sample_clearance.hpp: a sample on a segment
//    would see its control points on neither side). Only new Voronoi nodes inside the patch move, by
//    kSampleClearance spacings; old vertices and nodes on the patch edge stay.
void ConsistentCrackExtractor::Pass::clear_samples() {
  node_position_.resize(n_ + m_);
  for (int k = 0; k < n_ + m_; ++k) node_position_[k] = k < n_ ? voronoi_.nodes[k] : graph_.vertices()[k - n_];
  std::vector<std::array<int, 2>> kept;
  for (size_t k = 0; k < added_voronoi_edges_.size(); ++k)
    if (keep_line_[k])
      kept.push_back({node_of(voronoi_.edges[added_voronoi_edges_[k]].node_a), node_of(voronoi_.edges[added_voronoi_edges_[k]].node_b)});
  for (size_t k = 0; k < bridge_links_.size(); ++k)
    if (keep_link_[k]) kept.push_back({bridge_links_[k].from, bridge_links_[k].to});
  std::vector<char> movable(n_ + m_, 0);
  for (int k = 0; k < n_; ++k) movable[k] = alias_[k] == k && !on_box_boundary(voronoi_.nodes[k], domain_, weld_);
  clear_samples_off_edges(node_position_, kept, movable, cache_.points, *cache_.grid, kSampleClearance * h_);
}

// 4. Materialise: the kept new-line edges, then the kept bridges, in discovery order (deterministic). The
//    seeds of every added Voronoi edge join LS, so the line is never extracted again.
void ConsistentCrackExtractor::Pass::materialise() {
  std::vector<int> vertex_of(n_ + m_, -1);
  for (int v = 0; v < m_; ++v) vertex_of[n_ + v] = v;
  auto vertex_for = [&](int k) {
    if (vertex_of[k] < 0) vertex_of[k] = graph_.add_vertex(node_position_[k]);
    return vertex_of[k];
  };
  for (size_t k = 0; k < added_voronoi_edges_.size(); ++k) {
    if (!keep_line_[k]) continue;
    const int e = added_voronoi_edges_[k];
    graph_.add_edge(vertex_for(node_of(voronoi_.edges[e].node_a)), vertex_for(node_of(voronoi_.edges[e].node_b)));
    remember_seeds(e);
  }
  for (size_t k = 0; k < bridge_links_.size(); ++k) {
    if (!keep_link_[k]) continue;
    const BridgeLink& l = bridge_links_[k];
    graph_.add_edge(vertex_for(l.from), vertex_for(l.to));
    if (l.voronoi_edge >= 0) remember_seeds(l.voronoi_edge);
  }
  index_.add_edges(graph_, old_edges_);
}

void ConsistentCrackExtractor::Pass::remember_seeds(int voronoi_edge) {
  const auto& ve = voronoi_.edges[voronoi_edge];
  const int a = owner_.historical_seed_id(seeds_[ve.seed_a].position, seeds_[ve.seed_a].normal);
  const int b = owner_.historical_seed_id(seeds_[ve.seed_b].position, seeds_[ve.seed_b].normal);
  owner_.line_seed_pairs_.insert(pair_key(a, b));
}

// 5. Extend tips straight through the remaining damaged region (crack2d/tip_extension.hpp): the medial
//    axis stops short of a band's end, and a band that reaches the patch edge must give a crack that does.
void ConsistentCrackExtractor::Pass::extend_tips(ExtractionStats& stats) {
  TipExtensionSettings settings;
  settings.spacing = h_;
  settings.direction_length = kTipDirectionLength * h_;
  settings.min_direction = kMinFragment * h_;
  settings.step = kExtensionStep * h_;
  settings.piece = kExtensionPiece * h_;
  settings.edge_ligament = kEdgeLigament * h_;
  settings.sample_clearance = kSampleClearance * h_;
  settings.weld = weld_;
  stats.tip_extensions += crack2d::extend_tips(graph_, index_, field_, domain_, static_cast<size_t>(m_),
                                               boundary_points_, *boundary_grid_, settings);
}

bool ConsistentCrackExtractor::covered_by_crack(const Point& p, const DamageField& field) const {
  const CrackIndex::Nearest near = index_.nearest(p, kParallelCover * cell_);
  if (near.segment < 0) return false;
  // Closer than a link radius: a duplicate beside the crack, or a start that overlaps an old tip (which
  // would make a Z-shaped hook); the bridge from the tip covers that stretch instead.
  if (near.distance < kLinkRadius * spacing_) return true;
  // Beside the crack (not ahead of one of its tips) and joined to it through damaged material: the same
  // damaged band already holds a crack line, and a second one would leave a thin tongue or lens of
  // material between the two (so near-parallel branches merge).
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
