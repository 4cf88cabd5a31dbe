#include "brittle/crack_grid.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "brittle/errors.hpp"
#include "mpm/bspline_weights.hpp"

namespace shellfrac::brittle {

namespace {
constexpr int kMargin = 3;  // nodes beyond the stencils: B' and the searches stay inside the box
constexpr double kBytesPerNode = 2 * sizeof(double) + sizeof(uint16_t);
}  // namespace

double CrackGrid::memory_estimate(const Vec3& lo, const Vec3& hi, double h) {
  double nodes = 1;
  for (int a = 0; a < 3; ++a) nodes *= std::floor((hi[a] - lo[a]) / h) + 3 + 2 * kMargin;
  return nodes * kBytesPerNode;
}

CrackGrid::CrackGrid(const std::vector<Vec3>& rest, const std::vector<double>& c_his, const CrackGridOptions& o)
    : h_(o.spacing) {
  if (!(o.spacing > 0) || !std::isfinite(o.spacing))
    throw InputError("crack extraction: grid spacing h_v must be > 0 (got " + std::to_string(o.spacing) + ")");
  if (c_his.size() != rest.size()) throw InputError("crack extraction: one damage value per particle is needed");
  place_box(rest, o);
  std::vector<double> weight, damaged;
  rasterise(rest, c_his, o.damage_threshold, weight, damaged);
  restore_islands(weight, damaged);
  // Damaged fraction of the rasterised weight: 1 inside the damaged region, falling to 0 across its
  // boundary, and unaffected by the domain boundary (where both weights fall off together).
  damaged_weight_.assign(weight.size(), -1.0f);
  for (size_t i = 0; i < weight.size(); ++i)
    if (weight[i] > 0) damaged_weight_[i] = static_cast<float>(damaged[i] / weight[i]);
  classify(o.neighbour_radius);
}

void CrackGrid::place_box(const std::vector<Vec3>& rest, const CrackGridOptions& o) {
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (size_t p = 0; p < rest.size(); ++p) {
    if (!rest[p].allFinite()) throw InputError("crack extraction: particle " + std::to_string(p) + " has a non-finite rest position");
    lo = lo.cwiseMin(rest[p]);
    hi = hi.cwiseMax(rest[p]);
  }
  if (rest.empty()) lo = hi = Vec3::Zero();
  const double bytes = memory_estimate(lo, hi, h_);
  if (bytes > static_cast<double>(o.memory_limit)) {
    std::ostringstream m;
    m << "crack extraction: h_v = " << h_ << " m is too small for an object of extent " << (hi - lo).transpose()
      << " m: the grid would need about " << bytes / 1e9 << " GB (limit " << o.memory_limit / 1e9
      << " GB); use h_v of at least " << h_ * std::cbrt(bytes / static_cast<double>(o.memory_limit)) << " m";
    throw InputError(m.str());
  }
  const double inv_h = 1.0 / h_;
  for (int a = 0; a < 3; ++a) {
    lo_[a] = static_cast<int>(std::floor(lo[a] * inv_h - 0.5)) - kMargin;
    dims_[a] = static_cast<int>(std::floor(hi[a] * inv_h - 0.5)) + 2 + kMargin - lo_[a] + 1;
  }
}

void CrackGrid::rasterise(const std::vector<Vec3>& rest, const std::vector<double>& c_his, double threshold,
                          std::vector<double>& weight, std::vector<double>& damaged) {
  const size_t n = static_cast<size_t>(dims_.x()) * dims_.y() * dims_.z();
  weight.assign(n, 0.0);
  damaged.assign(n, 0.0);
  flags_.assign(n, 0);
  const double inv_h = 1.0 / h_;
  for (size_t p = 0; p < rest.size(); ++p) {
    const mpm::StencilWeights sw = mpm::stencil_weights(rest[p], inv_h);  // Eq. 2.10
    const int base[3] = {sw.ax[0].base, sw.ax[1].base, sw.ax[2].base};
    const bool full = c_his[p] >= threshold;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const double wt = sw.weight(i, j, k);
          if (!(wt > 0)) continue;
          const size_t idx = static_cast<size_t>(index(base[0] + i - lo_.x(), base[1] + j - lo_.y(), base[2] + k - lo_.z()));
          weight[idx] += wt;
          if (full) damaged[idx] += wt;
        }
  }
  for (size_t i = 0; i < n; ++i) {
    if (weight[i] > 0) flags_[i] |= kActive;
    if (damaged[i] > 0) flags_[i] |= kDamaged;
  }
}

