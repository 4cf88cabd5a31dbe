#include "brittle/crack_sides.hpp"
#include "brittle/solid_grid_impl.hpp"

#include <tbb/parallel_for.h>

#include <cmath>
#include <map>

namespace shellfrac::brittle {

void CrackSides::clear() {
  near_.clear();
  normal_.clear();
  slot_.clear();
  mask_.clear();
}

namespace {

constexpr double kFaceInterior = 1e-6;  // barycentric margin: the foot lies inside a face

// Closest crack points looked up once per node of a material-space grid of the given spacing (far fewer
// nodes than particles near a crack), and each particle uses its nearest node's: on a face the
// particle's side is the sign of its offset along the face normal, which does not depend on where on
// the face the foot lies; off the faces (near a crack front) the direction from the foot.
class NodeHits {
 public:
  NodeHits(const TriangleIndex& index, const std::vector<Vec3>& rest, double spacing, double reach) : spacing_(spacing) {
    Vec3 lo = rest.front(), hi = lo;
    for (const Vec3& x : rest) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
    base_ = (lo / spacing).array().floor().cast<int>();
    dims_ = Eigen::Vector3i((hi / spacing).array().floor().cast<int>()) - base_ + Eigen::Vector3i::Constant(2);
    const size_t nodes = static_cast<size_t>(dims_.x()) * dims_.y() * dims_.z();
    // Only the nodes some particle reads: most of a statue's bounding box is outside it.
    std::vector<uint8_t> used(nodes, 0);
    for (const Vec3& x : rest) used[node_of(x)] = 1;
    hit_.resize(nodes);
    tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes, 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t n = r.begin(); n != r.end(); ++n) {
        if (!used[n]) continue;
        const long i = static_cast<long>(n) % dims_.x(), j = (static_cast<long>(n) / dims_.x()) % dims_.y(),
                   k = static_cast<long>(n) / (static_cast<long>(dims_.x()) * dims_.y());
        const Vec3 node(static_cast<double>(base_.x() + i), static_cast<double>(base_.y() + j),
                        static_cast<double>(base_.z() + k));
        hit_[n] = index.closest(node * spacing, reach);
      }
    });
  }
  const TriangleIndex::Hit& at(const Vec3& x) const { return hit_[node_of(x)]; }

 private:
  size_t node_of(const Vec3& x) const {
    const Eigen::Vector3i c = Eigen::Vector3i((x / spacing_).array().round().cast<int>()) - base_;
    return static_cast<size_t>(c.x() + dims_.x() * (c.y() + static_cast<long>(dims_.y()) * c.z()));
  }
  double spacing_;
  Eigen::Vector3i base_, dims_;
  std::vector<TriangleIndex::Hit> hit_;
};

// The boundary edges and vertices of a crack sheet: its fronts (and rims), where the side of a point is
// the direction from its foot rather than a face normal.
class SheetFronts {
 public:
  explicit SheetFronts(const TriMesh& crack) : crack_(crack), boundary_vertex_(crack.positions.size(), 0) {
    for (const Tri& t : crack.triangles)
      for (int k = 0; k < 3; ++k) ++edge_uses_[std::minmax(t[k], t[(k + 1) % 3])];
    for (const auto& [e, uses] : edge_uses_)
      if (uses == 1) boundary_vertex_[static_cast<size_t>(e.first)] = boundary_vertex_[static_cast<size_t>(e.second)] = 1;
  }
  // Whether a foot lies on a boundary edge or vertex.
  bool contains(const TriangleIndex::Hit& h) const {
    const Tri& t = crack_.triangles[static_cast<size_t>(h.triangle)];
    int zeros = 0, zero = -1;
    for (int k = 0; k < 3; ++k)
      if (h.barycentric[k] <= kFaceInterior) ++zeros, zero = k;
    if (zeros == 0) return false;
    if (zeros == 1) {  // on the edge opposite corner `zero`
      const auto it = edge_uses_.find(std::minmax(t[(zero + 1) % 3], t[(zero + 2) % 3]));
      return it != edge_uses_.end() && it->second == 1;
    }
    for (int k = 0; k < 3; ++k)  // at a corner
      if (h.barycentric[k] > kFaceInterior) return boundary_vertex_[static_cast<size_t>(t[k])] != 0;
    return false;
  }

 private:
  const TriMesh& crack_;
  std::map<std::pair<int, int>, int> edge_uses_;
  std::vector<char> boundary_vertex_;
};

}  // namespace

