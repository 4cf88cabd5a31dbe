#pragma once
#include <vector>

#include "brittle/voronoi.hpp"

namespace shellfrac::brittle {

// Smoothing of crack sheets between Voronoi regions of a jittered lattice (ours, not in the thesis).
// When every node of a grid of spacing h is a site (the damage-time crack), the sheet between two regions
// is a union of the near-cubic cells' faces: a staircase at h. The smoothing works on that staircase:
//  - every vertex of the diagram belongs to a lattice corner (the cube corner (k + 1/2) h nearest to it);
//    a crack face is a staircase square with four corners (faces that shrink to an edge or a point there
//    are the jitter's slivers and carry no shape);
//  - Laplacian steps move the staircase's corners, each kept inside its cube of lattice nodes (as in
//    constrained surface nets): over the sheet towards the mean of their sheet neighbours, along junction
//    curves (corner edges whose squares touch three or more regions) and rims with their two curve
//    neighbours; junction ends and corners whose cube is not all sites (outside the object) stay;
//  - every vertex of the diagram then moves by the trilinear interpolation of its cube's corner
//    displacements (a continuous deformation of space: tiny jitter faces move nearly rigidly, vertices
//    away from the sheet stay), minus the components normal to the container walls it lies on;
//  - the vertices of a sheet face near a corner (the site jitter's cluster there, which kept the plane of
//    its cube face) are finally projected onto the sheet's tangent plane at that corner;
//  - a step (and a projection) is kept only where every tetrahedron (reference point, triangle of a face of its cell) stays
//    positively oriented, the reference point being the cell's site moved by the same deformation; the
//    corners that move a face that would fold are put back (after two halvings). The cells then stay
//    star-shaped around their reference points and the tetrahedra tile the container once (a degree
//    argument), so the regions still partition it exactly and their boundaries never fold or overlap.
// Every vertex is one point of the conforming diagram, so both cells of a face see the same moved face.
// Moved faces are marked bent and triangulated as stars around their centres (VoronoiFace::bent).
struct CrackSmoothingOptions {
  int passes = 10;       // Laplacian steps (Taubin's lambda|mu pairs measured worse: docs/brittle.md)
  double lambda = 0.5;   // Laplacian step
  double reach = 0.45;   // a corner moves at most this fraction of h along each axis
};

struct CrackSmoothingReport {
  size_t sheet_corners = 0;   // staircase corners that move over the sheet
  size_t curve_corners = 0;   // corners that move along a junction curve or a rim
  size_t fixed_corners = 0;   // junction ends, corners outside the object
  size_t rejected_moves = 0;  // corner steps undone because a cell would have folded
  double max_displacement = 0;  // of a diagram vertex [m]
  std::vector<Vec3> reference;  // per cell, its site moved by the deformation: each cell is star-shaped around it
};

// Moves the diagram's vertices so that the faces with smooth[f] != 0 (the sheets between the regions
// they bound) become smooth; the sites must be jittered nodes of the lattice h Z^3. Updates the moved
// faces' areas and centroids and their cells' volumes.
CrackSmoothingReport smooth_crack_faces(VoronoiDiagram& diagram, const std::vector<char>& smooth, double h,
                                        const CrackSmoothingOptions& options = {});

// Number of faces with a tetrahedron (reference point of a cell, triangle of the face) whose signed volume
// is not positive: 0 when every cell is star-shaped around its reference point (empty: the sites).
size_t folded_tetrahedra(const VoronoiDiagram& diagram, const std::vector<Vec3>& reference = {});

}  // namespace shellfrac::brittle
