#include "crack2d/crack_closure.hpp"

#include "crack2d/sample_clearance.hpp"
#include "core/union_find.hpp"
#include "crack2d/voronoi_medial_axis.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>

namespace shellfrac::crack2d {

using core::UnionFind;

namespace {

// Marks the samples within `radius` of any crack segment: only pairs of such samples can be separated
// by the crack, so only they need the exact visibility test.
std::vector<char> near_crack(const DamageField& field, const CrackIndex& index, double radius, double step) {
  std::vector<char> near(field.points().size(), 0);
  for (size_t e = 0; e < index.num_segments(); ++e) {
    const Segment& s = index.segment(e);
    const double len = (s.b - s.a).norm();
    const int probes = std::max(1, static_cast<int>(std::ceil(len / step)));
    // Probes every <= step along the segment; every point of it lies within step/2 of one.
    for (int k = 0; k <= probes; ++k) {
      const Point p = s.a + (s.b - s.a) * (static_cast<double>(k) / probes);
      field.grid().for_each_within(p, radius + 0.5 * step, [&](int i) { near[i] = 1; });
    }
  }
  return near;
}

// Boundary of the intact material: intact samples with a damaged neighbour, in index order.
std::vector<int> intact_boundary(const DamageField& field) {
  const std::vector<unsigned char>& damaged = field.flags();
  const size_t n = field.points().size();
  std::vector<char> is_site(n, 0);
  for (size_t j = 0; j < n; ++j)
    if (damaged[j]) field.neighbours().for_each(j, [&](int i) { is_site[i] = !damaged[i]; });
  std::vector<int> sites;
  for (size_t i = 0; i < n; ++i)
    if (is_site[i]) sites.push_back(static_cast<int>(i));
  return sites;
}

// Per site, the intact piece it belongs to (intact samples joined to their intact neighbours unless the
// crack lies between them), or -1 for pieces smaller than settings.min_piece: no crack is drawn around a
// sliver. Empty if the damaged material borders one piece only (nothing to separate).
std::vector<int> piece_labels(const DamageField& field, const CrackIndex& index, const std::vector<int>& sites,
                              const ClosureSettings& settings) {
  const std::vector<Point>& pts = field.points();
  const std::vector<unsigned char>& damaged = field.flags();
  const size_t n = pts.size();
  const std::vector<char> near = near_crack(field, index, settings.neighbour_radius, settings.spacing);
  UnionFind pieces(n);
  for (size_t i = 0; i < n; ++i) {
    if (damaged[i]) continue;
    field.neighbours().for_each(i, [&](int j) {
      if (j <= static_cast<int>(i) || damaged[j]) return;
      if (near[i] && near[j] && index.crosses(pts[i], pts[j])) return;
      pieces.unite(static_cast<int>(i), j);
    });
  }
  std::vector<size_t> piece_size(n, 0);
  for (size_t i = 0; i < n; ++i)
    if (!damaged[i]) ++piece_size[pieces.find(static_cast<int>(i))];
  std::vector<int> label(sites.size(), -1);
  int first_label = -1;
  bool several = false;
  for (size_t k = 0; k < sites.size(); ++k) {
    const int root = pieces.find(sites[k]);
    if (piece_size[root] < settings.min_piece) continue;
    label[k] = root;
    if (first_label < 0) first_label = root;
    several = several || root != first_label;
  }
  if (!several) label.clear();
  return label;
}

// Adds the chosen Voronoi edges to the graph, their nodes off the sample points
// (crack2d/sample_clearance.hpp: nodes inside the patch may move a hair). Returns the edges added.
size_t add_voronoi_edges(CrackGraph& graph, const VoronoiGraph& voronoi, const std::vector<int>& chosen,
                         const DamageField& field, const Box& domain, const ClosureSettings& settings) {
  std::vector<Point> node_position = voronoi.nodes;
  std::vector<std::array<int, 2>> edges;
  for (int e : chosen) edges.push_back({voronoi.edges[e].node_a, voronoi.edges[e].node_b});
  std::vector<char> movable(voronoi.nodes.size());
  for (size_t k = 0; k < movable.size(); ++k) movable[k] = !on_box_boundary(voronoi.nodes[k], domain, settings.weld);
  clear_samples_off_edges(node_position, edges, movable, field.points(), field.grid(), settings.sample_clearance);
  const size_t first_edge = graph.num_edges();
  std::vector<int> vertex_of(voronoi.nodes.size(), -1);
  auto vertex_for = [&](int node) {
    if (vertex_of[node] < 0) vertex_of[node] = graph.add_vertex(node_position[node]);
    return vertex_of[node];
  };
  for (int e : chosen) graph.add_edge(vertex_for(voronoi.edges[e].node_a), vertex_for(voronoi.edges[e].node_b));
  return graph.num_edges() - first_edge;
}

}  // namespace

void separate_intact_pieces(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
                            const ClosureSettings& settings, ClosureStats& stats) {
  const std::vector<int> sites = intact_boundary(field);
  if (sites.size() < 2) return;
  const std::vector<int> label = piece_labels(field, index, sites, settings);
  if (label.empty()) return;

  std::vector<Point> site_points(sites.size());
  for (size_t k = 0; k < sites.size(); ++k) site_points[k] = field.points()[sites[k]];
  const VoronoiGraph voronoi = build_voronoi_graph(site_points, domain);

  // A Voronoi edge between sites of two different pieces that see each other (the straight path between
  // them crosses no crack) is a path from one piece to the other through damaged material, cut exactly
  // by that edge: it joins the crack.
  std::vector<int> chosen;
  for (size_t e = 0; e < voronoi.edges.size(); ++e) {
    const auto& ve = voronoi.edges[e];
    const int la = label[ve.seed_a], lb = label[ve.seed_b];
    if (la < 0 || lb < 0 || la == lb) continue;
    const Point& a = voronoi.nodes[ve.node_a];
    const Point& b = voronoi.nodes[ve.node_b];
    if (!field.damaged_along(a, b)) continue;
    if (index.crosses(site_points[ve.seed_a], site_points[ve.seed_b])) continue;
    if (index.distance(0.5 * (a + b), settings.covered) < settings.covered) continue;
    chosen.push_back(static_cast<int>(e));
  }
  if (chosen.empty()) return;
  const size_t first_edge = graph.num_edges();
  stats.separating_edges += add_voronoi_edges(graph, voronoi, chosen, field, domain, settings);
  index.add_edges(graph, first_edge);
}

namespace {

// A join that lands inside a segment ends on a vertex of its own (the graph is append-only, so the
// segment is not split); that vertex is attached to the segment's two ends for path lengths.
struct Attachment {
  int vertex;
  int edge;
};

// Crack-graph distances from `source` up to `bound` (Dijkstra; ties by vertex index), walking the
// attachments as well.
struct PathTree {
  std::vector<double> dist;
  std::vector<int> previous;
};

PathTree graph_distances(const CrackGraph& g, const std::vector<std::vector<int>>& attached_to,
                         const std::vector<Attachment>& attachments, int source, double bound) {
  PathTree tree;
  std::vector<double>& dist = tree.dist;
  dist.assign(g.num_vertices(), std::numeric_limits<double>::infinity());
  tree.previous.assign(g.num_vertices(), -1);
  using Item = std::pair<double, int>;
  std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
  dist[source] = 0.0;
  queue.push({0.0, source});
  auto relax = [&](double d, int v, int w) {
    const double nd = d + (g.vertices()[w] - g.vertices()[v]).norm();
    if (nd > bound || nd >= dist[w]) return;
    dist[w] = nd;
    tree.previous[w] = v;
    queue.push({nd, w});
  };
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > dist[v]) continue;
    for (int e : g.incident_edges(v)) relax(d, v, g.other_end(e, v));
    for (int k : attached_to[v]) {
      const Attachment& at = attachments[k];
      if (at.vertex == v) {
        relax(d, v, g.edges()[at.edge][0]);
        relax(d, v, g.edges()[at.edge][1]);
      } else {
        relax(d, v, at.vertex);
      }
    }
  }
  return tree;
}