void CrackSides::set_crack(const TriMesh& crack, const std::vector<Vec3>& rest, double radius, double spacing) {
  clear();
  if (crack.triangles.empty() || rest.empty()) return;
  const TriangleIndex index(crack.positions, crack.triangles, 0.25 * radius, radius + spacing);
  const NodeHits hits(index, rest, spacing, radius + spacing);
  const SheetFronts fronts(crack);
  const size_t n = rest.size();
  slot_.assign(n, -1);
  mask_.assign(n, 0);
  for (size_t p = 0; p < n; ++p) {
    const TriangleIndex::Hit& h = hits.at(rest[p]);
    if (!h.found) continue;
    const Vec3 offset = rest[p] - h.point;
    const Vec3& face = index.triangle_normal(h.triangle);
    Vec3 dir;
    double distance;
    if (!fronts.contains(h) && face.squaredNorm() > 0) {
      // On a face or an inner edge of the sheet (a ridge between nearly coplanar faces): the side is
      // the sign of the offset along the face normal.
      distance = offset.dot(face);
      dir = distance >= 0 ? face : Vec3(-face);
      distance = std::abs(distance);
    } else {
      distance = offset.norm();
      dir = distance > 1e-9 * radius ? Vec3(offset / distance) : face;
    }
    if (distance >= radius) continue;
    slot_[p] = static_cast<int32_t>(near_.size());
    near_.push_back(static_cast<uint32_t>(p));
    normal_.push_back(dir);
  }
  if (near_.empty()) clear();
}

void CrackSides::classify(const SolidGrid& grid, const Vec3* x) {
  if (!active()) return;
  best_w_.assign(grid.num_nodes(), -1.0);
  best_slot_.assign(grid.num_nodes(), -1);
  const double inv_dx = 1.0 / grid.dx();
  const Eigen::Vector3i lo = grid.lower(), dims = grid.dims();
  const long sy = dims.x(), sz = static_cast<long>(dims.x()) * dims.y();
  auto weights = [&](const Vec3& xp, double w[3][3], long& base) {
    base = 0;
    const long stride[3] = {1, sy, sz};
    for (int a = 0; a < 3; ++a) {
      const double q = xp[a] * inv_dx;
      const int b = static_cast<int>(std::floor(q - 0.5));
      const double f = q - b;
      w[a][0] = 0.5 * (1.5 - f) * (1.5 - f);
      w[a][1] = 0.75 - (f - 1.0) * (f - 1.0);
      w[a][2] = 0.5 * (f - 0.5) * (f - 0.5);
      base += (b - lo[a]) * stride[a];
    }
  };
  // 1. Reference particle of every node: the near particle with the largest weight there (the first one
  //    in scatter order on ties), a coloured scatter so that it is the same for any thread count.
  grid.for_particles_coloured([&](uint32_t p) {
    const int32_t s = slot_[p];
    if (s < 0) return;
    double w[3][3];
    long base;
    weights(x[p], w, base);
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const size_t idx = static_cast<size_t>(base + i + j * sy + k * sz);
          const double wt = w[0][i] * w[1][j] * w[2][k];
          if (wt > best_w_[idx]) {
            best_w_[idx] = wt;
            best_slot_[idx] = s;
          }
        }
  });
  // 2. The reference normal of every node, one array per axis (zero where no near particle reaches: the
  //    test below then fails, as it should), so that step 3 reads each stencil row contiguously instead of
  //    a normal per node through its slot.
  const size_t nodes = grid.num_nodes();
  for (auto& a : ref_normal_) a.resize(nodes);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, nodes, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const int32_t ref = best_slot_[i];
      const Vec3 n = ref >= 0 ? normal_[static_cast<size_t>(ref)] : Vec3::Zero();
      for (int a = 0; a < 3; ++a) ref_normal_[a][i] = n[a];
    }
  });
  // 3. Field bits: clearly opposite to the node's reference particle -> field 1.
  const double *rx = ref_normal_[0].data(), *ry = ref_normal_[1].data(), *rz = ref_normal_[2].data();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, near_.size(), 512), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t s = r.begin(); s != r.end(); ++s) {
      const uint32_t p = near_[s];
      long base = 0;
      const long stride[3] = {1, sy, sz};
      for (int a = 0; a < 3; ++a) base += (static_cast<long>(std::floor(x[p][a] * inv_dx - 0.5)) - lo[a]) * stride[a];
      const double nx = normal_[s].x(), ny = normal_[s].y(), nz = normal_[s].z();
      FieldMask m = 0;
      for (int k = 0; k < 3; ++k)
        for (int j = 0; j < 3; ++j) {
          const long row = base + j * sy + k * sz;
          for (int i = 0; i < 3; ++i) {
            const double d = nx * rx[row + i] + ny * ry[row + i] + nz * rz[row + i];
            m |= FieldMask{d < kOppositeCosine} << (i + 3 * j + 9 * k);
          }
        }
      mask_[p] = m;
    }
  });
  (void)dims;
}

int CrackSides::field_at(size_t index, const Vec3& n) const {
  if (!active() || index >= best_slot_.size()) return 0;
  const int32_t ref = best_slot_[index];
  return ref >= 0 && n.dot(normal_[static_cast<size_t>(ref)]) < kOppositeCosine ? 1 : 0;
}

}  // namespace shellfrac::brittle
