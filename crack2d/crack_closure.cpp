#include "crack2d/crack_closure.hpp"

#include "crack2d/union_find.hpp"
#include "crack2d/voronoi_medial_axis.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <queue>

namespace shellfrac::crack2d {

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

}  // namespace

void separate_intact_pieces(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
                            const ClosureSettings& settings, ClosureStats& stats) {
  const std::vector<Point>& pts = field.points();
  const std::vector<unsigned char>& damaged = field.flags();
  const size_t n = pts.size();
  const double r = settings.neighbour_radius;

  const SampleNeighbours& adjacency = field.neighbours();
  // Boundary of the intact material: intact samples with a damaged neighbour.
  std::vector<char> is_site(n, 0);
  for (size_t j = 0; j < n; ++j)
    if (damaged[j]) adjacency.for_each(j, [&](int i) { is_site[i] = !damaged[i]; });
  std::vector<int> sites;
  for (size_t i = 0; i < n; ++i)
    if (is_site[i]) sites.push_back(static_cast<int>(i));
  if (sites.size() < 2) return;

  // Intact pieces: intact samples joined to their intact neighbours unless the crack lies between them.
  const std::vector<char> near = near_crack(field, index, r, settings.spacing);
  UnionFind pieces(n);
  for (size_t i = 0; i < n; ++i) {
    if (damaged[i]) continue;
    adjacency.for_each(i, [&](int j) {
      if (j <= static_cast<int>(i) || damaged[j]) return;
      if (near[i] && near[j] && index.crosses(pts[i], pts[j])) return;
      pieces.unite(static_cast<int>(i), j);
    });
  }
  std::vector<size_t> piece_size(n, 0);
  for (size_t i = 0; i < n; ++i)
    if (!damaged[i]) ++piece_size[pieces.find(static_cast<int>(i))];
  // Sites of pieces too small to stand alone get no label: no crack is drawn around a sliver.
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
  if (!several) return;  // damaged material borders one intact piece only: nothing to separate

  std::vector<Point> site_points(sites.size());
  for (size_t k = 0; k < sites.size(); ++k) site_points[k] = pts[sites[k]];
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
  std::vector<int> vertex_of(voronoi.nodes.size(), -1);
  auto vertex_for = [&](int node) {
    if (vertex_of[node] < 0) vertex_of[node] = graph.add_vertex(voronoi.nodes[node]);
    return vertex_of[node];
  };
  for (int e : chosen) graph.add_edge(vertex_for(voronoi.edges[e].node_a), vertex_for(voronoi.edges[e].node_b));
  stats.separating_edges += graph.num_edges() - first_edge;
  index.add_edges(graph, first_edge);
}

namespace {

struct JoinCandidate {
  double distance;
  int kind;        // 0: crack segment, 1: patch border
  uint32_t id;     // segment index, or border side
  Point q;         // end of the join on the target
  int vertex;      // existing crack vertex at q, or -1
};

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

double polygon_area(const std::vector<Point>& poly) {
  double twice = 0.0;
  for (size_t i = 0, j = poly.size() - 1; i < poly.size(); j = i++) twice += poly[j].x() * poly[i].y() - poly[i].x() * poly[j].y();
  return 0.5 * std::abs(twice);
}

}  // namespace

