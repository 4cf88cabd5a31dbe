#pragma once
// Straight continuation of crack tips through the damaged region (step 5 of the consistent extraction,
// crack2d/consistent_extraction.hpp; docs/crack-extraction.md). A medial line needs seeds on both flanks
// of its band, so it stops short of the band's end: without this step a band that reaches the patch
// edge would leave an uncut ligament there.
//  - a tip of this extraction's lines marches along its crack direction while the material ahead is
//    fully damaged and the march crosses no crack, at most 1.5 local band half-widths plus a spacing;
//  - an older tip marches only when a short, fully damaged ligament joins it to the patch edge (the
//    band often reaches the edge after the tip was extracted), and then lands exactly on that edge;
//  - either kind near a patch edge ahead of it takes the straight way out, square to that edge, when
//    that way is fully damaged and shorter than the march along the crack.
#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/damage_field.hpp"
#include "crack2d/sample_grid.hpp"

#include <vector>

namespace shellfrac::crack2d {

struct TipExtensionSettings {
  double spacing = 0.0;           // sample spacing h
  double direction_length = 0.0;  // crack length behind a tip that sets the extension direction
  double min_direction = 0.0;     // a tip whose direction chord is shorter is a stub and is not extended
  double step = 0.0;              // march step
  double piece = 0.0;             // longest segment of an extension
  double edge_ligament = 0.0;     // longest damaged ligament from an older tip to the patch edge
  double sample_clearance = 0.0;  // shift that moves a new segment off a sample lying on it
  double weld = 0.0;              // coincidence tolerance of the parameter plane
};

// Extends the tips of graph; vertices [0, old_vertices) are older, the rest are this extraction's.
// band_edge (with band_edge_grid over it): the boundary samples of the damaged region, whose distance
// from a new tip is the band's half-width there. New segments are kept off field.points(). Keeps index
// current; returns the number of tips extended.
size_t extend_tips(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
                   size_t old_vertices, const std::vector<Point>& band_edge, const SampleGrid& band_edge_grid,
                   const TipExtensionSettings& settings);

}  // namespace shellfrac::crack2d
