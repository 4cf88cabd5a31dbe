#include "brittle/triangle_index.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace shellfrac::brittle {

Vec3 closest_point_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c, Vec3* bary) {
  // Voronoi regions of the vertices, edges and face (Ericson, Real-Time Collision Detection, 5.1.5).
  auto out = [&](double u, double v, double w) {
    if (bary) *bary = Vec3(u, v, w);
    return Vec3(u * a + v * b + w * c);
  };
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return out(1, 0, 0);
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return out(0, 1, 0);
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {
    const double v = d1 / (d1 - d3);
    return out(1 - v, v, 0);
  }
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return out(0, 0, 1);
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {
    const double w = d2 / (d2 - d6);
    return out(1 - w, 0, w);
  }
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0) {
    const double w = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return out(0, 1 - w, w);
  }
  const double denom = va + vb + vc;
  if (!(std::abs(denom) > 0)) return out(1, 0, 0);  // degenerate triangle: its first corner
  const double v = vb / denom, w = vc / denom;
  return out(1 - v - w, v, w);
}

TriangleIndex::TriangleIndex(const std::vector<Vec3>& positions, const std::vector<Tri>& triangles, double bucket,
                             double max_reach)
    : positions_(positions), triangles_(triangles) {
  normals_.resize(triangles_.size());
  if (triangles_.empty()) return;
  Vec3 lo = Vec3::Constant(std::numeric_limits<double>::infinity()), hi = -lo;
  for (const Tri& t : triangles_)
    for (int k = 0; k < 3; ++k) {
      lo = lo.cwiseMin(positions_[t[k]]);
      hi = hi.cwiseMax(positions_[t[k]]);
    }
  // Buckets no smaller than needed to keep the grid below ~16M buckets.
  const Vec3 ext = hi - lo;
  cell_ = std::max({bucket, 1e-12, std::cbrt(std::max(ext.prod(), 0.0) / 16e6), ext.maxCoeff() / 4096.0});
  inv_cell_ = 1.0 / cell_;
  lo_ = lo - Vec3::Constant(cell_);
  for (int a = 0; a < 3; ++a) dims_[a] = static_cast<int>(std::floor(ext[a] * inv_cell_)) + 3;
  const size_t buckets = static_cast<size_t>(dims_.x()) * dims_.y() * dims_.z();
  auto bucket_of = [&](int i, int j, int k) { return static_cast<size_t>(i + dims_.x() * (j + static_cast<long>(dims_.y()) * k)); };
  std::vector<std::pair<uint32_t, uint32_t>> pairs;  // (bucket, triangle)
  for (size_t t = 0; t < triangles_.size(); ++t) {
    const Vec3 &a = positions_[triangles_[t][0]], &b = positions_[triangles_[t][1]], &c = positions_[triangles_[t][2]];
    const Vec3 n = (b - a).cross(c - a);
    normals_[t] = n.norm() > 0 ? Vec3(n.normalized()) : Vec3(Vec3::Zero());
    const Vec3 centre = (a + b + c) / 3.0;
    spheres_.emplace_back(centre.x(), centre.y(), centre.z(), std::max({(a - centre).norm(), (b - centre).norm(), (c - centre).norm()}));
    const Eigen::Vector3i l = ((a.cwiseMin(b).cwiseMin(c) - lo_) * inv_cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1);
    const Eigen::Vector3i h = ((a.cwiseMax(b).cwiseMax(c) - lo_) * inv_cell_).array().floor().cast<int>().max(0).min(dims_.array() - 1);
    for (int k = l.z(); k <= h.z(); ++k)
      for (int j = l.y(); j <= h.y(); ++j)
        for (int i = l.x(); i <= h.x(); ++i) pairs.emplace_back(static_cast<uint32_t>(bucket_of(i, j, k)), static_cast<uint32_t>(t));
  }
  offsets_.assign(buckets + 1, 0);
  for (const auto& pr : pairs) ++offsets_[pr.first + 1];
  for (size_t b = 0; b < buckets; ++b) offsets_[b + 1] += offsets_[b];
  items_.resize(pairs.size());
  std::vector<uint32_t> cursor(offsets_.begin(), offsets_.end() - 1);
  for (const auto& pr : pairs) items_[cursor[pr.first]++] = pr.second;
  // Chebyshev distance transform of the occupied buckets (two passes of a 26-neighbour chamfer), capped
  // at the reach in buckets plus one.
  const int cap = std::min(250, static_cast<int>(std::ceil(std::max(max_reach, bucket) * inv_cell_)) + 2);
  rings_.assign(buckets, static_cast<uint8_t>(cap));
  for (size_t b = 0; b < buckets; ++b)
    if (offsets_[b + 1] > offsets_[b]) rings_[b] = 0;
  for (int pass = 0; pass < 2; ++pass) {
    const int step = pass == 0 ? 1 : -1;
    for (int k = pass == 0 ? 0 : dims_.z() - 1; k >= 0 && k < dims_.z(); k += step)
      for (int j = pass == 0 ? 0 : dims_.y() - 1; j >= 0 && j < dims_.y(); j += step)
        for (int i = pass == 0 ? 0 : dims_.x() - 1; i >= 0 && i < dims_.x(); i += step) {
          uint8_t& r = rings_[bucket_of(i, j, k)];
          for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
              for (int dx = -1; dx <= 1; ++dx) {
                const int ii = i + dx, jj = j + dy, kk = k + dz;
                if (ii < 0 || jj < 0 || kk < 0 || ii >= dims_.x() || jj >= dims_.y() || kk >= dims_.z()) continue;
                r = std::min<uint8_t>(r, static_cast<uint8_t>(std::min(cap, rings_[bucket_of(ii, jj, kk)] + 1)));
              }
        }
  }
}