// Which side of the box p lies on (0: u = lo, 1: u = hi, 2: v = lo, 3: v = hi), or -1.
int border_side(const Point& p, const Box& box, double tol) {
  if (p.x() <= box.lo.x() + tol) return 0;
  if (p.x() >= box.hi.x() - tol) return 1;
  if (p.y() <= box.lo.y() + tol) return 2;
  if (p.y() >= box.hi.y() - tol) return 3;
  return -1;
}

// Crossing-number test; points on the outline may fall either way (they are samples, not crack points).
bool inside_polygon(const Point& p, const std::vector<Point>& poly) {
  bool inside = false;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) {
    const Point &a = poly[i], &b = poly[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) && p.x() < a.x() + (p.y() - a.y()) * (b.x() - a.x()) / (b.y() - a.y()))
      inside = !inside;
  }
  return inside;
}

// Tips of the crack graph and what is needed to join them to a target: attachments of earlier joins,
// the loop test and the "touches nothing else" test.
class TipCloser {
 public:
  struct Target {
    int kind;       // 0: crack segment, 1: patch border
    uint32_t id;    // segment index, or border side
    Point q;        // end on the target
    int vertex;     // existing crack vertex at q, or -1
  };

  TipCloser(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
            const ClosureSettings& settings)
      : graph_(graph), index_(index), field_(field), domain_(domain), settings_(settings), attached_to_(graph.num_vertices()) {
    for (size_t v = 0; v < graph_.num_vertices(); ++v) {
      const int vi = static_cast<int>(v);
      if (graph_.degree(vi) != 1 || on_box_boundary(graph_.vertices()[v], domain_, settings_.weld)) continue;
      const Point& p = graph_.vertices()[v];
      bool on_segment = false;
      for (const uint32_t id : index_.segments_near({p - Point::Constant(settings_.weld), p + Point::Constant(settings_.weld)})) {
        const auto& ed = graph_.edges()[id];
        if (ed[0] == vi || ed[1] == vi || point_segment_distance(p, index_.segment(id)) > settings_.weld) continue;
        attach(vi, static_cast<int>(id));
        on_segment = true;
      }
      if (!on_segment) tips_.push_back(vi);
    }
  }