void CrackGrid::classify(int neighbour_radius) {
  const size_t n = flags_.size();
  // Boundaries by 6-neighbourhood.
  const int off[6][3] = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  // Whether a 6-neighbour satisfies pred; a neighbour outside the box counts as `outside`.
  auto any_neighbour = [&](size_t i, bool outside, auto&& pred) {
    const Eigen::Vector3i c = coords(i);
    for (const auto& d : off) {
      const long j = index(c.x() + d[0], c.y() + d[1], c.z() + d[2]);
      if (j < 0 ? outside : pred(static_cast<size_t>(j))) return true;
    }
    return false;
  };
  std::vector<uint16_t> f = flags_;
  for (size_t i = 0; i < n; ++i) {
    const uint16_t fi = flags_[i];
    if (fi & kActive) {
      if (any_neighbour(i, true, [&](size_t j) { return !(flags_[j] & kActive); })) f[i] |= kSetB;
    } else if (any_neighbour(i, false, [&](size_t j) { return (flags_[j] & kActive) != 0; })) {
      f[i] |= kSetBd;
    }
    if (fi & kDamaged) {
      if (any_neighbour(i, true, [&](size_t j) { return !(flags_[j] & kDamaged); })) f[i] |= kSetD;
      else f[i] |= kInterior;
    }
  }
  for (size_t i = 0; i < n; ++i) {
    if ((f[i] & kSetD) && (f[i] & kSetB)) f[i] |= kSetS;
    else if (f[i] & kSetD) f[i] |= kSetV;
  }
  // N: within neighbour_radius of S (Chebyshev); B' nodes one step further out are also oriented.
  const int r = std::max(1, neighbour_radius);
  for (size_t i = 0; i < n; ++i) {
    if (!(f[i] & kSetS)) continue;
    const Eigen::Vector3i c = coords(i);
    for (int dz = -r - 1; dz <= r + 1; ++dz)
      for (int dy = -r - 1; dy <= r + 1; ++dy)
        for (int dx = -r - 1; dx <= r + 1; ++dx) {
          const long j = index(c.x() + dx, c.y() + dy, c.z() + dz);
          if (j < 0 || static_cast<size_t>(j) == i) continue;
          const bool inner = std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) <= r;
          if (inner && !(f[j] & kSetS)) f[j] |= kSetN;
          if (f[j] & kSetBd) f[j] |= kSetBdNear;
        }
  }
  for (size_t i = 0; i < n; ++i) {
    if (!(f[i] & kSetV)) continue;
    f[i] |= (f[i] & kSetN) ? kSetE : kSetI;
  }
  // The middle of an exit: S nodes whose active 6-neighbours are all damaged lie inside the footprint of
  // the damaged band on the surface, i.e. on (or near) the crack's continuation. A B' site in front of
  // such a node would own a cell on both sides of the crack (at a junction of several sheets, on all of
  // them), which no orientation can split, so it is left out and the E cells extend past it.
  for (size_t i = 0; i < n; ++i) {
    if (!(f[i] & kSetS)) continue;
    if (any_neighbour(i, false, [&](size_t j) { return (f[j] & kActive) && !(f[j] & kDamaged); })) continue;
    const Eigen::Vector3i c = coords(i);
    for (const auto& d : off) {
      const long j = index(c.x() + d[0], c.y() + d[1], c.z() + d[2]);
      if (j >= 0 && (f[j] & kSetBd)) f[j] |= kSetBdExit;
    }
  }
  flags_.swap(f);
}

void CrackGrid::restore_islands(const std::vector<double>& weight, const std::vector<double>& damaged) {
  // Candidates: damaged nodes where intact particles hold at least half of the rasterised weight.
  const size_t n = flags_.size();
  auto candidate = [&](size_t i) { return (flags_[i] & kDamaged) && damaged[i] <= 0.5 * weight[i]; };
  std::vector<int> group(n, -1);
  std::vector<size_t> members, queue;
  int next = 0;
  for (size_t start = 0; start < n; ++start) {
    if (group[start] != -1 || !candidate(start)) continue;
    // One 26-connected group of candidates; it is swallowed if no node next to it is intact already.
    members.clear();
    queue.assign(1, start);
    group[start] = -2;
    bool touches_intact = false;
    while (!queue.empty()) {
      const size_t i = queue.back();
      queue.pop_back();
      members.push_back(i);
      const Eigen::Vector3i c = coords(i);
      for (int dz = -1; dz <= 1; ++dz)
        for (int dy = -1; dy <= 1; ++dy)
          for (int dx = -1; dx <= 1; ++dx) {
            const long j = index(c.x() + dx, c.y() + dy, c.z() + dz);
            if (j < 0) continue;
            const size_t u = static_cast<size_t>(j);
            if ((flags_[u] & kActive) && !(flags_[u] & kDamaged)) touches_intact = true;
            if (group[u] == -1 && candidate(u)) {
              group[u] = -2;
              queue.push_back(u);
            }
          }
    }
    if (touches_intact) continue;  // the flank of an ordinary crack band
    if (island_.empty()) island_.assign(n, -1);
    for (size_t i : members) {
      island_[i] = next;
      flags_[i] = static_cast<uint16_t>((flags_[i] & ~kDamaged) | kIsland);
    }
    ++next;
  }
  islands_ = static_cast<size_t>(next);
}

