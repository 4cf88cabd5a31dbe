#include "brittle/solid_grid.hpp"
#include "brittle/solid_grid_impl.hpp"

#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <sstream>

#include "brittle/errors.hpp"
#include "brittle/solid_stencil.hpp"
#include "brittle/solid_transfer.hpp"

namespace shellfrac::brittle {

namespace {

bool cpu_has_avx2_fma() {
#if defined(SHELLFRAC_BRITTLE_AVX2)
  __builtin_cpu_init();
  return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
#else
  return false;
#endif
}

const detail::TransferKernels* kernels_for(SolidGrid::TransferIsa isa) {
  switch (isa) {
    case SolidGrid::TransferIsa::Generic: return &detail::transfer_kernels_generic();
    case SolidGrid::TransferIsa::Avx2:
#if defined(SHELLFRAC_BRITTLE_AVX2)
      if (cpu_has_avx2_fma()) return &detail::transfer_kernels_avx2();
#endif
      return nullptr;
    case SolidGrid::TransferIsa::Auto: break;
  }
  const detail::TransferKernels* k = kernels_for(SolidGrid::TransferIsa::Avx2);
  return k ? k : &detail::transfer_kernels_generic();
}

}  // namespace

SolidGrid::SolidGrid(double dx) : dx_(dx), inv_dx_(1.0 / dx), kernels_(kernels_for(TransferIsa::Auto)) {
  if (!(dx > 0)) throw InputError("grid spacing must be > 0");
}

bool SolidGrid::set_transfer_isa(TransferIsa isa) {
  const detail::TransferKernels* k = kernels_for(isa);
  if (!k) return false;
  kernels_ = k;
  return true;
}

const char* SolidGrid::transfer_isa() const { return kernels_->isa; }

template <class Grid, class Fields, class Normals>
Grid SolidGrid::raw_of(Fields& field, Normals& normal) const {
  Grid g;
  g.field[0] = field[0].data();
  g.field[1] = two_fields_ ? field[1].data() : g.field[0];
  g.normal = two_fields_ ? normal.data()->n : nullptr;
  for (int a = 0; a < 3; ++a) g.lo[a] = lo_[a];
  g.stride_y = stride_y_;
  g.stride_z = stride_z_;
  g.dx = dx_;
  g.inv_dx = inv_dx_;
  return g;
}

detail::TransferGrid SolidGrid::raw() { return raw_of<detail::TransferGrid>(field_, normal_); }
detail::ConstTransferGrid SolidGrid::raw() const { return raw_of<detail::ConstTransferGrid>(field_, normal_); }

long SolidGrid::node_index(int i, int j, int k) const {
  const int a = i - lo_.x(), b = j - lo_.y(), c = k - lo_.z();
  if (a < 0 || b < 0 || c < 0 || a >= dims_.x() || b >= dims_.y() || c >= dims_.z()) return -1;
  return a + b * stride_y_ + c * stride_z_;
}

GVec3 SolidGrid::node_position(size_t index) const {
  const long i = static_cast<long>(index) % stride_y_, j = (static_cast<long>(index) / stride_y_) % dims_.y(),
             k = static_cast<long>(index) / stride_z_;
  return GVec3(static_cast<double>(lo_.x() + i), static_cast<double>(lo_.y() + j), static_cast<double>(lo_.z() + k)) * dx_;
}

long SolidGrid::base_index(const GVec3& x) const {
  long idx = 0;
  const long stride[3] = {1, stride_y_, stride_z_};
  for (int a = 0; a < 3; ++a) idx += (static_cast<long>(std::floor(x[a] * inv_dx_ - 0.5)) - lo_[a]) * stride[a];
  return idx;
}

long SolidGrid::nearest_node(const GVec3& x) const {
  return node_index(static_cast<int>(std::lround(x.x() * inv_dx_)), static_cast<int>(std::lround(x.y() * inv_dx_)),
                    static_cast<int>(std::lround(x.z() * inv_dx_)));
}

namespace {

// The particles' bounding box; throws naming the first particle (by index) with a non-finite position.
void particle_box(const GVec3* x, size_t n, GVec3& lo, GVec3& hi) {
  struct Box {
    GVec3 lo = GVec3::Constant(std::numeric_limits<double>::infinity());
    GVec3 hi = GVec3::Constant(-std::numeric_limits<double>::infinity());
    size_t bad = std::numeric_limits<size_t>::max();
  };
  const Box box = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 4096), Box(),
      [&](const tbb::blocked_range<size_t>& r, Box b) {
        for (size_t p = r.begin(); p != r.end(); ++p) {
          if (!x[p].allFinite()) {
            b.bad = std::min(b.bad, p);
            continue;
          }
          b.lo = b.lo.cwiseMin(x[p]);
          b.hi = b.hi.cwiseMax(x[p]);
        }
        return b;
      },
      [](Box a, const Box& b) {
        a.lo = a.lo.cwiseMin(b.lo);
        a.hi = a.hi.cwiseMax(b.hi);
        a.bad = std::min(a.bad, b.bad);
        return a;
      });
  if (box.bad != std::numeric_limits<size_t>::max()) {
    std::ostringstream m;
    m << "particle " << box.bad << " has a non-finite position (the step diverged; lower the time step)";
    throw NumericalError(m.str());
  }
  lo = box.lo;
  hi = box.hi;
}

}  // namespace

