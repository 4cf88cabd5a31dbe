#pragma once
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
