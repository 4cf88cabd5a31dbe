#include "mpm/solid_particles.hpp"

#include <tbb/parallel_for.h>

#include <Eigen/LU>
#include <array>
#include <cmath>
#include <random>
#include <unordered_map>

namespace shellfrac::mpm {

void SolidParticles::add(const std::vector<Vec3>& points, double spacing, const Vec3& v0) {
  const double V = spacing * spacing * spacing;
  for (const Vec3& p : points) {
    x.push_back(p);
    v.push_back(v0);
    volume.push_back(V);
    mass.push_back(material.density * V);
    F.push_back(Mat3::Identity());
    C.push_back(Mat3::Zero());
    stress.push_back(Mat3::Zero());
  }
}

size_t SolidParticles::compute_stress() {
  std::vector<unsigned char> bad(size(), 0);
  tbb::parallel_for(size_t{0}, size(), [&](size_t p) {
    const Mat3& f = F[p];
    const double J = f.determinant();
    if (!(J > 0) || !f.allFinite()) {
      bad[p] = 1;
      return;
    }
    // V^0 P F^T with P = mu (F - F^-T) + lambda ln J F^-T (Eq. 2.6): V^0 (mu (F F^T - I) + lambda ln J I).
    stress[p] = volume[p] * (material.mu * (f * f.transpose() - Mat3::Identity()) +
                             material.lambda * std::log(J) * Mat3::Identity());
  });
  for (size_t p = 0; p < size(); ++p)
    if (bad[p]) return p;
  return size();
}

void SolidParticles::update(double dt) {
  tbb::parallel_for(size_t{0}, size(), [&](size_t p) {
    F[p] = (Mat3::Identity() + dt * C[p]) * F[p];  // Eq. 2.26
    x[p] += dt * v[p];                              // Eq. 2.21
  });
}

ParticleSet SolidParticles::view() {
  ParticleSet s;
  s.count = size();
  s.position = x.data();
  s.velocity = v.data();
  s.mass = mass.data();
  s.stress = stress.data();
  s.mls_force = true;
  s.affine = C.data();
  return s;
}

std::vector<Vec3> sample_jittered(const Shape& shape, const Vec3& lo, const Vec3& hi, double spacing, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::vector<Vec3> out;
  const Eigen::Vector3i n = ((hi - lo) / spacing).array().ceil().cast<int>();
  for (int k = 0; k < n.z(); ++k)
    for (int j = 0; j < n.y(); ++j)
      for (int i = 0; i < n.x(); ++i) {
        const Vec3 p = lo + spacing * Vec3(i + u(rng), j + u(rng), k + u(rng));
        if (shape.signed_distance(p) < 0) out.push_back(p);
      }
  return out;
}

std::vector<Vec3> sample_poisson_disk(const Shape& shape, const Vec3& lo, const Vec3& hi, double spacing,
                                      unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const double cell = spacing / std::sqrt(3.0);  // at most one point per background cell
  auto key = [&](const Vec3& p) {
    const Eigen::Vector3i c = ((p - lo) / cell).array().floor().cast<int>();
    return (static_cast<long long>(c.x()) * 73856093LL) ^ (static_cast<long long>(c.y()) * 19349663LL) ^
           (static_cast<long long>(c.z()) * 83492791LL);
  };
  std::unordered_multimap<long long, size_t> grid;
  std::vector<Vec3> out;
  auto fits = [&](const Vec3& p) {
    if ((p.array() < lo.array()).any() || (p.array() > hi.array()).any() || shape.signed_distance(p) >= 0) return false;
    const Eigen::Vector3i c = ((p - lo) / cell).array().floor().cast<int>();
    for (int dz = -2; dz <= 2; ++dz)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const Vec3 q = lo + cell * Vec3(c.x() + dx + 0.5, c.y() + dy + 0.5, c.z() + dz + 0.5);
          auto range = grid.equal_range(key(q));
          for (auto it = range.first; it != range.second; ++it)
            if ((out[it->second] - p).norm() < spacing) return false;
        }
    return true;
  };
  auto insert = [&](const Vec3& p) {
    grid.emplace(key(p), out.size());
    out.push_back(p);
  };
  // Seed: the first jittered point found inside the shape.
  for (const Vec3& p : sample_jittered(shape, lo, hi, spacing, seed)) {
    if (fits(p)) {
      insert(p);
      break;
    }
  }
  std::vector<size_t> active(out.empty() ? 0 : 1, 0);
  while (!active.empty()) {
    const size_t pick = static_cast<size_t>(u(rng) * static_cast<double>(active.size())) % active.size();
    const Vec3 centre = out[active[pick]];
    bool placed = false;
    for (int t = 0; t < 30 && !placed; ++t) {
      // Uniform in the shell between spacing and 2 spacing around the active point.
      Vec3 dir(u(rng) - 0.5, u(rng) - 0.5, u(rng) - 0.5);
      if (dir.norm() < 1e-9) continue;
      const double r = spacing * std::cbrt(1.0 + 7.0 * u(rng));
      const Vec3 cand = centre + r * dir.normalized();
      if (fits(cand)) {
        active.push_back(out.size());
        insert(cand);
        placed = true;
      }
    }
    if (!placed) {
      active[pick] = active.back();
      active.pop_back();
    }
  }
  return out;
}

}  // namespace shellfrac::mpm
