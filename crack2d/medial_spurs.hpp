#pragma once
// Pruning of spurs of the medial axis (thesis sec. 4.4.2 extracts the medial axis of the damaged region;
// a bump on the flank of a damaged band has a medial branch of its own that is no crack). A terminal
// branch from a free tip to a junction is a spur when the region it describes sticks out of the band
// by less than `min_protrusion`: with L the branch length and r the distance to the nearest boundary
// seed, the protrusion is L + r(tip) - r(junction) (how far the disc at the tip reaches beyond the disc
// at the junction). A real branch of the damage (a Y-shaped band) sticks out by its whole length.
#include <array>
#include <vector>

namespace shellfrac::crack2d {

// edge_nodes/edge_length: all candidate edges (working-graph node ids and lengths); keep: the edges
// chosen as new lines, cleared for the edges of pruned spurs; anchored: nodes that lie on the earlier
// crack (a branch ending there continues the crack and is never a spur); node_radius: r per node.
// Returns the number of pruned branches. Deterministic (tips in node order).
int prune_spurs(const std::vector<std::array<int, 2>>& edge_nodes, const std::vector<double>& edge_length,
                std::vector<char>& keep, const std::vector<char>& anchored, const std::vector<double>& node_radius,
                double min_protrusion);

}  // namespace shellfrac::crack2d
