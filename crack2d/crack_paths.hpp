#pragma once
// Shortest crack-free paths in a patch's parameter plane. Straight-line visibility (CrackIndex::crosses)
// decides what a point sees; a path may in addition bend around the crack's corners: beyond a free tip,
// or on the open side of a bend or junction. These are the only places where a shortest path among
// segment obstacles bends, so a Dijkstra search over them ("portals") gives exact path lengths.
//
// Used by the shell's last MLS fallback: a point that sees too few control points in straight lines takes
// those of its own fragment, reached along such paths (docs/mls.md). Every hop of a path is checked with
// CrackIndex::crosses, so no path ever crosses or touches a crack.
#include <limits>
#include <vector>

#include "crack2d/crack_index.hpp"
#include "crack2d/geometry.hpp"

namespace shellfrac::crack2d {

// One point per reflex corner of the crack (a free tip, or an angular sector wider than pi between
// consecutive segments at a vertex), placed `offset` from the vertex along the sector's bisector.
// Segments ending at bit-identical points share a vertex. Portals outside the index domain are dropped.
class CrackPortals {
 public:
  void build(const CrackIndex& index, double offset);
  const std::vector<Point>& points() const { return points_; }
  // Unit bisector of each portal's sector, pointing away from the crack (beyond a tip: the crack's
  // direction continued). The half-plane it points into is "ahead" of the corner.
  const std::vector<Point>& ahead() const { return ahead_; }
  size_t size() const { return points_.size(); }
  // Free crack tips (vertices with one segment) whose portal lies in the domain: the tip vertex and the
  // index of its portal in points(). Used by the diffraction weights (docs/mls.md, "Tip weights").
  const std::vector<Point>& tips() const { return tips_; }
  // The crack vertex of each portal (the corner it lies beyond), parallel to points().
  const std::vector<Point>& corners() const { return corners_; }
  const std::vector<size_t>& tip_portals() const { return tip_portals_; }
  size_t built_for_segments() const { return segments_; }  // num_segments() of the index at build time

 private:
  std::vector<Point> points_, ahead_;
  std::vector<Point> tips_, corners_;
  std::vector<size_t> tip_portals_;
  size_t segments_ = 0;
};

struct PathSettings {
  // Lengths and angles are measured in scaled coordinates (du / scale_u, dv / scale_v), e.g. cells.
  double scale_u = 1.0, scale_v = 1.0;
  double limit = std::numeric_limits<double>::infinity();     // longest admissible path (scaled units)
  double max_turn = std::numeric_limits<double>::infinity();  // total turning along a path (radians)
  // A path bending at a corner must go on into the closed half-plane ahead of it: past a tip it may
  // fan out sideways but never wrap back behind the crack to its far side.
  bool ahead_only = false;
};

// Shortest admissible paths from one source: Dijkstra over the portals, each hop a crack-free straight
// segment. A path is admissible when its length is <= limit and the sum of its turning angles is
// <= max_turn (the turning is that of the shortest path; a longer, straighter one is not looked for),
// and, with ahead_only, every bend leaves into the half-plane ahead of its corner.
// Reuse one object per thread; not thread-safe itself.
class CrackPaths {
 public:
  // Starts a search from `source`. The search itself runs lazily: call settle_all() or settle_next().
  void start(const CrackIndex& index, const CrackPortals& portals, const Point& source, const PathSettings& s);
  // Settles the next nearest portal; false when none is left within the limits (search exhausted).
  bool settle_next();
  void settle_all() {
    while (settle_next()) {
    }
  }
  // True when no reachable portal is left unsettled (after settle_all always).
  bool exhausted() const { return exhausted_; }

  // Shortest admissible path to `target` through the settled portals: its length and the first point
  // after the source on it (the target itself when the source sees it). False when there is none.
  bool path_to(const Point& target, double& length, Point& first_hop) const;
  // Number of hops of the last path_to result minus one (0: straight line). For diagnostics and tests.
  int last_bends() const { return last_bends_; }

  // Settled nodes (the source first): position, path length from the source and its number of bends.
  size_t num_settled() const { return settled_.size(); }
  const Point& settled_point(size_t i) const { return nodes_[settled_[i]].p; }
  double settled_length(size_t i) const { return nodes_[settled_[i]].length; }

  double scaled_length(const Point& a, const Point& b) const;

 private:
  struct Node {
    Point p;
    double length = std::numeric_limits<double>::infinity();
    double turn = 0.0;        // total turning of the path up to this node
    Point in_dir{0.0, 0.0};   // scaled unit direction of the last hop into this node (0 for the source)
    Point ahead{0.0, 0.0};    // the portal's ahead direction (0 for the source)
    Point first_hop{0.0, 0.0};
    int bends = 0;
    bool settled = false;
  };
  double turn_at(const Node& n, const Point& next) const;
  // False when ahead_only forbids the hop n -> next (it would bend back behind n's corner).
  bool goes_ahead(const Node& n, const Point& next) const {
    return !s_.ahead_only || (next - n.p).dot(n.ahead) >= 0.0;
  }

  const CrackIndex* index_ = nullptr;
  PathSettings s_;
  std::vector<Node> nodes_;      // [0] is the source, then the portals within the limit
  std::vector<size_t> settled_;  // node ids in the order they were settled
  bool exhausted_ = false;
  mutable int last_bends_ = 0;
};

}  // namespace shellfrac::crack2d