  // Free tips (degree 1, off the border, not the end of an earlier join), in vertex order.
  const std::vector<int>& tips() const { return tips_; }
  bool still_free(int tip) const { return graph_.degree(tip) == 1; }

  // Nearest point of segment id to p, snapped to an end vertex when it coincides with one.
  Target on_segment(uint32_t id, const Point& p) const {
    const auto& ed = graph_.edges()[id];
    const Point a = graph_.vertices()[ed[0]], b = graph_.vertices()[ed[1]];
    const Point d = b - a;
    const double len2 = d.squaredNorm();
    const double s = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
    Target t{0, id, a + s * d, -1};
    if ((t.q - a).norm() <= settings_.weld) t.vertex = ed[0], t.q = a;
    else if ((t.q - b).norm() <= settings_.weld) t.vertex = ed[1], t.q = b;
    return t;
  }
  bool incident(uint32_t id, int vertex) const { return graph_.edges()[id][0] == vertex || graph_.edges()[id][1] == vertex; }

  // Intact samples enclosed by a link from the tip to c together with the shortest way back to the tip
  // through the crack (and along the border); SIZE_MAX when there is no such way within the search
  // bound. A link that closes a loop only around damaged material would cut rubble out of the band.
  // Intact samples inside the loop that landing `tip` on `c` would close (max() when it closes none),
  // and whether that loop runs around a corner of the patch (the crack meets one border side and
  // lands on the adjacent one).
  struct Enclosure {
    size_t intact = std::numeric_limits<size_t>::max();
    bool around_corner = false;
  };
  size_t enclosed_intact(int tip, const Target& c) { return enclosure(tip, c).intact; }
  Enclosure enclosure(int tip, const Target& c) {
    if (tree_tip_ != tip) {
      tree_ = graph_distances(graph_, attached_to_, attachments_, tip, settings_.loop_search);
      tree_tip_ = tip;
    }
    double best = std::numeric_limits<double>::infinity();
    int via = -1;
    Point corner = Point::Zero();
    bool use_corner = false;
    if (c.kind == 0) {
      const auto& ed = graph_.edges()[c.id];
      for (int k = 0; k < 2; ++k) {
        const double len = tree_.dist[ed[k]] + (graph_.vertices()[ed[k]] - c.q).norm();
        if (len < best) best = len, via = ed[k];
      }
    } else {
      const int side_q = static_cast<int>(c.id);
      for (size_t w = 0; w < tree_.dist.size(); ++w) {
        if (!std::isfinite(tree_.dist[w])) continue;
        const Point& pw = graph_.vertices()[w];
        const int side_w = border_side(pw, domain_, settings_.weld);
        if (side_w < 0 || (side_w / 2 == side_q / 2 && side_w != side_q)) continue;  // opposite sides: a wide loop
        const double len = tree_.dist[w] + (pw - c.q).lpNorm<1>();
        if (len < best) {
          best = len, via = static_cast<int>(w);
          use_corner = side_w != side_q;
          // Adjacent sides meet at the corner with the u of the vertical side and the v of the horizontal one.
          const Point& vertical = side_q < 2 ? c.q : pw;
          const Point& horizontal = side_q < 2 ? pw : c.q;
          corner = Point(vertical.x(), horizontal.y());
        }
      }
    }
    if (via < 0 || !std::isfinite(best)) return {};
    std::vector<Point> loop{graph_.vertices()[tip], c.q};
    if (use_corner) loop.push_back(corner);
    for (int v = via; v >= 0 && v != tip; v = tree_.previous[v]) loop.push_back(graph_.vertices()[v]);
    Point lo = loop[0], hi = loop[0];
    for (const Point& q : loop) lo = lo.cwiseMin(q), hi = hi.cwiseMax(q);
    size_t intact = 0;
    field_.grid().for_each_within(0.5 * (lo + hi), 0.5 * (hi - lo).norm(), [&](int i) {
      if (!field_.flags()[i] && inside_polygon(field_.points()[i], loop)) ++intact;
    });
    return {intact, use_corner};
  }

