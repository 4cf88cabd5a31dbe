#include "brittle/impact.hpp"

#include <cmath>
#include <limits>
#include <sstream>

#include "brittle/errors.hpp"
#include "brittle/triangle_index.hpp"

namespace shellfrac::brittle {

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

  // Elements around the point; the nearest element's distance decides whether the point is on the object.
  std::vector<size_t> chosen;
  double nearest = std::numeric_limits<double>::infinity();
  size_t nearest_tri = 0;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Tri& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
    const double d = (closest_point_on_triangle(im.point, a, b, c) - im.point).norm();
    if (d < nearest) {
      nearest = d;
      nearest_tri = t;
    }
    if (((a + b + c) / 3.0 - im.point).norm() <= radius) chosen.push_back(t);
  }
  const double tolerance = std::max(radius, 2.0 * solid.spacing);
  if (!(nearest <= tolerance)) {
    std::ostringstream m;
    m << "point (" << im.point.transpose() << ") is " << nearest << " m from the surface of '" << mesh.name
      << "' (more than " << tolerance << " m): impacts must touch the object";
    fail(m.str());
  }
  if (chosen.empty()) chosen.push_back(nearest_tri);

  double area = 0;
  Vec3 mean_normal = Vec3::Zero();
  for (size_t t : chosen) {
    const Tri& tri = mesh.triangles[t];
    const Vec3 n = (mesh.positions[tri[1]] - mesh.positions[tri[0]]).cross(mesh.positions[tri[2]] - mesh.positions[tri[0]]);
    area += 0.5 * n.norm();
    mean_normal += 0.5 * n;
  }
  if (!(area > 0)) fail("touches only degenerate (zero-area) triangles");
  if (!(dir.dot(mean_normal) < 0)) {
    std::ostringstream m;
    m << "direction (" << dir.transpose() << ") points out of the object at (" << im.point.transpose()
      << "); an impact pushes into the surface (against its outward normal (" << mean_normal.normalized().transpose() << "))";
    fail(m.str());
  }
  const Vec3 total_force = (im.impulse / im.duration) * dir;
  std::vector<GhostParticle> ghosts;
  for (size_t t : chosen) {
    const Tri& tri = mesh.triangles[t];
    const Vec3 &a = mesh.positions[tri[0]], &b = mesh.positions[tri[1]], &c = mesh.positions[tri[2]];
    const Vec3 n = (b - a).cross(c - a);
    const double ae = 0.5 * n.norm();
    if (!(ae > 0)) continue;
    GhostParticle g;
    g.rest = (a + b + c) / 3.0 - 0.5 * solid.spacing * n.normalized();  // just inside, where nodes have mass
    g.force = total_force * (ae / area);  // traction I n / (t_c A_e) spread in proportion to area
    g.start = im.start_time;
    g.end = im.start_time + im.duration;
    double best = std::numeric_limits<double>::infinity();
    for (size_t p = 0; p < solid.size(); ++p) {
      const double d = (solid.rest[p] - g.rest).squaredNorm();
      if (d < best) {
        best = d;
        g.anchor = p;
      }
    }
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
