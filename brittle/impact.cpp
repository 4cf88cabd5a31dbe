#include "brittle/impact.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "brittle/errors.hpp"
#include "brittle/triangle_index.hpp"

namespace shellfrac::brittle {

namespace {

// One surface element's part inside the contact ball: its centroid, the element's normal and its area.
struct Patch {
  Vec3 centroid, normal;
  double area;
};

// The part of triangle a b c within `radius` of `point`, by a barycentric subdivision fine against the
// radius (at most 64^2); area 0 if none.
Patch part_inside(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& n, const Vec3& point, double radius) {
  const double longest = std::max({(b - a).norm(), (c - b).norm(), (a - c).norm()});
  const int k = std::clamp(static_cast<int>(std::ceil(8.0 * longest / radius)), 1, 64);
  const double sub_area = 0.5 * n.norm() / (k * k);
  double inside = 0;
  Vec3 centroid = Vec3::Zero();
  const Vec3 e1 = (b - a) / k, e2 = (c - a) / k;
  for (int i = 0; i < k; ++i)
    for (int j = 0; i + j < k; ++j) {
      const Vec3 o = a + i * e1 + j * e2;
      const Vec3 up = o + (e1 + e2) / 3.0;                 // centroid of the upright sub-triangle
      if ((up - point).norm() <= radius) inside += sub_area, centroid += sub_area * up;
      if (i + j + 1 < k) {
        const Vec3 down = o + 2.0 * (e1 + e2) / 3.0;         // and of the inverted one next to it
        if ((down - point).norm() <= radius) inside += sub_area, centroid += sub_area * down;
      }
    }
  return {inside > 0 ? Vec3(centroid / inside) : Vec3::Zero(), n.normalized(), inside};
}

// The contact patch: the part of the surface within `radius` of the point (thesis sec. 3.9: a circular
// area). Each element that reaches into it gives one patch at the centroid of its part inside, so that
// the load is a uniform traction over the patch whatever the tessellation. (Choosing whole elements by
// their centroids put the whole load of an impact on a coarsely meshed face, e.g. a box face of four large
// triangles, on the centroid of the nearest triangle, several centimetres off the point.) A point off the
// surface by more than the radius gets its closest point. `fail` is called for a point too far away.
template <class Fail>
std::vector<Patch> contact_patches(const Impact& im, const TriMesh& mesh, double radius, double tolerance, Fail&& fail) {
  std::vector<Patch> patches;
  double nearest = std::numeric_limits<double>::infinity();
  size_t nearest_tri = 0;
  Vec3 nearest_point = Vec3::Zero();
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Tri& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
    const Vec3 q = closest_point_on_triangle(im.point, a, b, c);
    const double d = (q - im.point).norm();
    if (d < nearest) {
      nearest = d;
      nearest_tri = t;
      nearest_point = q;
    }
    if (d > radius) continue;
    const Vec3 n = (b - a).cross(c - a);
    if (!(n.norm() > 0)) continue;
    const Patch part = part_inside(a, b, c, n, im.point, radius);
    if (part.area > 0) patches.push_back(part);
  }
  if (!(nearest <= tolerance)) {
    std::ostringstream m;
    m << "point (" << im.point.transpose() << ") is " << nearest << " m from the surface of '" << mesh.name
      << "' (more than " << tolerance << " m): impacts must touch the object";
    fail(m.str());
  }
  if (patches.empty()) {
    const Tri& tri = mesh.triangles[nearest_tri];
    const Vec3 n = (mesh.positions[tri[1]] - mesh.positions[tri[0]]).cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    if (n.norm() > 0) patches.push_back({nearest_point, n.normalized(), 0.5 * n.norm()});
  }
  return patches;
}

// The solid particle nearest to x at rest.
size_t nearest_particle(const BrittleSolid& solid, const Vec3& x) {
  size_t anchor = 0;
  double best = std::numeric_limits<double>::infinity();
  for (size_t p = 0; p < solid.size(); ++p) {
    const double d = (solid.rest[p] - x).squaredNorm();
    if (d < best) {
      best = d;
      anchor = p;
    }
  }
  return anchor;
}

}  // namespace

std::vector<GhostParticle> impact_ghosts(const Impact& im, const TriMesh& mesh, const BrittleSolid& solid,
                                         const std::string& source) {
  auto fail = [&](const std::string& why) { throw InputError(source + ": impact " + why); };
  if (!im.point.allFinite()) fail("point is not finite");
  if (!(im.impulse > 0) || !std::isfinite(im.impulse)) fail("impulse must be > 0 (got " + std::to_string(im.impulse) + " N s)");
  if (!(im.duration > 0) || !std::isfinite(im.duration)) fail("duration must be > 0 (got " + std::to_string(im.duration) + " s)");
  if (!(im.direction.norm() > 0) || !im.direction.allFinite()) fail("direction must be a non-zero vector");
  if (solid.size() == 0) fail("has no particles to act on");
  const Vec3 dir = im.direction.normalized();
  const double radius = im.radius > 0 ? im.radius : 2.0 * solid.spacing;
  const std::vector<Patch> patches = contact_patches(im, mesh, radius, std::max(radius, 2.0 * solid.spacing), fail);

  double area = 0;
  Vec3 mean_normal = Vec3::Zero();
  for (const Patch& pa : patches) {
    area += pa.area;
    mean_normal += pa.area * pa.normal;
  }
  if (!(area > 0)) fail("touches only degenerate (zero-area) triangles");
  Vec3 push = dir;
  if (!(dir.dot(mean_normal) < 0) && im.normal_if_outward && mean_normal.norm() > 0) push = -mean_normal.normalized();
  if (!(push.dot(mean_normal) < 0)) {
    std::ostringstream m;
    m << "direction (" << dir.transpose() << ") points out of the object at (" << im.point.transpose()
      << "); an impact pushes into the surface (against its outward normal (" << mean_normal.normalized().transpose() << "))";
    fail(m.str());
  }
  const Vec3 total_force = (im.impulse / im.duration) * push;
  std::vector<GhostParticle> ghosts;
  for (const Patch& pa : patches) {
    GhostParticle g;
    g.rest = pa.centroid - 0.5 * solid.spacing * pa.normal;  // just inside, where nodes have mass
    g.force = total_force * (pa.area / area);  // traction I n / (t_c A) times the patch's area (Eq. 3.12)
    g.start = im.start_time;
    g.end = im.start_time + im.duration;
    g.anchor = nearest_particle(solid, g.rest);
    ghosts.push_back(g);
  }
  return ghosts;
}

double impact_duration(const HertzBody& projectile, const BrittleSolid& solid, const Vec3& contact_point, double v) {
  double mass = 0;
  Vec3 centre = Vec3::Zero();
  for (size_t p = 0; p < solid.size(); ++p) {
    mass += solid.particles.mass[p];
    centre += solid.particles.mass[p] * solid.rest[p];
  }
  if (!(mass > 0)) throw InputError("impact_duration: the solid has no mass");
  centre /= mass;
  HertzBody object;
  object.youngs_modulus = solid.material.youngs_modulus;
  object.poisson_ratio = solid.material.poisson_ratio;
  object.radius = (contact_point - centre).norm();
  object.mass = mass;
  return hertz_contact_time(projectile, object, v);
}

}  // namespace shellfrac::brittle
