#pragma once
#include <vector>

#include "brittle/crack_smoothing.hpp"
#include "brittle/crack_surface.hpp"
#include "brittle/damage.hpp"
#include "brittle/regions.hpp"

namespace shellfrac::brittle {

// Breakage ordered by the damage time tau_p (an extension: the thesis records tau_p, sec. 3.7, but
// extracts the crack from c_his alone). When a dropped object is overloaded several times over, the
// damage fills whole volumes instead of thin bands: the medial surface of a fully damaged blob
// (Algorithm 1) is no sheet between intact parts and the object stays whole. The order of breakage
// still holds the fracture pattern: cracks run where the material failed first, the material inside a
// fragment fails later (or never), shielded by the cracks around it. So the damage time is rasterised
// (Eq. 3.13, intact particles counting as breaking last) and the object is split along its valleys:
// a watershed of tau_i on the crack grid, flooded from the latest-breaking nodes down. A basin is a
// fragment core; two basins stay apart only if both rise at least `dynamics` x (time span) above the
// node where they meet (shallow basins are noise of the Weibull strengths and merge). Each grid node's
// Voronoi cell carries its basin, and the faces between different basins are the crack.
struct BreakageOrderOptions {
  bool enabled = false;
  double dynamics = 0.1;   // a basin's depth, as a fraction of the span of damage times, to stand alone
  double min_share = 0.01; // regions holding fewer particles than this share join a neighbour
  // The crack faces come out as staircases of the lattice's cube-like cells; their vertices are smoothed
  // (brittle/crack_smoothing.hpp) so that fragments get smooth crack faces. passes = 0: the staircases.
  CrackSmoothingOptions smoothing;
};

// The crack as faces between watershed basins of the rasterised damage time; the diagram's sites are
// the active nodes of a grid of spacing options.grid.spacing (jittered like extract_crack's), its box
// covers options.cover_lo/hi. With `sheets` (the medial-surface extraction and its regions), a node also
// keeps the sheets' region it lies in, so the cracks between intact parts stay (to within h_v/2) and the
// basins split what they could not. No broken particle: an empty crack (one region).
struct SheetRegions {
  const CrackExtraction* crack = nullptr;
  const Regions* regions = nullptr;
};
CrackExtraction damage_time_crack(const std::vector<Vec3>& rest, const std::vector<ParticleDamage>& damage,
                                  const CrackExtractionOptions& options, double dynamics, SheetRegions sheets = {});

// A region of the damage-time diagram is connected through its cells, but the cells of the sites
// outside the object (the kernel's rim around it, the container) can join parts that are apart inside
// the object: a basin reaching round another's crack sheet through the rim nodes. Its cut (region n
// object, thesis sec. 3.5) then falls apart, and a small part escapes the min_share merge, which sees
// only the whole region. So each region is split into the sets of its cells that hold points (particles,
// nearest site) and are connected through non-crack faces among themselves; a cell without points joins
// the set that reaches it first in a breadth-first search inside the region (cells in index order), and
// a region without points stays as it is. Regions are renumbered by lowest cell. Returns the number of
// regions added.
int split_regions_at_empty_cells(const VoronoiDiagram& diagram, const std::vector<char>& crack_face, Regions& regions,
                                 const std::vector<Vec3>& points);

// Regions holding fewer than min_share of the points are merged, smallest first, into the neighbouring
// region they share the largest face area with (a piece under the resolvable size stays with its
// neighbour instead of being counted as a sliver). Regions are renumbered 0..count-1 by lowest cell.
void merge_small_regions(const VoronoiDiagram& diagram, Regions& regions, const std::vector<size_t>& points_in_region,
                         double min_share);

// Number of regions holding at least one point and at least min_share of the points.
int count_pieces(const std::vector<size_t>& points_in_region, double min_share);

}  // namespace shellfrac::brittle
