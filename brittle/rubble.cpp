#include "brittle/rubble.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <tbb/parallel_for.h>

namespace shellfrac::brittle {

namespace {
constexpr int64_t kUnchecked = -2;
bool fully_damaged(const ParticleDamage& d) { return d.c_his >= 1.0; }
}  // namespace

RubbleFinder::RubbleFinder(const std::vector<Vec3>& rest, double radius) : rest_(&rest), radius_(radius) {
  blocker_.assign(rest.size(), kUnchecked);
  if (rest.empty() || !(radius > 0)) return;
  Vec3 lo = rest.front(), hi = lo;
  for (const Vec3& x : rest) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  buckets_ = PointBuckets(rest, std::max(radius, (hi - lo).maxCoeff() / 512.0));  // at most 512 per axis
}

int64_t RubbleFinder::intact_neighbour(size_t p, const std::vector<ParticleDamage>& damage) const {
  const std::vector<Vec3>& rest = *rest_;
  const Vec3& x = rest[p];
  const PointBuckets& g = buckets_;
  const Eigen::Vector3i c = g.bucket(x);
  const double r2 = radius_ * radius_;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const Eigen::Vector3i b = c + Eigen::Vector3i(dx, dy, dz);
        if (!g.inside(b)) continue;
        const size_t k = g.index(b);
        for (uint32_t e = g.offsets[k]; e < g.offsets[k + 1]; ++e) {
          const uint32_t q = g.items[e];
          if (!fully_damaged(damage[q]) && (rest[q] - x).squaredNorm() <= r2) return q;
        }
      }
  return -1;
}

std::vector<uint32_t> RubbleFinder::update(const std::vector<ParticleDamage>& damage, const uint8_t* eligible,
                                           std::vector<uint8_t>& rubble) {
  const size_t n = blocker_.size();
  std::vector<uint8_t> fresh(n, 0);
  if (rest_ && radius_ > 0) {
    tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t p = r.begin(); p != r.end(); ++p) {
        if (rubble[p] || !fully_damaged(damage[p]) || (eligible && !eligible[p])) continue;
        const int64_t b = blocker_[p];
        if (b >= 0 && !fully_damaged(damage[static_cast<size_t>(b)])) continue;  // still held
        blocker_[p] = intact_neighbour(p, damage);
        fresh[p] = blocker_[p] < 0;
      }
    });
  }
  std::vector<uint32_t> out;
  for (size_t p = 0; p < n; ++p)
    if (fresh[p]) {
      rubble[p] = 1;
      out.push_back(static_cast<uint32_t>(p));
    }
  return out;
}

Rubble::Rubble(const std::vector<Vec3>& rest, double radius) : finder_(rest, radius) { flag_.assign(rest.size(), 0); }

size_t Rubble::retire(mpm::SolidParticles& q, const std::vector<ParticleDamage>& damage) {
  eligible_.resize(q.size());
  tbb::parallel_for(tbb::blocked_range<size_t>(0, q.size(), 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p != r.end(); ++p) eligible_[p] = q.F[p].determinant() >= 1.0;
  });
  const std::vector<uint32_t> fresh = finder_.update(damage, eligible_.data(), flag_);
  if (fresh.empty()) return 0;
  if (count_ == 0) transfer_mass_ = q.mass;
  for (const uint32_t p : fresh) {
    // No mass and no stress: it adds nothing to p2g. It stays where it is (hold): as a tracer of the grid
    // velocity it would follow nodes that only the edge of some kernel reaches, whose velocities are
    // unbounded.
    transfer_mass_[p] = 0.0;
    momentum_ += q.mass[p] * q.v[p];
    q.stress[p].setZero();
    list_.push_back(p);
    held_x_.push_back(q.x[p]);
  }
  count_ += fresh.size();
  hold(q);
  return fresh.size();
}

void Rubble::hold(mpm::SolidParticles& q) const {
  for (size_t k = 0; k < list_.size(); ++k) {
    const size_t p = list_[k];
    q.x[p] = held_x_[k];
    q.v[p].setZero();
    q.C[p].setZero();
    q.F[p].setIdentity();
  }
}

void Rubble::reanchor(std::vector<GhostParticle>& ghosts, const std::vector<Vec3>& rest) {
  for (GhostParticle& g : ghosts) {
    if (!contains(g.anchor)) continue;
    size_t best = g.anchor;
    double best_d = std::numeric_limits<double>::infinity();
    for (size_t p = 0; p < rest.size(); ++p) {
      if (flag_[p]) continue;
      const double d = (rest[p] - g.rest).squaredNorm();
      if (d < best_d) {
        best_d = d;
        best = p;
      }
    }
    if (best == g.anchor) continue;  // everything is rubble: the ghost keeps pushing where it is
    ++reanchored_ghosts_;
    g.anchor = best;
    g.rest = rest[best];
  }
}

}  // namespace shellfrac::brittle
