#pragma once
// Consistent crack extraction from fully damaged sample points (thesis sec. 4.4.2, Fig. 4.7, Fig. 4.8;
// improves the per-frame medial-surface extraction of sec. 3.3). See docs/crack-extraction.md.
//
// Each extract() call:
//  0. the damaged set is regularised at the cell scale: closing with a disc of half a cell, and intact
//     pockets of less than a cell filled (crack2d/damage_closing.hpp);
//  1. boundary seeds D^c: damaged samples with an undamaged sample within 1.5 spacing, each with an
//     outward normal (mean direction to those undamaged neighbours);
//  2. Voronoi diagram of D' = D^c plus the historical seeds LS (Boost.Polygon, clipped to the domain);
//  3. new lines: Voronoi edges inside the damaged region whose two seeds are both in D^c, lie on opposite
//     sides of the band (normals and the 90-degree disc test), are not a historical pair, and do not
//     duplicate the crack already lying in the same damaged band;
//  4. bridges (crack2d/group_bridges.hpp): every group of new lines not yet attached is joined along
//     Voronoi cell boundaries (shortest path over damaged Voronoi edges) to the previous crack, preferring
//     an old tip (tip bridge, Fig. 4.8b), or to another group (branch link, Fig. 4.8c); spurs are pruned
//     (crack2d/medial_spurs.hpp); the seeds of every added Voronoi edge join LS;
//  5. tips of the new lines are extended straight through the rest of the damaged region (and clipped to
//     the domain), so a band that reaches the patch edge gives a crack that reaches it too
//     (crack2d/tip_extension.hpp);
//  6. closure (crack2d/crack_closure.hpp): tips within a cell of a crack, cut or the border join it, and
//     damaged material that still links two intact pieces is cut along its medial axis;
//  7. the result is checked to contain the previous graph exactly.
#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/prescribed_cut.hpp"
#include "crack2d/sample_grid.hpp"
#include "crack2d/sample_neighbours.hpp"

#include <memory>
#include <unordered_map>
#include <unordered_set>
#include <vector>

namespace shellfrac::crack2d {

struct ExtractionStats {
  size_t seeds = 0, new_edges = 0, tip_bridges = 0, branch_links = 0, subset_violations = 0;
  size_t tip_extensions = 0;  // straight continuations of new tips through the damaged region
  size_t pruned_spurs = 0;      // medial branches dropped as spurs (crack2d/medial_spurs.hpp)
  size_t separating_edges = 0;  // closure: segments added between intact pieces linked by damage
  size_t crack_joins = 0;       // closure: tips joined to another crack or a prescribed cut
  size_t border_joins = 0;      // closure: tips joined to the patch border
  size_t continuations = 0;     // closure: tips continued through damaged material
};

class DamageField;

class ConsistentCrackExtractor {
 public:
  // domain: the patch's parameter rectangle; spacing: typical distance between neighbouring sample points;
  // cell: the simulation cell size in parameter units (the closure's reach and the scale at which the
  // damaged set is regularised). Without it, a cell of kDefaultSamplesPerCell spacings is assumed.
  ConsistentCrackExtractor(const Box& domain, double spacing, double cell);
  ConsistentCrackExtractor(const Box& domain, double spacing);
  static constexpr double kDefaultSamplesPerCell = 4.0;  // 4 x 4 quadrature points per cell

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
  // Sample points of the last extraction with their bucket grid and neighbour lists (the quadrature
  // points of a patch do not move in the parameter plane, so these are built once).
  struct SampleCache {
    std::vector<Point> points;
    std::unique_ptr<SampleGrid> grid;  // refers to points
    SampleNeighbours adjacency;        // within kBoundaryRadius spacings
    SampleNeighbours disc;             // within the closing radius
    std::vector<char> at_edge;         // closer to the patch edge than the closing radius
  };
  const SampleCache& samples_for(const std::vector<Point>& points);
  size_t samples_per_cell() const;
  // A new medial edge at p duplicates the existing crack (see kParallelCover).
  bool covered_by_crack(const Point& p, const DamageField& field) const;
  void close_graph(const DamageField& field, ExtractionStats& stats);
  // The working state of one extract() call, one member function per step above (consistent_extraction.cpp).
  class Pass;

  Box domain_;
  double spacing_;
  double cell_;
  CrackGraph graph_;
  CrackIndex index_;
  std::vector<HistoricalSeed> line_seeds_;              // LS
  std::unordered_map<uint64_t, int> line_seed_by_key_;   // lattice key -> LS index
  std::unordered_set<uint64_t> line_seed_pairs_;         // LS index pairs that define historical lines
  size_t total_subset_violations_ = 0;
  std::unique_ptr<SampleCache> samples_;
};

}  // namespace shellfrac::crack2d
