#pragma once
#include <deque>
#include <vector>

#include "brittle/crack_surface.hpp"
#include "brittle/point_locator.hpp"

namespace shellfrac::brittle {

// Voronoi-tessellation regions (thesis sec. 3.5.1): maximal sets of cells connected through faces that
// are not crack faces, found by breadth-first search; numbered by their lowest cell.
struct Regions {
  std::vector<int> cell_region;
  int count = 0;
};
Regions find_regions(const VoronoiDiagram& diagram, const std::vector<char>& crack_face);

// Breadth-first search from the queued cells through faces that are not crack faces: every reached cell
// whose label is still -1 and that accept(cell) admits takes the label of the cell it was reached from.
// Leaves the queue empty.
template <class Accept>
void flood_cells(const VoronoiDiagram& d, const std::vector<char>& crack_face, std::vector<int>& label,
                 std::deque<int>& queue, Accept&& accept) {
  while (!queue.empty()) {
    const int c = queue.front();
    queue.pop_front();
    for (int f : d.cell_faces[static_cast<size_t>(c)]) {
      if (crack_face[static_cast<size_t>(f)]) continue;
      const int o = d.other(f, c);
      if (o < 0 || label[static_cast<size_t>(o)] >= 0 || !accept(o)) continue;
      label[static_cast<size_t>(o)] = label[static_cast<size_t>(c)];
      queue.push_back(o);
    }
  }
}

// The region's boundary as a closed, outward triangle mesh: faces towards other regions and the
// container walls (fans with a canonical first vertex, so that two regions share identical triangles
// along their common faces). Crack faces inside one region (partial cracks) are not part of it.
TriMesh region_boundary(const VoronoiDiagram& diagram, const Regions& regions, int region);

// The Voronoi cell containing a point: its nearest site.
class SiteLocator {
 public:
  explicit SiteLocator(const VoronoiDiagram& diagram) : locator_(diagram.sites) {}
  int cell_of(const Vec3& x) const { return locator_.nearest(x); }

 private:
  PointLocator locator_;
};

// For each region, the number of the given points (particles, material space) inside it.
std::vector<size_t> points_per_region(const VoronoiDiagram& diagram, const Regions& regions, const std::vector<Vec3>& points);

}  // namespace shellfrac::brittle
