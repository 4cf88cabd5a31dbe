#pragma once
// The one visibility query shared by MLS supports, phantom-node grouping and the render mesh: a
// uniform-grid bucket index over the crack segments of one patch.
//
// Cells are sized from the mean segment length (about two segments per cell side) and the grid is
// re-sized on rebuild or when incremental additions have more than doubled the segment count. A segment
// is registered in every cell its closed point set meets (conservative row-by-row rasterisation with a
// small pad), and a query rasterises the same way, so bucket lookup never misses a hit. Segments
// outside the domain are clamped into the border cells, so they are still found.
//
// All const queries are thread-safe (no scratch state): a segment seen twice is simply tested twice.
// Predicates are exact (see geometry.hpp).
#include "crack2d/crack_graph.hpp"
#include "crack2d/geometry.hpp"

#include <cstdint>
#include <vector>

namespace shellfrac::crack2d {

class CrackIndex {
 public:
  explicit CrackIndex(const Box& domain = Box{Point(0, 0), Point(1, 1)});

  void rebuild(const CrackGraph& g);                       // full rebuild
  void add_edges(const CrackGraph& g, size_t first_edge);  // incremental, for edges [first_edge, end)

  // True when the closed segment ab intersects any crack segment (touching and collinear overlap count).
  bool crosses(const Point& a, const Point& b) const;
  // True when any crack segment with index >= first_edge intersects the closed box.
  bool touches(const Box& box, size_t first_edge = 0) const;
  // Distance from p to the nearest crack segment, or max_distance if none is closer.
  double distance(const Point& p, double max_distance) const;
  // The crack point nearest to p within max_distance: distance, segment index (lowest on ties) and the
  // point; segment -1 (and distance max_distance) when there is none.
  struct Nearest {
    double distance;
    int segment;
    Point point;
  };
  Nearest nearest(const Point& p, double max_distance) const;
  // Indices of the segments that may meet the closed box (a superset: bucket contents), sorted, unique.
  std::vector<uint32_t> segments_near(const Box& box) const;

  size_t num_segments() const { return segments_.size(); }
  const Segment& segment(size_t i) const { return segments_[i]; }
  const Box& domain() const { return domain_; }
  int cells_x() const { return nx_; }
  int cells_y() const { return ny_; }

 private:
  void resize_grid();  // choose the cell size from the current segments and re-bucket them all
  void insert(uint32_t id);
  int column(double x) const;
  int row(double y) const;
  // Calls visit(cell index) for every cell the closed segment ab may meet; stops when visit returns true.
  template <class Visit>
  bool for_each_cell_on_segment(const Point& a, const Point& b, Visit&& visit) const;

  Box domain_;
  int nx_ = 1, ny_ = 1;
  double cell_w_ = 1, cell_h_ = 1;
  double inv_cell_w_ = 1, inv_cell_h_ = 1;
  std::vector<Segment> segments_;
  std::vector<std::vector<uint32_t>> cells_;
  size_t grid_sized_for_ = 0;  // segment count the current cell size was chosen for
};

}  // namespace shellfrac::crack2d
