#include "crack2d/tip_extension.hpp"

#include "crack2d/sample_clearance.hpp"

#include <algorithm>
#include <cmath>

namespace shellfrac::crack2d {

namespace {

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

// The end of an earlier join that landed inside a segment is no tip (crack2d/crack_closure.hpp).
bool landed_on_segment(const CrackGraph& graph, const CrackIndex& index, int tip, double weld) {
  const Point p = graph.vertices()[tip];
  bool landed = false;
  for (const uint32_t id : index.segments_near({p - Point::Constant(weld), p + Point::Constant(weld)}))
    landed = landed || (graph.edges()[id][0] != tip && graph.edges()[id][1] != tip &&
                        point_segment_distance(p, index.segment(id)) <= weld);
  return landed;
}

// Marches from p along d while the material ahead is damaged and no crack is crossed; stops on the patch
// edge. Returns the length reached; hit tells whether the edge was reached.
double march(const Point& p, const Point& d, double length, const CrackIndex& index, const DamageField& field,
             const Box& domain, const TipExtensionSettings& settings, bool& hit) {
  const double h = settings.spacing;
  double reached = 0.0;
  hit = false;
  for (double t = settings.step; t <= length + 1e-12; t += settings.step) {
    Segment step{p + d * reached, p + d * t};
    const bool inside = box_contains(domain, step.b);
    if (!inside) {
      if (!clip_segment_to_box(step, domain)) break;
    }
    if (!field.damaged_at(step.b)) break;
    if (index.crosses(step.a + d * (1e-6 * h), step.b)) break;
    reached = (step.b - p).norm();
    if (!inside) {
      hit = true;
      break;
    }
  }
  return reached;
}

// A damaged ligament between the tip and a near patch edge breaks across its narrowest section: when the
// straight way out to an edge ahead of the tip is fully damaged and shorter than the march along the
// crack, the tip goes there instead. Along the crack direction alone, a tip beside a corner ran
// diagonally through the ligament and landed past a control point, which was left tied to the wrong
// side (a pinned corner of cloth-two-balls then stretched 10x). Updates dir, reached and hit_edge.
void prefer_short_ligament(const Point& p, const Point& along, const CrackIndex& index, const DamageField& field,
                           const Box& domain, const TipExtensionSettings& settings, Point& dir, double& reached,
                           bool& hit_edge) {
  const Point outward[4] = {{-1, 0}, {1, 0}, {0, -1}, {0, 1}};
  const double gap[4] = {p.x() - domain.lo.x(), domain.hi.x() - p.x(), p.y() - domain.lo.y(), domain.hi.y() - p.y()};
  for (int side = 0; side < 4; ++side) {
    // Only edges ahead of the tip: turning back or square to the crack would cut along it.
    if (gap[side] > settings.edge_ligament || outward[side].dot(along) <= 0.0) continue;
    bool hit = false;
    const double r = march(p, outward[side], settings.edge_ligament, index, field, domain, settings, hit);
    if (hit && (!hit_edge || r < reached)) {
      dir = outward[side];
      reached = r;
      hit_edge = true;
    }
  }
}

// Adds the march from the tip as pieces of at most settings.piece, off the sample points; the last one
// lands exactly on the patch edge when the march reached it.
void add_extension(CrackGraph& graph, int tip, const Point& dir, double reached, bool hit_edge,
                   const DamageField& field, const Box& domain, const TipExtensionSettings& settings) {
  const Point p = graph.vertices()[tip];
  const int pieces = std::max(1, static_cast<int>(std::ceil(reached / settings.piece)));
  int last = tip;
  for (int k = 1; k <= pieces; ++k) {
    Point q = p + dir * (reached * k / pieces);
    if (hit_edge && k == pieces) {
      Segment s{p, q + dir * (1e-9 * settings.spacing)};
      clip_segment_to_box(s, domain);
      q = s.b;
    } else if (segment_hits_sample(graph.vertices()[last], q, field.points(), field.grid())) {
      q += settings.sample_clearance * Point(-dir.y(), dir.x());
    }
    const int next = graph.add_vertex(q);
    graph.add_edge(last, next);
    last = next;
  }
}

}  // namespace

size_t extend_tips(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
                   size_t old_vertices, const std::vector<Point>& band_edge, const SampleGrid& band_edge_grid,
                   const TipExtensionSettings& settings) {
  const double h = settings.spacing;
  size_t extended = 0;
  const size_t vertices_before_extension = graph.num_vertices();
  for (size_t v = 0; v < vertices_before_extension; ++v) {
    const int tip = static_cast<int>(v);
    const bool old_tip = v < old_vertices;
    if (graph.degree(tip) != 1) continue;
    const Point p = graph.vertices()[tip];
    if (on_box_boundary(p, domain, settings.weld)) continue;
    if (landed_on_segment(graph, index, tip, settings.weld)) continue;
    const Point from = graph.vertices()[trace_back(graph, tip, settings.direction_length)];
    // Only a crack with an established direction is extended; a short stub would point anywhere.
    if ((p - from).norm() < settings.min_direction) continue;
    const Point along = (p - from).normalized();
    const int nearest_seed = band_edge_grid.nearest(p, 10.0 * h);
    const double radius = nearest_seed >= 0 ? (band_edge[nearest_seed] - p).norm() : 0.0;
    const double max_length = old_tip ? settings.edge_ligament : 1.5 * radius + h;
    Point dir = along;
    bool hit_edge = false;
    double reached = march(p, dir, max_length, index, field, domain, settings, hit_edge);
    prefer_short_ligament(p, along, index, field, domain, settings, dir, reached, hit_edge);
    if (reached <= 0.0 || (old_tip && !hit_edge)) continue;
    add_extension(graph, tip, dir, reached, hit_edge, field, domain, settings);
    ++extended;
    index.add_edges(graph, index.num_segments());
  }
  return extended;
}

}  // namespace shellfrac::crack2d
