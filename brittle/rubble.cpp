#include "brittle/rubble.hpp"

#include <algorithm>
#include <cmath>

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

}  // namespace shellfrac::brittle
