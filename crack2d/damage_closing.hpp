#pragma once
// Regularisation of the fully damaged sample set before crack extraction (docs/crack-extraction.md).
//
// The damage history c_his reaches 1 at individual quadrature points, and within one simulation cell it
// varies between them (bending stress changes across the cell), so a damaged zone is often a speckle of
// damaged and intact samples rather than a solid region. Its medial axis would be a tangle of short
// pieces that never separate anything. Two monotone set operations turn it into the region the cell
// resolution can actually represent:
//  - morphological closing with a disc of radius r (dilate, then erode): gaps and concave notches
//    narrower than about 2r are filled, convex shapes and isolated damaged samples are left as they are;
//  - pocket filling: a group of intact samples (neighbours within `neighbour_radius`) enclosed by damage
//    and holding at most `max_pocket` samples (less than a cell of material) counts as damaged; a crack
//    around it would only cut off a sliver.
// Neither fills intact material at the patch edge (samples flagged in `at_edge`, those closer to the edge
// than the closing radius): beyond the edge there is no damage, so a gap between a damaged zone and the
// edge is no gap in the damage, and an intact patch at the edge (a pinned corner, say) that damage
// cuts off from the rest stays intact, to be cut off by the crack.
// Both are monotone (a larger input set gives a larger output set), so the regularised set grows with
// c_his exactly like the raw one. Deterministic: samples are visited in input order.
#include "crack2d/sample_neighbours.hpp"

#include <vector>

namespace shellfrac::crack2d {

// disc: neighbours within the closing radius r (null: no closing); adjacency: neighbours that make
// intact samples one group; max_pocket: groups with at most this many samples are filled (0: none);
// at_edge: samples that are never filled; damaged: 1 where c_his reached 1.
std::vector<unsigned char> close_damage(const std::vector<unsigned char>& damaged, const SampleNeighbours* disc,
                                        const SampleNeighbours& adjacency, size_t max_pocket,
                                        const std::vector<char>& at_edge);

}  // namespace shellfrac::crack2d