  // The segment ab touches no crack segment, except the tip's own edges (when a is the tip) and the
  // target (when b is its end q).
  bool clear(const Point& a, const Point& b, int tip, const Target* target) const {
    const Box span{a.cwiseMin(b), a.cwiseMax(b)};
    for (const uint32_t id : index_.segments_near(span)) {
      if (tip >= 0 && incident(id, tip)) continue;
      if (target && target->kind == 0 && id == target->id) continue;
      if (target && target->vertex >= 0 && incident(id, target->vertex)) continue;
      const Segment s = index_.segment(id);
      if (segments_intersect(a, b, s.a, s.b)) return false;
    }
    return true;
  }

  // Adds the crack vertex at the target end (unless it is an existing vertex) and the edge from `from`.
  void land(int from, const Target& c) {
    int target = c.vertex;
    if (target < 0) {
      Point q = c.q;
      const Point p = graph_.vertices()[from];
      if (segment_hits_sample(p, q, field_.points(), field_.grid())) {
        // Off the samples (crack2d/sample_clearance.hpp): slide the end a hair along the target, into
        // the patch or towards the middle of the target segment.
        if (c.kind == 1) {
          q += settings_.sample_clearance * (c.id < 2 ? Point(0.0, 1.0) : Point(1.0, 0.0));
          if (!box_contains(domain_, q)) q -= 2.0 * settings_.sample_clearance * (c.id < 2 ? Point(0.0, 1.0) : Point(1.0, 0.0));
        } else {
          const Segment s = index_.segment(c.id);
          const Point inward = 0.5 * (s.a + s.b) - q;
          if (inward.norm() > settings_.sample_clearance) q += settings_.sample_clearance * inward.normalized();
        }
      }
      if (c.kind == 0) {
        // The rounded projection may stop a hair short of the target segment; move it over so the
        // link and the target share a point exactly (the overshoot is a few ulps). Should that fail,
        // the link ends on the target's nearer end vertex instead.
        const Segment s = index_.segment(c.id);
        const Point base = q, dir = (base - p).normalized();
        double eps = 1e-15 * std::max(1.0, base.cwiseAbs().maxCoeff());
        for (int k = 0; k < 30 && !segments_intersect(p, q, s.a, s.b); ++k, eps *= 2.0) q = base + dir * eps;
        if (!segments_intersect(p, q, s.a, s.b)) {
          const auto& ed = graph_.edges()[c.id];
          target = (graph_.vertices()[ed[0]] - base).norm() <= (graph_.vertices()[ed[1]] - base).norm() ? ed[0] : ed[1];
        }
      }
      if (target < 0) {
        target = add_vertex(q);
        if (c.kind == 0) attach(target, static_cast<int>(c.id));
      }
    }
    add_edge(from, target);
  }

  int add_vertex(const Point& p) {
    const int v = graph_.add_vertex(p);
    attached_to_.resize(graph_.num_vertices());
    return v;
  }
  void add_edge(int a, int b) {
    const size_t first_edge = graph_.num_edges();
    graph_.add_edge(a, b);
    index_.add_edges(graph_, first_edge);
    tree_tip_ = -1;  // the graph changed
  }

  // The border points nearest to p, one per side.
  std::array<Target, 4> border_targets(const Point& p) const {
    return {Target{1, 0, Point(domain_.lo.x(), p.y()), -1}, Target{1, 1, Point(domain_.hi.x(), p.y()), -1},
            Target{1, 2, Point(p.x(), domain_.lo.y()), -1}, Target{1, 3, Point(p.x(), domain_.hi.y()), -1}};
  }