void SolidGrid::rebuild(const GVec3* x, size_t n, const std::vector<GVec3>& extra, bool two_fields, size_t memory_limit) {
  GVec3 lo, hi;
  particle_box(x, n, lo, hi);
  for (const GVec3& e : extra) {
    lo = lo.cwiseMin(e);
    hi = hi.cwiseMax(e);
  }
  if (n == 0 && extra.empty()) lo = hi = GVec3::Zero();
  allocate_box(lo, hi, two_fields, memory_limit);
  bin_into_slabs(x, n);
}

void SolidGrid::allocate_box(const GVec3& lo, const GVec3& hi, bool two_fields, size_t memory_limit) {
  // Node ranges in doubles first: material flown far enough apart would overflow an int index, and the
  // size check must see the true extent before anything is cast or allocated.
  Eigen::Vector3d lo_d, extent;
  for (int a = 0; a < 3; ++a) {
    lo_d[a] = std::floor(lo[a] * inv_dx_ - 0.5);
    extent[a] = std::floor(hi[a] * inv_dx_ - 0.5) + 2 - lo_d[a] + 1;
  }
  const double nodes = extent.x() * extent.y() * extent.z();
  const double bytes = nodes * (two_fields ? 2 * sizeof(GridNode) + sizeof(NodeNormal) : sizeof(GridNode));
  constexpr double kIndexLimit = 1e9;  // well inside int for the node indices and their sums
  if (bytes > static_cast<double>(memory_limit) || lo_d.cwiseAbs().maxCoeff() > kIndexLimit ||
      extent.maxCoeff() > kIndexLimit) {
    std::ostringstream m;
    m << "the MPM grid around the solid would need " << extent.transpose() << " nodes (" << bytes / 1e9
      << " GB, limit " << memory_limit / 1e9 << " GB): material has flown far apart or the grid spacing " << dx_
      << " m is too small";
    throw NumericalError(m.str());
  }
  lo_ = lo_d.cast<int>();
  dims_ = extent.cast<int>();
  stride_y_ = dims_.x();
  stride_z_ = static_cast<long>(dims_.x()) * dims_.y();
  two_fields_ = two_fields;
  const size_t count = static_cast<size_t>(nodes);
  field_[0].assign(count, GridNode{0, {0, 0, 0}});
  if (two_fields) {
    field_[1].assign(count, GridNode{0, {0, 0, 0}});
    normal_.assign(count, NodeNormal{{0, 0, 0, 0}});
  } else {
    field_[1].clear();
    normal_.clear();
  }
}

void SolidGrid::bin_into_slabs(const GVec3* x, size_t n) {
  // Slabs four nodes thick along the longest axis; a stable counting sort keeps index order inside one.
  // Ties go to z: particles sampled in z-major order then stay contiguous inside a slab.
  slab_axis_ = 2;
  for (int a = 1; a >= 0; --a)
    if (dims_[a] > dims_[slab_axis_]) slab_axis_ = a;
  const size_t slabs = static_cast<size_t>(dims_[slab_axis_] + 3) / 4;
  std::vector<uint32_t> slab_of(n);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p != r.end(); ++p)
      slab_of[p] = static_cast<uint32_t>((static_cast<int>(std::floor(x[p][slab_axis_] * inv_dx_ - 0.5)) - lo_[slab_axis_]) / 4);
  });
  slab_offsets_.assign(slabs + 1, 0);
  for (size_t p = 0; p < n; ++p) ++slab_offsets_[slab_of[p] + 1];
  for (size_t s = 0; s < slabs; ++s) slab_offsets_[s + 1] += slab_offsets_[s];
  slab_order_.resize(n);
  std::vector<uint32_t> cursor(slab_offsets_.begin(), slab_offsets_.end() - 1);
  for (size_t p = 0; p < n; ++p) slab_order_[cursor[slab_of[p]]++] = static_cast<uint32_t>(p);
}

void SolidGrid::transfer_to_grid(const SolidView& s, double dt) {
  const detail::TransferGrid g = raw();
  const detail::ScatterKernel scatter = kernels_->scatter;
  // The coloured slab order of for_particles_coloured, a slab per kernel call.
  for_slabs_coloured(
      [&](size_t slab) { scatter(g, s, dt, slab_order_.data(), slab_offsets_[slab], slab_offsets_[slab + 1]); });
}

