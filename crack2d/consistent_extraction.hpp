#pragma once
// Consistent crack extraction from fully damaged sample points (thesis sec. 4.4.2, Fig. 4.7, Fig. 4.8;
// improves the per-frame medial-surface extraction of sec. 3.3). See docs/crack-extraction.md.
//
// Each extract() call:
//  1. boundary seeds D^c: damaged samples with an undamaged sample within 1.5 spacing, each with an
//     outward normal (mean direction to those undamaged neighbours);
//  2. Voronoi diagram of D' = D^c plus the historical seeds LS (Boost.Polygon, clipped to the domain);
//  3. new lines: Voronoi edges inside the damaged region whose two seeds are both in D^c, lie on opposite
//     sides of the band, and are not a historical pair (historical lines stay as stored);
//  4. bridges: every group of new lines not yet attached is joined along Voronoi cell boundaries
//     (shortest path over damaged Voronoi edges) to the previous crack (tip bridge, Fig. 4.8b) or to
//     another group (branch link, Fig. 4.8c); the seeds of every added Voronoi edge join LS;
//  5. tips of the new lines are extended straight through the rest of the damaged region (and clipped to
//     the domain), so a band that reaches the patch edge gives a crack that reaches it too;
//  6. the result is checked to contain the previous graph exactly.
#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/prescribed_cut.hpp"

#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace shellfrac::crack2d {

struct ExtractionStats {
  size_t seeds = 0, new_edges = 0, tip_bridges = 0, branch_links = 0, subset_violations = 0;
  size_t tip_extensions = 0;  // straight continuations of new tips through the damaged region
};

class ConsistentCrackExtractor {
 public:
  // domain: the patch's parameter rectangle; spacing: typical distance between neighbouring sample points
  ConsistentCrackExtractor(const Box& domain, double spacing);

  // Prescribed cut (polyline, or closed curve when closed = true) in parameter coordinates; enters the
  // same graph as permanent historical lines. Throws CutError (see prescribed_cut.hpp).
  void add_prescribed_cut(const std::vector<Point>& polyline, bool closed);

  // points: parameter coordinates of all sample points of the patch; damaged[i] != 0 when the point's
  // damage history reached 1. Extends graph() consistently; returns what happened.
  ExtractionStats extract(const std::vector<Point>& points, const std::vector<unsigned char>& damaged);

  const CrackGraph& graph() const { return graph_; }
  // Index over graph(), kept current by extract() and add_prescribed_cut().
  const CrackIndex& index() const { return index_; }
  size_t total_subset_violations() const { return total_subset_violations_; }
  size_t num_historical_seeds() const { return line_seeds_.size(); }

 private:
  struct HistoricalSeed {
    Point position;
    Point normal;
  };
  int historical_seed_id(const Point& p, const Point& normal);  // finds or appends to LS

  Box domain_;
  double spacing_;
  CrackGraph graph_;
  CrackIndex index_;
  std::vector<HistoricalSeed> line_seeds_;              // LS
  std::unordered_map<uint64_t, int> line_seed_by_key_;   // lattice key -> LS index
  std::unordered_set<uint64_t> line_seed_pairs_;         // LS index pairs that define historical lines
  size_t total_subset_violations_ = 0;
};

}  // namespace shellfrac::crack2d