TriangleIndex::Hit TriangleIndex::closest(const Vec3& x, double max_distance) const {
  Hit best;
  if (triangles_.empty()) return best;
  const Vec3 q = (x - lo_) * inv_cell_;
  const Eigen::Vector3i c = q.array().floor().cast<int>().max(0).min(dims_.array() - 1);
  // How far x lies outside its (clamped) bucket, and the rings needed to cover max_distance.
  const Vec3 centre = lo_ + (c.cast<double>() + Vec3::Constant(0.5)) * cell_;
  const double slack = std::max(0.0, ((x - centre).cwiseAbs().array() - 0.5 * cell_).maxCoeff());
  if (slack > max_distance) return best;
  const int reach = static_cast<int>(std::ceil((max_distance + slack) * inv_cell_));
  const size_t own = static_cast<size_t>(c.x() + dims_.x() * (c.y() + static_cast<long>(dims_.y()) * c.z()));
  if (rings_[own] > reach + 1) return best;  // no occupied bucket within reach
  double best_d2 = max_distance * max_distance;
  std::vector<std::pair<double, size_t>> shell;  // occupied buckets of one ring, by box distance
  for (int r = std::max(0, static_cast<int>(rings_[own]) - 1); r <= reach; ++r) {
    shell.clear();
    for (int dz = -r; dz <= r; ++dz)
      for (int dy = -r; dy <= r; ++dy) {
        const bool face = std::abs(dz) == r || std::abs(dy) == r;
        for (int dx = -r; dx <= r; dx += (face || r == 0) ? 1 : 2 * r) {  // only the shell of the cube
          const int i = c.x() + dx, j = c.y() + dy, k = c.z() + dz;
          if (i < 0 || j < 0 || k < 0 || i >= dims_.x() || j >= dims_.y() || k >= dims_.z()) continue;
          const size_t b = static_cast<size_t>(i + dims_.x() * (j + static_cast<long>(dims_.y()) * k));
          if (offsets_[b] == offsets_[b + 1]) continue;
          const Vec3 box_lo = lo_ + Vec3(i, j, k) * cell_;
          const double d2 = (box_lo - x).cwiseMax(x - box_lo - Vec3::Constant(cell_)).cwiseMax(0.0).squaredNorm();
          if (d2 < best_d2) shell.emplace_back(d2, b);
        }
      }
    // Nearest buckets first: the best point shrinks fast and the rest are skipped by their box.
    std::sort(shell.begin(), shell.end());
    for (const auto& [d2_box, b] : shell) {
      if (d2_box >= best_d2) break;
      for (uint32_t e = offsets_[b]; e < offsets_[b + 1]; ++e) {
        const int tri = static_cast<int>(items_[e]);
        const Eigen::Vector4d& sph = spheres_[static_cast<size_t>(tri)];
        const double gap = (x - sph.head<3>()).norm() - sph[3];
        if (gap > 0 && gap * gap > best_d2) continue;  // the whole triangle is farther than the best
        const Tri& t = triangles_[static_cast<size_t>(tri)];
        Vec3 bc;
        const Vec3 p = closest_point_on_triangle(x, positions_[t[0]], positions_[t[1]], positions_[t[2]], &bc);
        const double d2 = (p - x).squaredNorm();
        // Ties go to the lower triangle index, so the answer does not depend on the search order.
        if (d2 < best_d2 || (best.found && d2 == best_d2 && tri < best.triangle)) {
          best_d2 = d2;
          best.found = true;
          best.point = p;
          best.triangle = tri;
          best.barycentric = bc;
        }
      }
    }
    // Buckets beyond ring r are at least r * cell - slack away.
    if (best.found && std::sqrt(best_d2) <= r * cell_ - slack) break;
  }
  if (best.found) best.distance = std::sqrt(best_d2);
  return best;
}

}  // namespace shellfrac::brittle