int CrackGrid::bordering_island(size_t n) const {
  if (island_.empty()) return -1;
  const Eigen::Vector3i c = coords(n);
  int found = -1;
  for (int dz = -1; dz <= 1; ++dz)
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const long j = index(c.x() + dx, c.y() + dy, c.z() + dz);
        if (j < 0) continue;
        const size_t u = static_cast<size_t>(j);
        if (!(flags_[u] & kActive) || (flags_[u] & kDamaged)) continue;  // not intact
        if (island_[u] < 0 || (found >= 0 && island_[u] != found)) return -2;
        found = island_[u];
      }
  return found;
}

Vec3 CrackGrid::position(size_t n) const { return (coords(n) + lo_).cast<double>() * h_; }

Eigen::Vector3i CrackGrid::coords(size_t n) const {
  const long sx = dims_.x(), sxy = static_cast<long>(dims_.x()) * dims_.y();
  const long i = static_cast<long>(n);
  return Eigen::Vector3i(static_cast<int>(i % sx), static_cast<int>((i / sx) % dims_.y()), static_cast<int>(i / sxy));
}

long CrackGrid::index(int i, int j, int k) const {
  if (i < 0 || j < 0 || k < 0 || i >= dims_.x() || j >= dims_.y() || k >= dims_.z()) return -1;
  return i + static_cast<long>(dims_.x()) * (j + static_cast<long>(dims_.y()) * k);
}

size_t CrackGrid::count(uint16_t set) const {
  size_t c = 0;
  for (uint16_t f : flags_) c += (f & set) ? 1 : 0;
  return c;
}

double CrackGrid::interior_fraction(const Vec3& x) const {
  const Vec3 q = x / h_ - lo_.cast<double>();
  const Eigen::Vector3i b = q.array().floor().cast<int>();
  const Vec3 t = q - b.cast<double>();
  double sum = 0;
  for (int dz = 0; dz < 2; ++dz)
    for (int dy = 0; dy < 2; ++dy)
      for (int dx = 0; dx < 2; ++dx) {
        const long j = index(b.x() + dx, b.y() + dy, b.z() + dz);
        if (j < 0 || !(flags_[static_cast<size_t>(j)] & kInterior)) continue;
        sum += (dx ? t.x() : 1 - t.x()) * (dy ? t.y() : 1 - t.y()) * (dz ? t.z() : 1 - t.z());
      }
  return sum;
}

Vec3 CrackGrid::damage_normal(size_t n) const {
  const Eigen::Vector3i c = coords(n);
  const float own = damaged_weight_[n];
  auto value = [&](const Eigen::Vector3i& q) {  // outside the domain: the node's own value (one-sided)
    const long i = index(q.x(), q.y(), q.z());
    return i >= 0 && damaged_weight_[static_cast<size_t>(i)] >= 0 ? damaged_weight_[static_cast<size_t>(i)] : own;
  };
  Vec3 g;
  for (int a = 0; a < 3; ++a) {
    Eigen::Vector3i p = c, m = c;
    ++p[a];
    --m[a];
    g[a] = value(p) - value(m);
  }
  const double len = g.norm();
  return len > 0 ? Vec3(-g / len) : Vec3(Vec3::Zero());
}

long CrackGrid::nearest_in(size_t n, uint16_t set, int max_steps) const {
  // Rings of growing Chebyshev radius around n: the first ring holding I nodes decides; within it the
  // Euclidean nearest, ties to the lower index (deterministic "any" of Algorithm 2).
  const Eigen::Vector3i c = coords(n);
  const Vec3 x = position(n);
  for (int r = 1; r <= max_steps; ++r) {
    long best = -1;
    double best_d = std::numeric_limits<double>::infinity();
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy)
        for (int dx = -r; dx <= r; ++dx) {
          if (std::max({std::abs(dx), std::abs(dy), std::abs(dz)}) != r) continue;
          const long j = index(c.x() + dx, c.y() + dy, c.z() + dz);
          if (j < 0 || !(flags_[static_cast<size_t>(j)] & set)) continue;
          const double d = (position(static_cast<size_t>(j)) - x).squaredNorm();
          if (d < best_d || (d == best_d && j < best)) {
            best_d = d;
            best = j;
          }
        }
    if (best >= 0) return best;
  }
  return -1;
}

}  // namespace shellfrac::brittle
