#include "brittle/brittle_solid.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <sstream>
#include <tuple>

#include "brittle/errors.hpp"
#include "mpm/level_set_shape.hpp"

namespace shellfrac::brittle {

void BrittleSolid::add_particles(const std::vector<Vec3>& points, double particle_volume, const Vec3& velocity) {
  const size_t first = size();
  for (const Vec3& p : points) {
    particles.x.push_back(p);
    particles.v.push_back(velocity);
    particles.volume.push_back(particle_volume);
    particles.mass.push_back(material.density * particle_volume);
    particles.F.push_back(Mat3::Identity());
    particles.C.push_back(Mat3::Zero());
    particles.stress.push_back(Mat3::Zero());
    rest.push_back(p);
    damage.emplace_back();
    failure_stress.push_back(material.failure_stress);
    brittleness.push_back(0.0);
  }
  particles.material = {material.mu(), material.lambda(), material.density};
  (void)first;
}

void BrittleSolid::set_strength(const std::vector<StrengthRegion>& regions, const WeibullStrength& weibull, double grid_dx) {
  if (!(material.youngs_modulus > 0)) throw InputError("youngs_modulus must be > 0");
  if (material.model == DamageModel::Nacc) {
    // NACC breaks by softening of its yield surface: no failure stress, no fracture energy.
    if (!regions.empty() || weibull.enabled)
      throw InputError("strength regions and Weibull scatter belong to Rankine damage, not NACC plasticity");
    if (const std::string e = material.nacc.validate(); !e.empty()) throw InputError("nacc: " + e);
    failure_stress.assign(size(), 0.0);
    brittleness.assign(size(), 0.0);
    for (ParticleDamage& d : damage) d.alpha = material.nacc.alpha0;
    return;
  }
  if (!(material.fracture_energy > 0)) throw InputError("fracture_energy must be > 0");
  if (material.model == DamageModel::PhaseField) {
    // The phase field has no failure stress: the fracture energy and length scale set where it breaks.
    if (!regions.empty() || weibull.enabled)
      throw InputError("strength regions and Weibull scatter belong to Rankine damage, not the phase field");
    failure_stress.assign(size(), 0.0);
    brittleness.assign(size(), 0.0);
    return;
  }
  failure_stress = assign_failure_stress(rest, material.failure_stress, regions, weibull);
  const double l = material.characteristic_length > 0 ? material.characteristic_length : std::sqrt(3.0) * grid_dx;
  brittleness.resize(size());
  for (size_t p = 0; p < size(); ++p) {
    brittleness[p] = shellfrac::brittle::brittleness(failure_stress[p], material.fracture_energy, material.youngs_modulus, l);
    if (brittleness[p] < 0) {
      std::ostringstream m;
      m << "particle " << p << " at (" << rest[p].transpose() << "): failure stress " << failure_stress[p]
        << " Pa is too high for fracture_energy " << material.fracture_energy << " J/m^2 and characteristic length "
        << l << " m (needs sigma_f^2 l / (2 E G_f) < 1, here "
        << failure_stress[p] * failure_stress[p] * l / (2 * material.youngs_modulus * material.fracture_energy)
        << "); raise fracture_energy or lower the strength";
      throw InputError(m.str());
    }
  }
}

size_t BrittleSolid::count_damaged(double threshold) const {
  size_t n = 0;
  for (const ParticleDamage& d : damage) n += d.c_his >= threshold ? 1 : 0;
  return n;
}

std::vector<double> BrittleSolid::damage_history() const {
  std::vector<double> h(size());
  for (size_t p = 0; p < size(); ++p) h[p] = damage[p].c_his;
  return h;
}

namespace {

std::vector<Vec3> sort_by_cell(std::vector<Vec3> pts, double spacing) {
  std::vector<std::tuple<long, long, long, size_t>> key(pts.size());
  for (size_t i = 0; i < pts.size(); ++i)
    key[i] = {static_cast<long>(std::floor(pts[i].z() / (2 * spacing))), static_cast<long>(std::floor(pts[i].y() / (2 * spacing))),
              static_cast<long>(std::floor(pts[i].x() / (2 * spacing))), i};
  std::sort(key.begin(), key.end());
  std::vector<Vec3> out(pts.size());
  for (size_t i = 0; i < pts.size(); ++i) out[i] = pts[std::get<3>(key[i])];
  return out;
}

}  // namespace

std::vector<Vec3> sample_mesh(const TriMesh& mesh, double spacing, Sampling sampling, unsigned seed,
                              const std::string& source, size_t max_points) {
  require_closed_solid(mesh, source);
  if (!(spacing > 0)) throw InputError(source + ": particle spacing must be > 0");
  const double volume = inspect_mesh(mesh).volume;
  const double estimate = volume / (spacing * spacing * spacing);
  if (estimate > static_cast<double>(max_points)) {
    std::ostringstream m;
    m << source << ": particle spacing " << spacing << " m would sample about " << static_cast<size_t>(estimate)
      << " particles (about " << static_cast<size_t>(estimate * 400 / 1e6) << " MB); the limit is " << max_points
      << "; use a larger spacing";
    throw InputError(m.str());
  }
  std::vector<Vec3> verts(mesh.positions.begin(), mesh.positions.end());
  std::vector<Eigen::Vector3i> tris(mesh.triangles.begin(), mesh.triangles.end());
  const mpm::LevelSetShape shape(verts, tris, 0.5 * spacing);
  const Vec3 lo = shape.lower(), hi = shape.upper();
  std::vector<Vec3> pts;
  if (sampling == Sampling::Regular) {
    const Eigen::Vector3i n = ((hi - lo) / spacing).array().ceil().cast<int>();
    const Vec3 offset = 0.5 * ((hi - lo) - spacing * n.cast<double>());  // centre the lattice in the box
    for (int k = 0; k < n.z(); ++k)
      for (int j = 0; j < n.y(); ++j)
        for (int i = 0; i < n.x(); ++i) {
          const Vec3 p = lo + offset + spacing * Vec3(i + 0.5, j + 0.5, k + 0.5);
          if (shape.signed_distance(p) < 0) pts.push_back(p);
        }
  } else if (sampling == Sampling::Jittered) {
    pts = mpm::sample_jittered(shape, lo, hi, spacing, seed);
  } else {
    pts = mpm::sample_poisson_disk(shape, lo, hi, spacing, seed);
  }
  if (pts.empty()) throw InputError(source + ": no particle fits inside the mesh at spacing " + std::to_string(spacing));
  return sort_by_cell(std::move(pts), spacing);
}

BrittleSolid make_solid(const TriMesh& mesh, const BrittleMaterial& material, double spacing, Sampling sampling,
                        unsigned seed, const std::string& source) {
  BrittleSolid s;
  s.material = material;
  s.spacing = spacing;
  const std::vector<Vec3> pts = sample_mesh(mesh, spacing, sampling, seed, source);
  s.add_particles(pts, inspect_mesh(mesh).volume / static_cast<double>(pts.size()), Vec3::Zero());
  return s;
}

}  // namespace shellfrac::brittle