void join_tips(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
               const ClosureSettings& settings, ClosureStats& stats) {
  const double reach = settings.cell;
  std::vector<int> tips;
  std::vector<Attachment> attachments;
  std::vector<std::vector<int>> attached_to(graph.num_vertices());
  auto attach = [&](int vertex, int edge) {
    attached_to.resize(graph.num_vertices());
    const int k = static_cast<int>(attachments.size());
    attachments.push_back({vertex, edge});
    attached_to[vertex].push_back(k);
    attached_to[graph.edges()[edge][0]].push_back(k);
    attached_to[graph.edges()[edge][1]].push_back(k);
  };
  for (size_t v = 0; v < graph.num_vertices(); ++v) {
    const int vi = static_cast<int>(v);
    if (graph.degree(vi) != 1 || on_box_boundary(graph.vertices()[v], domain, settings.weld)) continue;
    const Point& p = graph.vertices()[v];
    bool on_segment = false;
    for (const uint32_t id : index.segments_near({p - Point::Constant(settings.weld), p + Point::Constant(settings.weld)})) {
      const auto& ed = graph.edges()[id];
      if (ed[0] == vi || ed[1] == vi || point_segment_distance(p, index.segment(id)) > settings.weld) continue;
      attach(vi, static_cast<int>(id));
      on_segment = true;
    }
    if (!on_segment) tips.push_back(vi);
  }

  std::vector<JoinCandidate> candidates;
  for (const int tip : tips) {
    if (graph.degree(tip) != 1) continue;
    const Point p = graph.vertices()[tip];
    candidates.clear();
    const Box around{p - Point(reach, reach), p + Point(reach, reach)};
    for (const uint32_t id : index.segments_near(around)) {
      const auto& ed = graph.edges()[id];
      if (ed[0] == tip || ed[1] == tip) continue;
      const Point a = graph.vertices()[ed[0]], b = graph.vertices()[ed[1]];
      const Point d = b - a;
      const double len2 = d.squaredNorm();
      const double s = len2 > 0.0 ? std::clamp((p - a).dot(d) / len2, 0.0, 1.0) : 0.0;
      Point q = a + s * d;
      int vertex = -1;
      if ((q - a).norm() <= settings.weld) vertex = ed[0], q = a;
      else if ((q - b).norm() <= settings.weld) vertex = ed[1], q = b;
      const double dist = (q - p).norm();
      if (dist <= reach) candidates.push_back({dist, 0, id, q, vertex});
    }
    const Point border[4] = {{domain.lo.x(), p.y()}, {domain.hi.x(), p.y()}, {p.x(), domain.lo.y()}, {p.x(), domain.hi.y()}};
    for (uint32_t side = 0; side < 4; ++side) {
      const double dist = (border[side] - p).norm();
      if (dist <= reach) candidates.push_back({dist, 1, side, border[side], -1});
    }
    if (candidates.empty()) continue;
    std::sort(candidates.begin(), candidates.end(), [](const JoinCandidate& x, const JoinCandidate& y) {
      if (x.distance != y.distance) return x.distance < y.distance;
      if (x.kind != y.kind) return x.kind < y.kind;
      return x.id < y.id;
    });

    PathTree tree;  // crack-graph paths from the tip, computed when a candidate needs them
    // Area enclosed by the join together with the shortest way back to the tip through the crack (and
    // along the border), or infinity when there is no such way within the search bound.
    auto loop_area = [&](const JoinCandidate& c) {
      if (tree.dist.empty()) tree = graph_distances(graph, attached_to, attachments, tip, settings.loop_search);
      double best = std::numeric_limits<double>::infinity();
      int via = -1;
      Point corner = Point::Zero();
      bool use_corner = false;
      if (c.kind == 0) {
        const auto& ed = graph.edges()[c.id];
        for (int k = 0; k < 2; ++k) {
          const double len = tree.dist[ed[k]] + (graph.vertices()[ed[k]] - c.q).norm();
          if (len < best) best = len, via = ed[k];
        }
      } else {
        const int side_q = static_cast<int>(c.id);
        for (size_t w = 0; w < tree.dist.size(); ++w) {
          if (!std::isfinite(tree.dist[w])) continue;
          const Point& pw = graph.vertices()[w];
          const int side_w = border_side(pw, domain, settings.weld);
          if (side_w < 0 || (side_w / 2 == side_q / 2 && side_w != side_q)) continue;  // opposite sides: a wide loop
          const double len = tree.dist[w] + (pw - c.q).lpNorm<1>();
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
      if (via < 0 || !std::isfinite(best)) return std::numeric_limits<double>::infinity();
      std::vector<Point> loop{graph.vertices()[tip], c.q};
      if (use_corner) loop.push_back(corner);
      for (int v = via; v >= 0 && v != tip; v = tree.previous[v]) loop.push_back(graph.vertices()[v]);
      return polygon_area(loop);
    };
    for (const JoinCandidate& c : candidates) {
      if (!field.damaged_along(p, c.q)) continue;
      if (loop_area(c) < settings.min_loop_area) continue;
      // The join may touch only the tip's own edge (at p) and the target (at q).
      bool blocked = false;
      const Box span{p.cwiseMin(c.q), p.cwiseMax(c.q)};
      for (const uint32_t id : index.segments_near(span)) {
        const auto& ed = graph.edges()[id];
        if (ed[0] == tip || ed[1] == tip) continue;
        if (c.kind == 0 && id == c.id) continue;
        if (c.vertex >= 0 && (ed[0] == c.vertex || ed[1] == c.vertex)) continue;
        const Segment s = index.segment(id);
        if (segments_intersect(p, c.q, s.a, s.b)) {
          blocked = true;
          break;
        }
      }
      if (blocked) continue;
      int target = c.vertex;
      if (target < 0) {
        Point q = c.q;
        if (c.kind == 0) {
          // The rounded projection may stop a hair short of the target segment; move it over so the
          // join and the target share a point exactly (the overshoot is a few ulps).
          const Segment s = index.segment(c.id);
          const Point dir = (q - p).normalized();
          double eps = 1e-15 * std::max(1.0, q.cwiseAbs().maxCoeff());
          for (int k = 0; k < 60 && !segments_intersect(p, q, s.a, s.b); ++k, eps *= 2.0) q = c.q + dir * eps;
        }
        target = graph.add_vertex(q);
        if (c.kind == 0) attach(target, static_cast<int>(c.id));
      }
      const size_t first_edge = graph.num_edges();
      graph.add_edge(tip, target);
      index.add_edges(graph, first_edge);
      ++(c.kind == 0 ? stats.crack_joins : stats.border_joins);
      break;
    }
  }
}

}  // namespace shellfrac::crack2d