 private:
  void attach(int vertex, int edge) {
    attached_to_.resize(graph_.num_vertices());
    const int k = static_cast<int>(attachments_.size());
    attachments_.push_back({vertex, edge});
    attached_to_[vertex].push_back(k);
    attached_to_[graph_.edges()[edge][0]].push_back(k);
    attached_to_[graph_.edges()[edge][1]].push_back(k);
  }

  CrackGraph& graph_;
  CrackIndex& index_;
  const DamageField& field_;
  const Box& domain_;
  const ClosureSettings& settings_;
  std::vector<int> tips_;
  std::vector<Attachment> attachments_;
  std::vector<std::vector<int>> attached_to_;
  PathTree tree_;
  int tree_tip_ = -1;
};

// Continues free crack tips through the damaged samples (continue_tips): per tip, the shortest way
// through damaged samples that crosses no crack to a sample next to another crack, a cut or the border,
// then that way straightened and laid into the graph.
class TipContinuation {
 public:
  using Target = TipCloser::Target;
  TipContinuation(TipCloser& closer, CrackIndex& index, const DamageField& field, const ClosureSettings& settings)
      : closer_(closer), index_(index), field_(field), settings_(settings), pts_(field.points()),
        dist_(pts_.size(), std::numeric_limits<double>::infinity()), previous_(pts_.size(), -1) {}

  // True if the tip was continued.
  bool run(int tip, const Point& p) {
    Target target{};
    const int reached = search(tip, p, target);
    const bool laid = reached >= 0 && lay(tip, p, reached, target);
    for (int s : touched_) {
      dist_[s] = std::numeric_limits<double>::infinity();
      previous_[s] = -1;
    }
    touched_.clear();
    return laid;
  }

 private:
  // Dijkstra over the sample adjacency from the tip, bounded by the continuation reach: the first
  // sample with an acceptable target beside it (-1: none).
  int search(int tip, const Point& p, Target& target) {
    using Item = std::pair<double, int>;
    const std::vector<unsigned char>& damaged = field_.flags();
    const double r = settings_.neighbour_radius;
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    field_.grid().for_each_within(p, r, [&](int s) {
      if (!damaged[s] || !closer_.clear(p, pts_[s], tip, nullptr)) return;
      const double d = (pts_[s] - p).norm();
      if (d < dist_[s]) {
        if (std::isinf(dist_[s])) touched_.push_back(s);
        dist_[s] = d;
        previous_[s] = -1;
        queue.push({d, s});
      }
    });
    while (!queue.empty()) {
      const auto [d, s] = queue.top();
      queue.pop();
      if (d > dist_[s]) continue;
      if (target_beside(tip, s, target)) return s;
      field_.neighbours().for_each(static_cast<size_t>(s), [&](int t) {
        if (!damaged[t] || t == s) return;
        const double nd = d + (pts_[t] - pts_[s]).norm();
        if (nd > settings_.continuation_reach || nd >= dist_[t]) return;
        if (!closer_.clear(pts_[s], pts_[t], -1, nullptr)) return;
        if (std::isinf(dist_[t])) touched_.push_back(t);
        dist_[t] = nd;
        previous_[t] = s;
        queue.push({nd, t});
      });
    }
    return -1;
  }

  // A target next to sample s: the nearest crack point (not the tip's own edges) or the border.
  bool target_beside(int tip, int s, Target& target) {
    const double r = settings_.neighbour_radius;
    std::vector<Target> candidates;
    const CrackIndex::Nearest near = index_.nearest(pts_[s], r);
    if (near.segment >= 0 && !closer_.incident(static_cast<uint32_t>(near.segment), tip))
      candidates.push_back(closer_.on_segment(static_cast<uint32_t>(near.segment), pts_[s]));
    for (const Target& t : closer_.border_targets(pts_[s]))
      if ((t.q - pts_[s]).norm() <= r) candidates.push_back(t);
    for (const Target& c : candidates) {
      if (!field_.damaged_along(pts_[s], c.q) || !closer_.clear(pts_[s], c.q, -1, &c)) continue;
      // Only towards another crack (or a border the crack does not reach): a way back to the tip's
      // own crack would run back through its own damage band and cut out the material beside it;
      // where such a loop is really needed, the separation pass finds it. The exception is a loop
      // around a patch corner that encloses no intact sample: a fully damaged corner (the pinned
      // corner of a torn cloth) has no strength left, and left attached it hangs on as a strand.
      const TipCloser::Enclosure loop = closer_.enclosure(tip, c);
      const bool damaged_corner = c.kind != 0 && loop.around_corner && loop.intact == 0;
      if (loop.intact != std::numeric_limits<size_t>::max() && !damaged_corner) continue;
      target = c;
      return true;
    }
    return false;
  }

