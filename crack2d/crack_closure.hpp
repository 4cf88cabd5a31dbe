#pragma once
// Closure of the crack graph after the medial-axis extraction (thesis sec. 4.4.2, Fig. 4.8
// extended to prescribed cuts and the patch border). See docs/crack-extraction.md.
//
//  - separate_intact_pieces: where fully damaged material links two intact pieces of the patch that
//    the crack does not already separate, the Voronoi edges between the two pieces' boundary samples
//    (the medial axis of the damaged material between them) become crack segments;
//  - continue_tips: a crack tip inside fully damaged material is continued along the shortest way
//    through that material (straightened) to another crack, a cut or the border, when one lies within
//    `continuation_reach` and the link closes no loop with the tip's own crack: the two flanks of the
//    crack are otherwise still linked around the tip;
//  - join_tips: a crack tip within one simulation cell of another crack, a prescribed cut or the patch
//    border is joined to it by the shortest straight segment, when that segment runs through fully
//    damaged material and does not close a loop around less than one cell of intact material.
// Both only append to the graph (the previous graph stays an exact subset) and keep the index current.
#include "crack2d/crack_graph.hpp"
#include "crack2d/crack_index.hpp"
#include "crack2d/damage_field.hpp"

namespace shellfrac::crack2d {

struct ClosureSettings {
  double spacing = 0.0;           // sample spacing h
  double cell = 0.0;              // simulation cell size (parameter units): the join reach
  double neighbour_radius = 0.0;  // samples closer than this are neighbours (adjacency of intact material)
  double covered = 0.0;           // a separating edge whose midpoint is this close to the crack duplicates it
  double loop_search = 0.0;       // longest way back through the crack searched for such a loop
  size_t min_piece = 0;           // fewest intact samples of a piece worth separating, or of a loop worth closing
  double continuation_reach = 0.0;  // longest way through damaged material a tip is continued
  double sample_clearance = 0.0;  // shift that moves a new segment off a sample lying on it
  double weld = 0.0;              // coincidence tolerance of the parameter plane
};

struct ClosureStats {
  size_t separating_edges = 0;  // crack segments added between intact pieces
  size_t crack_joins = 0;       // tips joined to another crack or a prescribed cut
  size_t border_joins = 0;      // tips joined to the patch border
  size_t continuations = 0;     // tips continued through damaged material to a crack, cut or border
};

void separate_intact_pieces(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
                            const ClosureSettings& settings, ClosureStats& stats);

void continue_tips(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
                   const ClosureSettings& settings, ClosureStats& stats);

void join_tips(CrackGraph& graph, CrackIndex& index, const DamageField& field, const Box& domain,
               const ClosureSettings& settings, ClosureStats& stats);

}  // namespace shellfrac::crack2d
