#include "crack2d/voronoi_medial_axis.hpp"

#include <boost/polygon/voronoi.hpp>

#include <algorithm>
#include <cmath>
#include <unordered_map>

namespace shellfrac::crack2d {

namespace {
constexpr double kLatticeSteps = 268435456.0;  // 2^28 across the larger domain side
constexpr double kNodeMergeFraction = 1e-7;   // of the larger domain side (about 27 lattice steps)
constexpr double kOriginShiftU = 0.3183;      // lattice origin offset, in steps (see SeedLattice)
constexpr double kOriginShiftV = 0.6180;

using BoostPoint = boost::polygon::point_data<int32_t>;

// Merges points closer than tol into one node; deterministic (first come keeps its coordinates).
class NodeWelder {
 public:
  explicit NodeWelder(double tol) : tol_(tol) {}
  int add(const Point& p, std::vector<Point>& nodes) {
    const int64_t cx = static_cast<int64_t>(std::floor(p.x() / tol_));
    const int64_t cy = static_cast<int64_t>(std::floor(p.y() / tol_));
    for (int64_t dx = -1; dx <= 1; ++dx)
      for (int64_t dy = -1; dy <= 1; ++dy) {
        auto it = buckets_.find(key(cx + dx, cy + dy));
        if (it == buckets_.end()) continue;
        for (int id : it->second)
          if ((nodes[id] - p).norm() <= tol_) return id;
      }
    nodes.push_back(p);
    const int id = static_cast<int>(nodes.size()) - 1;
    buckets_[key(cx, cy)].push_back(id);
    return id;
  }

 private:
  static uint64_t key(int64_t x, int64_t y) {
    return (static_cast<uint64_t>(x) * 0x9E3779B97F4A7C15ull) ^ static_cast<uint64_t>(y);
  }
  double tol_;
  std::unordered_map<uint64_t, std::vector<int>> buckets_;
};
}  // namespace

SeedLattice::SeedLattice(const Box& domain) {
  const double side = std::max({domain.hi.x() - domain.lo.x(), domain.hi.y() - domain.lo.y(), 1e-300});
  scale = kLatticeSteps / side;
  // The lattice origin sits off the domain centre by different fractions of a step in u and v, so
  // seeds placed symmetrically about the centre or a diagonal do not stay exactly symmetric after
  // rounding. Otherwise their bisectors run exactly along the symmetry lines, through the quadrature
  // points, cell centres and Greville points lying there, which then have no side of the crack.
  centre = 0.5 * (domain.lo + domain.hi) + Point(kOriginShiftU, kOriginShiftV) / scale;
}

std::array<int32_t, 2> SeedLattice::quantise(const Point& p) const {
  // Seeds lie in the domain, so |q| <= 2^27; the clamp only guards against callers passing far-off points.
  const double limit = 1.0e9;
  const double qx = std::clamp(std::round((p.x() - centre.x()) * scale), -limit, limit);
  const double qy = std::clamp(std::round((p.y() - centre.y()) * scale), -limit, limit);
  return {static_cast<int32_t>(qx), static_cast<int32_t>(qy)};
}

Point SeedLattice::to_parameter(double qx, double qy) const {
  return Point(centre.x() + qx / scale, centre.y() + qy / scale);
}

VoronoiGraph build_voronoi_graph(const std::vector<Point>& seeds, const Box& domain) {
  VoronoiGraph out;
  const SeedLattice lattice(domain);
  // Distinct lattice sites, each remembering the first seed that produced it.
  std::vector<BoostPoint> sites;
  std::vector<int> site_seed;
  std::unordered_map<uint64_t, int> seen;
  for (size_t i = 0; i < seeds.size(); ++i) {
    const auto q = lattice.quantise(seeds[i]);
    if (seen.emplace(SeedLattice::key(q), static_cast<int>(i)).second) {
      sites.emplace_back(q[0], q[1]);
      site_seed.push_back(static_cast<int>(i));
    }
  }
  if (sites.size() < 2) return out;

  boost::polygon::voronoi_diagram<double> diagram;
  boost::polygon::construct_voronoi(sites.begin(), sites.end(), &diagram);

  const double side = std::max(domain.hi.x() - domain.lo.x(), domain.hi.y() - domain.lo.y());
  NodeWelder welder(kNodeMergeFraction * side);
  const double ray_length = 4.0 * kLatticeSteps;  // in lattice units: far beyond the domain
  for (const auto& edge : diagram.edges()) {
    const auto* twin = edge.twin();
    if (&edge > twin) continue;  // visit each undirected edge once
    const size_t ci = edge.cell()->source_index(), cj = twin->cell()->source_index();
    const BoostPoint& p1 = sites[ci];
    const BoostPoint& p2 = sites[cj];
    Point a, b;
    // Rays and full lines: the bisector runs along the perpendicular of (p1 -> p2), with p1's cell on its left.
    const double ox = 0.5 * (double(p1.x()) + double(p2.x())), oy = 0.5 * (double(p1.y()) + double(p2.y()));
    double dx = double(p1.y()) - double(p2.y()), dy = double(p2.x()) - double(p1.x());
    const double dnorm = std::hypot(dx, dy);
    dx /= dnorm;
    dy /= dnorm;
    if (edge.vertex0())
      a = lattice.to_parameter(edge.vertex0()->x(), edge.vertex0()->y());
    else
      a = lattice.to_parameter(ox - dx * ray_length, oy - dy * ray_length);
    if (edge.vertex1())
      b = lattice.to_parameter(edge.vertex1()->x(), edge.vertex1()->y());
    else
      b = lattice.to_parameter(ox + dx * ray_length, oy + dy * ray_length);
    Segment s{a, b};
    if (!clip_segment_to_box(s, domain)) continue;
    const int na = welder.add(s.a, out.nodes);
    const int nb = welder.add(s.b, out.nodes);
    if (na == nb) continue;
    const int sa = site_seed[ci], sb = site_seed[cj];
    out.edges.push_back({na, nb, std::min(sa, sb), std::max(sa, sb)});
  }
  return out;
}

}  // namespace shellfrac::crack2d