  // The path tip -> samples -> target, through the midpoints between consecutive samples (a crack
  // through a sample would leave it without a side), straightened: from each kept point, the farthest
  // later point reachable by a straight segment through damaged material touching no crack. False,
  // and nothing laid, where a straight piece would have to cut a crack.
  bool lay(int tip, const Point& p, int reached, const Target& target) {
    std::vector<Point> path{target.q};
    for (int s = reached; previous_[s] >= 0; s = previous_[s]) path.push_back(0.5 * (pts_[s] + pts_[previous_[s]]));
    path.push_back(p);
    std::reverse(path.begin(), path.end());
    const size_t last = path.size() - 1;
    auto passable = [&](size_t i, size_t j) {
      return field_.damaged_along(path[i], path[j]) &&
             closer_.clear(path[i], path[j], i == 0 ? tip : -1, j == last ? &target : nullptr);
    };
    std::vector<size_t> kept{0};
    while (kept.back() < last) {
      const size_t at = kept.back();
      size_t next = at + 1;
      for (size_t j = last; j > at + 1; --j)
        if (passable(at, j)) {
          next = j;
          break;
        }
      if (next == at + 1 && !passable(at, next)) return false;  // rather than a segment that cuts a crack
      kept.push_back(next);
    }
    int from = tip;
    for (size_t k = 1; k < kept.size(); ++k) {
      if (kept[k] == last) {
        closer_.land(from, target);
        break;
      }
      Point q = path[kept[k]];
      const Point d = (q - path[kept[k - 1]]).normalized();
      if (segment_hits_sample(path[kept[k - 1]], q, pts_, field_.grid())) q += settings_.sample_clearance * Point(-d.y(), d.x());
      const int v = closer_.add_vertex(q);
      closer_.add_edge(from, v);
      from = v;
    }
    return true;
  }

  TipCloser& closer_;
  CrackIndex& index_;
  const DamageField& field_;
  const ClosureSettings& settings_;
  const std::vector<Point>& pts_;
  std::vector<double> dist_;
  std::vector<int> previous_, touched_;
};

}  // namespace

void join_tips(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
               const ClosureSettings& settings, ClosureStats& stats) {
  using Target = TipCloser::Target;
  const double reach = settings.cell;
  TipCloser closer(graph, index, field, domain, settings);
  std::vector<std::pair<double, Target>> candidates;
  for (const int tip : closer.tips()) {
    if (!closer.still_free(tip)) continue;
    const Point p = graph.vertices()[tip];
    candidates.clear();
    for (const uint32_t id : index.segments_near({p - Point(reach, reach), p + Point(reach, reach)})) {
      if (closer.incident(id, tip)) continue;
      const Target t = closer.on_segment(id, p);
      const double dist = (t.q - p).norm();
      if (dist <= reach) candidates.push_back({dist, t});
    }
    for (const Target& t : closer.border_targets(p)) {
      const double dist = (t.q - p).norm();
      if (dist <= reach) candidates.push_back({dist, t});
    }
    std::sort(candidates.begin(), candidates.end(), [](const auto& x, const auto& y) {
      if (x.first != y.first) return x.first < y.first;
      if (x.second.kind != y.second.kind) return x.second.kind < y.second.kind;
      return x.second.id < y.second.id;
    });
    for (const auto& [dist, c] : candidates) {
      if (!field.damaged_along(p, c.q)) continue;
      if (closer.enclosed_intact(tip, c) < settings.min_piece) continue;
      if (!closer.clear(p, c.q, tip, &c)) continue;
      closer.land(tip, c);
      ++(c.kind == 0 ? stats.crack_joins : stats.border_joins);
      break;
    }
  }
}

void continue_tips(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
                   const ClosureSettings& settings, ClosureStats& stats) {
  TipCloser closer(graph, index, field, domain, settings);
  TipContinuation continuation(closer, index, field, settings);
  for (const int tip : closer.tips()) {
    if (!closer.still_free(tip)) continue;
    const Point p = graph.vertices()[tip];
    if (!field.damaged_at(p)) continue;
    if (continuation.run(tip, p)) ++stats.continuations;
  }
}

}  // namespace shellfrac::crack2d