void SolidGrid::add_point_forces(const std::vector<GVec3>& x, const std::vector<GVec3>& force, const std::vector<int>& field, double dt) {
  for (size_t g = 0; g < x.size(); ++g) {
    const Stencil st = make_stencil(x[g], inv_dx_, dx_);
    GridNode* f = field_[two_fields_ && field[g] == 1 ? 1 : 0].data();
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const long idx = node_index(st.base[0] + i, st.base[1] + j, st.base[2] + k);
          if (idx < 0) continue;
          const double w = st.w[0][i] * st.w[1][j] * st.w[2][k] * dt;
          for (int a = 0; a < 3; ++a) f[idx].p[a] += w * force[g][a];
        }
  }
}

void SolidGrid::update_velocities(double dt, const GVec3& g) {
  for (int fi = 0; fi < (two_fields_ ? 2 : 1); ++fi) {
    GridNode* f = field_[fi].data();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, num_nodes(), 4096), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        GridNode& nd = f[i];
        if (nd.m > 0) {
          const double inv = 1.0 / nd.m;
          for (int a = 0; a < 3; ++a) nd.p[a] = nd.p[a] * inv + dt * g[a];
        } else {
          nd.p[0] = nd.p[1] = nd.p[2] = 0.0;
        }
      }
    });
  }
}

FieldContactStats SolidGrid::resolve_field_contact() {
  FieldContactStats stats;
  if (!two_fields_) return stats;
  struct Count {
    size_t both = 0, contact = 0;
  };
  const Count c = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, num_nodes(), 4096), Count(),
      [&](const tbb::blocked_range<size_t>& r, Count acc) {
        for (size_t i = r.begin(); i != r.end(); ++i) {
          GridNode &a = field_[0][i], &b = field_[1][i];
          if (!(a.m > 0) || !(b.m > 0)) continue;
          ++acc.both;
          const GVec3 ni = crack_normal(i);
          const double len = ni.norm();
          if (!(len > 0)) continue;
          // normal_ points from the crack into field 0: field 0's outward normal (towards field 1) is -n,
          // field 1's is +n (thesis: n_{i,0} = n_i, n_{i,1} = -n_i with n taken outward from each field).
          const GVec3 n = ni / len;
          const GVec3 va(a.p[0], a.p[1], a.p[2]), vb(b.p[0], b.p[1], b.p[2]);
          const GVec3 vcm = (a.m * va + b.m * vb) / (a.m + b.m);
          // Eq. 3.7 for field 0 with n_0 = -n: (v_cm - v_0) . n_0 < 0 <=> the fields approach; the same
          // holds for field 1 then (both sides of one test).
          const double gap_rate = (vcm - va).dot(-n);
          if (!(gap_rate < 0)) continue;
          ++acc.contact;
          // Eq. 3.6: v_xi = v~_xi + dt f_ct / m with f_ct = m / dt ((v_cm - v~_xi) . n_xi) n_xi.
          const GVec3 na = va + ((vcm - va).dot(n)) * n;
          const GVec3 nb = vb + ((vcm - vb).dot(n)) * n;
          for (int d = 0; d < 3; ++d) {
            a.p[d] = na[d];
            b.p[d] = nb[d];
          }
        }
        return acc;
      },
      [](Count x, const Count& y) {
        x.both += y.both;
        x.contact += y.contact;
        return x;
      });
  stats.two_field_nodes = c.both;
  stats.contact_nodes = c.contact;
  return stats;
}

void SolidGrid::apply_colliders(const std::vector<mpm::Collider>& colliders, double t) {
  if (colliders.empty()) return;
  std::vector<Eigen::Isometry3d> inverse_pose;
  for (const mpm::Collider& c : colliders) inverse_pose.push_back(c.motion.pose(t).inverse());
  for (int fi = 0; fi < (two_fields_ ? 2 : 1); ++fi) {
    GridNode* f = field_[fi].data();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, num_nodes(), 1024), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t i = r.begin(); i != r.end(); ++i) {
        if (!(f[i].m > 0)) continue;
        const GVec3 x = node_position(i);
        for (size_t c = 0; c < colliders.size(); ++c) {
          const mpm::Collider& col = colliders[c];
          const GVec3 local = inverse_pose[c] * x;
          if (col.shape->signed_distance(local) > 0) continue;
          const GVec3 normal = inverse_pose[c].linear().transpose() * col.shape->normal(local);
          const GVec3 v = mpm::collide_velocity(GVec3(f[i].p[0], f[i].p[1], f[i].p[2]), col.motion.velocity_at(x, t), normal,
                                                col.boundary, col.friction);
          for (int d = 0; d < 3; ++d) f[i].p[d] = v[d];
        }
      }
    });
  }
}

void SolidGrid::transfer_to_particles(const SolidView& s, double dt) const {
  const detail::ConstTransferGrid g = raw();
  const detail::GatherKernel gather = kernels_->gather;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, s.count, 2048),
                    [&](const tbb::blocked_range<size_t>& r) { gather(g, s, dt, r.begin(), r.end()); });
}

}  // namespace shellfrac::brittle
