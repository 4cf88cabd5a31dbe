#pragma once
#include <vector>

#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// A face shared by two Voronoi cells (or a cell and a wall of the container box). Its polygon is ordered
// so that the right-hand normal points from cell_a into cell_b.
struct VoronoiFace {
  int cell_a = -1;
  int cell_b = -1;            // < 0: container wall -1 .. -6 (x-, x+, y-, y+, z-, z+)
  std::vector<int> vertices;  // welded vertex ids
  double area = 0;
  Vec3 centroid = Vec3::Zero();
  // Vertices moved off the face's plane (brittle/crack_smoothing.hpp): the face is then triangulated as a
  // star around the mean of its vertices, since a fan of a bent polygon whose vertices lie nearly on a
  // line folds over itself.
  bool bent = false;
  bool wall() const { return cell_b < 0; }
};

// The 3D Voronoi diagram of a set of sites clipped to a box, computed cell by cell with voro++ and made
// conforming: vertices that neighbouring cells computed separately are welded, and each shared face is
// stored once. Faces of zero area after welding are dropped.
struct VoronoiDiagram {
  std::vector<Vec3> sites;
  Vec3 box_lo = Vec3::Zero(), box_hi = Vec3::Zero();
  std::vector<Vec3> vertices;
  std::vector<VoronoiFace> faces;
  std::vector<std::vector<int>> cell_faces;  // face ids of each cell
  std::vector<double> cell_volume;           // as voro++ reports it

  size_t num_cells() const { return sites.size(); }
  // The cell across face f from cell c (-1 for a wall).
  int other(int face, int cell) const {
    const VoronoiFace& f = faces[static_cast<size_t>(face)];
    return f.cell_a == cell ? f.cell_b : f.cell_a;
  }
};

// The mean of a face's vertices (the centre of a bent face's star).
inline Vec3 face_centre(const std::vector<Vec3>& vertices, const VoronoiFace& face) {
  Vec3 c = Vec3::Zero();
  for (int v : face.vertices) c += vertices[static_cast<size_t>(v)];
  return c / static_cast<double>(face.vertices.size());
}

// The triangles of a face, oriented from cell_a to cell_b, as vertex ids (-1: the face's centre): a fan
// from the smallest vertex id (the same for every user of the face, so neighbouring regions share
// identical triangles), or for a bent face a star around its centre.
template <class F>
void for_face_triangles(const VoronoiFace& face, F&& f) {
  const std::vector<int>& v = face.vertices;
  const size_t n = v.size();
  if (face.bent) {
    for (size_t i = 0; i < n; ++i) f(-1, v[i], v[(i + 1) % n]);
    return;
  }
  size_t m = 0;
  for (size_t i = 1; i < n; ++i)
    if (v[i] < v[m]) m = i;
  for (size_t i = 1; i + 1 < n; ++i) f(v[m], v[(m + i) % n], v[(m + i + 1) % n]);
}

// Computes the diagram. Sites must be finite, inside the box and pairwise distinct (closer than
// 1e-9 of the box diagonal counts as coincident). Throws NumericalError naming the site and its position
// when an input is unusable or voro++ cannot compute a cell.
VoronoiDiagram compute_voronoi(const std::vector<Vec3>& sites, const Vec3& box_lo, const Vec3& box_hi);

}  // namespace shellfrac::brittle
