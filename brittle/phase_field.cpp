#include "brittle/phase_field.hpp"

#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <cmath>
#include <sstream>

#include "brittle/cholmod_solver.hpp"
#include "brittle/errors.hpp"
#include "brittle/solid_grid_impl.hpp"
#include "brittle/solid_stencil.hpp"
#include "brittle/solid_transfer.hpp"

namespace shellfrac::brittle {

const char* to_string(PhaseFieldSolver s) { return s == PhaseFieldSolver::Cholmod ? "cholmod" : "cg"; }
const char* to_string(PhaseFieldGradient g) { return g == PhaseFieldGradient::Mls ? "mls" : "spline"; }

std::string PhaseFieldOptions::validate() const {
  std::ostringstream m;
  if (!(length_scale >= 0) || !std::isfinite(length_scale)) m << "length_scale must be >= 0 (0 = half the grid spacing), got " << length_scale;
  else if (!(mobility > 0) || !std::isfinite(mobility)) m << "mobility M_c must be > 0 [1/s], got " << mobility;
  else if (!(residual > 0 && residual < 1)) m << "residual stiffness r must lie in (0, 1), got " << residual;
  else if (interval < 1) m << "interval must be >= 1 step";
  else if (!(tolerance > 0 && tolerance < 1)) m << "tolerance must lie in (0, 1), got " << tolerance;
  else if (max_iterations < 1) m << "max_iterations must be >= 1";
  else if (!(broken_below >= 0 && broken_below < 1)) m << "broken_below must lie in [0, 1), got " << broken_below;
  return m.str();
}

namespace {

// M_p^{-1} of the quadratic kernel times dx^2: grad Theta_i(x_p) = (4 / dx^2) w_ip (x_i - x_p).
constexpr double kGradient = 4.0;
// The code of the stencil centre (offset 0, 0, 0) among the 5 x 5 x 5 neighbour offsets.
constexpr int kCentre = 62;

inline int offset_code(int dx, int dy, int dz) { return (dx + 2) + 5 * (dy + 2) + 25 * (dz + 2); }

// The per-axis factors of grad Theta_i(x_p): grad Theta_ijk = (g_i w_j w_k, w_i g_j w_k, w_i w_j g_k)
// with g either the derivative of the quadratic B-spline (Eq. 2.10 differentiated) or the MLS factor
// of CD-MPM sec. 4.2.2, (4 / dx^2) w (x_i - x_p), which is exact for linear fields only. Both separate
// by axis, which the operator below uses to sum one axis at a time.
inline void axis_gradients(const Stencil& st, PhaseFieldGradient mode, double inv_dx, double g[3][3]) {
  const double mls = kGradient * inv_dx * inv_dx;
  for (int a = 0; a < 3; ++a) {
    if (mode == PhaseFieldGradient::Mls) {
      for (int i = 0; i < 3; ++i) g[a][i] = mls * st.w[a][i] * st.d[a][i];
    } else {
      const double f = -st.d[a][0] * inv_dx;  // q - base in [0.5, 1.5)
      g[a][0] = -(1.5 - f) * inv_dx;
      g[a][1] = -2.0 * (f - 1.0) * inv_dx;
      g[a][2] = (f - 0.5) * inv_dx;
    }
  }
}

// fn(local i, j, k, node index, weight w_ip, gradient grad Theta_i(x_p)) over the 27 nodes of a
// particle's stencil, for the penalty points and CHOLMOD's assembly (the operator, the assembly of the
// lumped terms and the update of c run the vector kernels of brittle/phase_field_kernels_impl.hpp).
template <class Fn>
inline void for_stencil(const SolidGrid& grid, const Stencil& st, PhaseFieldGradient mode, double inv_dx, Fn&& fn) {
  const long base = grid.node_index(st.base[0], st.base[1], st.base[2]);
  const long sy = grid.stride(1), sz = grid.stride(2);
  double g[3][3];
  axis_gradients(st, mode, inv_dx, g);
  for (int k = 0; k < 3; ++k)
    for (int j = 0; j < 3; ++j)
      for (int i = 0; i < 3; ++i) {
        const double w = st.w[0][i] * st.w[1][j] * st.w[2][k];
        const GVec3 grad(g[0][i] * st.w[1][j] * st.w[2][k], st.w[0][i] * g[1][j] * st.w[2][k], st.w[0][i] * st.w[1][j] * g[2][k]);
        fn(i, j, k, static_cast<size_t>(base + i + j * sy + k * sz), w, grad);
      }
}

// The grid box as the per-particle kernels see it (brittle/solid_transfer.hpp); they need no node arrays.
detail::ConstTransferGrid kernel_box(const SolidGrid& grid) {
  detail::ConstTransferGrid g;
  for (int a = 0; a < 3; ++a) g.lo[a] = grid.lower()[a];
  g.stride_y = grid.stride(1);
  g.stride_z = grid.stride(2);
  g.dx = grid.dx();
  g.inv_dx = 1.0 / grid.dx();
  return g;
}

// The particles' positions as the kernels read them (3 doubles each).
const double* positions(const PhaseFieldParticles& p) { return p.count > 0 ? p.x->data() : nullptr; }

// Runs a kernel over every slab's particles, slab colour by colour (the grid's scatter order).
template <class Kernel, class Args>
void over_slabs(const SolidGrid& grid, Kernel kernel, const Args& args) {
  const detail::ConstTransferGrid g = kernel_box(grid);
  grid.for_slabs_coloured([&](size_t slab) {
    kernel(g, args, grid.slab_begin(slab), 0, static_cast<size_t>(grid.slab_end(slab) - grid.slab_begin(slab)));
  });
}

// Dot product over the free nodes, summed in fixed blocks: the same bits for any thread count.
double masked_dot(const std::vector<double>& a, const std::vector<double>& b, const std::vector<uint8_t>& mask) {
  return tbb::parallel_deterministic_reduce(
      tbb::blocked_range<size_t>(0, a.size(), 4096), 0.0,
      [&](const tbb::blocked_range<size_t>& r, double s) {
        for (size_t i = r.begin(); i != r.end(); ++i)
          if (mask[i]) s += a[i] * b[i];
        return s;
      },
      [](double x, double y) { return x + y; });
}

template <class Fn>
void for_nodes(size_t n, Fn&& fn) {
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 8192), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t i = r.begin(); i != r.end(); ++i) fn(i);
  });
}

}  // namespace

PhaseFieldSystem::PhaseFieldSystem(const PhaseFieldOptions& options, double fracture_energy, double dx)
    : options_(options), G_(fracture_energy), dx_(dx), l0_(options.length_scale > 0 ? options.length_scale : 0.5 * dx) {
  const std::string bad = options_.validate();
  if (!bad.empty()) throw InputError("phase field: " + bad);
  if (!(G_ > 0) || !std::isfinite(G_)) throw InputError("phase field: the fracture energy G must be > 0 [J/m^2]");
  if (!(dx_ > 0)) throw InputError("phase field: grid spacing must be > 0");
}

PhaseFieldSystem::~PhaseFieldSystem() = default;

size_t PhaseFieldSystem::analyses() const { return cholmod_ ? cholmod_->analyses() : 0; }

void PhaseFieldSystem::assemble(const SolidGrid& grid, const PhaseFieldParticles& p, double dt) {
  const size_t n = grid.num_nodes();
  for (std::vector<double>* v : {&c_old_, &diag_, &rhs_}) v->resize(n);  // set from lumped_ below
  precond_.assign(n, 0.0);
  free_.assign(n, 0);
  const double Mc = options_.mobility, r = options_.residual;
  const double inv_dt = dt > 0 ? 1.0 / dt : 0.0;
  lumped_.assign(n, LumpedNode{0, 0, 0, 0});
  detail::PhaseFieldAssemblyArgs args;
  args.lumped = reinterpret_cast<double*>(lumped_.data());
  args.precond = precond_.data();  // H_ii here
  args.position = positions(p);
  args.volume = p.volume;
  args.history = p.history;
  args.c = p.c;
  args.history_factor = 4.0 * l0_ * Mc * (1.0 - r) / G_;
  args.mass_constant = Mc + inv_dt;
  args.source_constant = Mc;
  args.inv_dt = inv_dt;
  args.stiffness = 4.0 * l0_ * l0_ * Mc;  // 4 l0^2 M_c (Eq. 6)
  args.mls_gradient = options_.gradient == PhaseFieldGradient::Mls;
  over_slabs(grid, grid.kernels().phase_field_assembly, args);
  for_nodes(n, [&](size_t i) {
    const LumpedNode& l = lumped_[i];
    diag_[i] = l.mass;
    rhs_[i] = l.source;
    if (l.weight > 0) {
      c_old_[i] = l.weighted_c / l.weight;
      free_[i] = 1;
    } else {
      c_old_[i] = 1.0;
    }
  });
  c_.assign(n, 1.0);
  for_nodes(n, [&](size_t i) {
    if (free_[i]) {
      c_[i] = c_old_[i];
      precond_[i] += diag_[i];  // M_ii + H_ii, inverted once the penalty is in
    } else {
      precond_[i] = 0.0;
      rhs_[i] = 0.0;
    }
  });
}

void PhaseFieldSystem::add_penalty(const SolidGrid& grid, const std::vector<GVec3>& points) {
  penalty_points_ = points;
  penalty_ = 0;
  if (!points.empty()) {
    // 1e8 times the largest diagonal entry: the field at a broken point is 0 to ~1e-8 of its range, and
    // the system stays well enough conditioned for CG.
    double largest = 0;
    for (size_t i = 0; i < precond_.size(); ++i) largest = std::max(largest, precond_[i]);
    penalty_ = 1e8 * largest;
  }
  const double inv_dx = 1.0 / dx_;
  const PhaseFieldGradient gradient = options_.gradient;
  for (const GVec3& x : points) {
    const Stencil st = make_stencil(x, inv_dx, dx_);
    for (int a = 0; a < 3; ++a)
      if (grid.node_index(st.base[0] + (a == 0) * 2, st.base[1] + (a == 1) * 2, st.base[2] + (a == 2) * 2) < 0 ||
          grid.node_index(st.base[0], st.base[1], st.base[2]) < 0)
        throw InputError("phase field: a broken point lies outside the grid");
    for_stencil(grid, st, gradient, inv_dx, [&](int, int, int, size_t i, double w, const GVec3&) {
      if (w > 0 && !free_[i]) throw InputError("phase field: a broken point lies outside the solid");
      precond_[i] += penalty_ * w * w;
    });
  }
  for_nodes(precond_.size(), [&](size_t i) { precond_[i] = free_[i] ? 1.0 / precond_[i] : 0.0; });
}

void PhaseFieldSystem::apply(const SolidGrid& grid, const PhaseFieldParticles& p, const std::vector<double>& x,
                             std::vector<double>& y) const {
  const size_t n = grid.num_nodes();
  y.assign(n, 0.0);
  const double laplace = 4.0 * l0_ * l0_ * options_.mobility;
  const PhaseFieldGradient gradient = options_.gradient;
  const double inv_dx = 1.0 / dx_;
  // grad c_h(x_p), then its share back to each node (the kernel). x is 0 off the free nodes, and y is
  // zeroed there below, so neither pass needs the mask.
  detail::PhaseFieldOperatorArgs args;
  args.x = x.data();
  args.y = y.data();
  args.position = positions(p);
  args.volume = p.volume;
  args.scale = laplace;
  args.mls_gradient = gradient == PhaseFieldGradient::Mls;
  over_slabs(grid, grid.kernels().phase_field_operator, args);
  for (const GVec3& xb : penalty_points_) {  // few points: serial, in order
    const Stencil st = make_stencil(xb, inv_dx, dx_);
    double value = 0;
    for_stencil(grid, st, gradient, inv_dx, [&](int, int, int, size_t i, double w, const GVec3&) { value += w * x[i]; });
    for_stencil(grid, st, gradient, inv_dx, [&](int, int, int, size_t i, double w, const GVec3&) { y[i] += penalty_ * w * value; });
  }
  for_nodes(n, [&](size_t i) { y[i] = free_[i] ? y[i] + diag_[i] * x[i] : 0.0; });
}

void PhaseFieldSystem::solve_cg(const SolidGrid& grid, const PhaseFieldParticles& p, PhaseFieldStats& stats) {
  const size_t n = grid.num_nodes();
  std::vector<double> x(n), r(n), z(n), d(n), Ad;
  for_nodes(n, [&](size_t i) { x[i] = free_[i] ? c_[i] : 0.0; });
  apply(grid, p, x, Ad);
  for_nodes(n, [&](size_t i) { r[i] = free_[i] ? rhs_[i] - Ad[i] : 0.0; });
  const double bnorm = std::sqrt(masked_dot(rhs_, rhs_, free_));
  const double goal = options_.tolerance * bnorm;
  double rnorm = std::sqrt(masked_dot(r, r, free_));
  for_nodes(n, [&](size_t i) { z[i] = precond_[i] * r[i]; d[i] = z[i]; });
  double rz = masked_dot(r, z, free_);
  size_t it = 0;
  while (rnorm > goal && it < options_.max_iterations) {
    apply(grid, p, d, Ad);
    const double dAd = masked_dot(d, Ad, free_);
    if (!(dAd > 0)) break;  // round-off floor reached (or a breakdown, caught below)
    const double alpha = rz / dAd;
    for_nodes(n, [&](size_t i) {
      x[i] += alpha * d[i];
      r[i] -= alpha * Ad[i];
      z[i] = precond_[i] * r[i];
    });
    ++it;
    rnorm = std::sqrt(masked_dot(r, r, free_));
    const double rz_next = masked_dot(r, z, free_);
    const double beta = rz_next / rz;
    rz = rz_next;
    for_nodes(n, [&](size_t i) { d[i] = z[i] + beta * d[i]; });
  }
  if (!std::isfinite(rnorm)) throw NumericalError("phase field: the conjugate gradient solve diverged (non-finite residual)");
  for_nodes(n, [&](size_t i) {
    if (free_[i]) c_[i] = x[i];
  });
  stats.iterations = it;
  stats.residual = bnorm > 0 ? rnorm / bnorm : 0.0;
  stats.converged = rnorm <= goal;
}

void PhaseFieldSystem::update_pattern(const SolidGrid& grid, PhaseFieldStats& stats) {
  const size_t n = grid.num_nodes();
  const Eigen::Vector3i lo = grid.lower(), dims = grid.dims();
  std::vector<long> nodes;
  for (size_t i = 0; i < n; ++i)
    if (free_[i]) nodes.push_back(static_cast<long>(i));
  std::vector<Eigen::Vector3i> coords(nodes.size());
  for (size_t k = 0; k < nodes.size(); ++k) {
    const long i = nodes[k];
    coords[k] = lo + Eigen::Vector3i(static_cast<int>(i % dims.x()), static_cast<int>((i / dims.x()) % dims.y()),
                                     static_cast<int>(i / (static_cast<long>(dims.x()) * dims.y())));
  }
  unknown_of_.assign(n, -1);
  for (size_t k = 0; k < nodes.size(); ++k) unknown_of_[nodes[k]] = static_cast<int>(k);
  unknown_node_ = nodes;
  // The pattern is every free neighbour within two nodes (all pairs that can share a particle), so it
  // depends on the active set alone, not on where the particles sit inside their cells.
  if (cholmod_ && coords == unknown_coord_) return;
  unknown_coord_ = std::move(coords);
  const size_t m = nodes.size();
  entry_of_.assign(125 * m, -1);
  column_start_.assign(m + 1, 0);
  row_index_.clear();
  std::vector<std::pair<int, int>> rows;  // (row, offset code)
  for (size_t j = 0; j < m; ++j) {
    rows.clear();
    const Eigen::Vector3i& cj = unknown_coord_[j];
    for (int dz = -2; dz <= 2; ++dz)
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) {
          const long nb = grid.node_index(cj.x() + dx, cj.y() + dy, cj.z() + dz);
          if (nb < 0) continue;
          const int k = unknown_of_[nb];
          if (k >= 0 && k <= static_cast<int>(j)) rows.emplace_back(k, offset_code(dx, dy, dz));
        }
    std::sort(rows.begin(), rows.end());
    for (const auto& [row, code] : rows) {
      entry_of_[125 * j + code] = static_cast<int>(row_index_.size());
      row_index_.push_back(row);
    }
    column_start_[j + 1] = static_cast<int>(row_index_.size());
  }
  if (!cholmod_) cholmod_ = std::make_unique<CholmodSolver>();
  cholmod_->analyse(m, column_start_, row_index_);
  stats.analysed = true;
}

void PhaseFieldSystem::solve_cholmod(const SolidGrid& grid, const PhaseFieldParticles& p, PhaseFieldStats& stats) {
  update_pattern(grid, stats);
  const size_t m = unknown_node_.size();
  if (m == 0) return;
  double* values = cholmod_->values();
  std::fill(values, values + row_index_.size(), 0.0);
  for (size_t j = 0; j < m; ++j) values[entry_of_[125 * j + kCentre]] = diag_[unknown_node_[j]];
  const double laplace = 4.0 * l0_ * l0_ * options_.mobility;
  const PhaseFieldGradient gradient = options_.gradient;
  const double inv_dx = 1.0 / dx_;
  grid.for_particles_coloured([&](size_t q) {
    const Stencil st = make_stencil(p.x[q], inv_dx, dx_);
    int local[27][3], unknown[27];
    GVec3 d[27];
    int count = 0;
    for_stencil(grid, st, gradient, inv_dx, [&](int i, int j, int k, size_t node, double wi, const GVec3& grad) {
      const int u = unknown_of_[node];
      if (u < 0 || wi == 0.0) return;
      local[count][0] = i, local[count][1] = j, local[count][2] = k;
      unknown[count] = u, d[count] = grad;
      ++count;
    });
    const double scale = p.volume[q] * laplace;
    // H_ab = V 4 l0^2 M_c grad Theta_a . grad Theta_b, upper entries into column b.
    for (int b = 0; b < count; ++b)
      for (int a = 0; a < count; ++a) {
        if (unknown[a] > unknown[b]) continue;
        const int code = offset_code(local[a][0] - local[b][0], local[a][1] - local[b][1], local[a][2] - local[b][2]);
        values[entry_of_[125 * unknown[b] + code]] += scale * d[a].dot(d[b]);
      }
  });
  for (const GVec3& xb : penalty_points_) {
    const Stencil st = make_stencil(xb, inv_dx, dx_);
    for_stencil(grid, st, gradient, inv_dx, [&](int ia, int ja, int ka, size_t na, double wa, const GVec3&) {
      for_stencil(grid, st, gradient, inv_dx, [&](int ib, int jb, int kb, size_t nb, double wb, const GVec3&) {
        const int ua = unknown_of_[na], ub = unknown_of_[nb];
        if (ua < 0 || ub < 0 || ua > ub || wa * wb == 0.0) return;
        values[entry_of_[125 * ub + offset_code(ia - ib, ja - jb, ka - kb)]] += penalty_ * wa * wb;
      });
    });
  }
  cholmod_->factorize();
  std::vector<double> b(m), x(m);
  for (size_t j = 0; j < m; ++j) b[j] = rhs_[unknown_node_[j]];
  cholmod_->solve(b.data(), x.data());
  for (size_t j = 0; j < m; ++j) c_[unknown_node_[j]] = x[j];
  // The residual of the result, with the matrix-free operator (an independent check of the assembly).
  std::vector<double> Ac;
  std::vector<double> xd(grid.num_nodes(), 0.0);
  for (size_t j = 0; j < m; ++j) xd[unknown_node_[j]] = x[j];
  apply(grid, p, xd, Ac);
  for_nodes(Ac.size(), [&](size_t i) { Ac[i] = free_[i] ? rhs_[i] - Ac[i] : 0.0; });
  const double bnorm = std::sqrt(masked_dot(rhs_, rhs_, free_));
  stats.residual = bnorm > 0 ? std::sqrt(masked_dot(Ac, Ac, free_)) / bnorm : 0.0;
  if (!std::isfinite(stats.residual)) throw NumericalError("phase field: the Cholesky solve gave a non-finite result");
}

PhaseFieldStats PhaseFieldSystem::solve(const SolidGrid& grid, const PhaseFieldParticles& p, double dt,
                                        const std::vector<GVec3>& broken_points) {
  PhaseFieldStats stats;
  assemble(grid, p, dt);
  add_penalty(grid, broken_points);
  stats.unknowns = static_cast<size_t>(std::count(free_.begin(), free_.end(), uint8_t{1}));
  if (options_.solver == PhaseFieldSolver::Cholmod) solve_cholmod(grid, p, stats);
  else solve_cg(grid, p, stats);
  // Back to the particles without healing (sec. 4.2.1).
  detail::PhaseFieldGatherArgs back;
  back.c_new = c_.data();
  back.c_old = c_old_.data();
  back.position = positions(p);
  back.c = p.c;
  const detail::ConstTransferGrid g = kernel_box(grid);
  const detail::PhaseFieldGatherKernel gather = grid.kernels().phase_field_gather;
  tbb::parallel_for(tbb::blocked_range<size_t>(0, p.count, 4096),
                    [&](const tbb::blocked_range<size_t>& r) { gather(g, back, r.begin(), r.end()); });
  return stats;
}

std::vector<PhaseFieldSystem::Entry> PhaseFieldSystem::assembled_upper() const {
  std::vector<Entry> out;
  if (!cholmod_) return out;
  const double* v = cholmod_->values();
  for (size_t j = 0; j + 1 < column_start_.size(); ++j)
    for (int e = column_start_[j]; e < column_start_[j + 1]; ++e) out.push_back({row_index_[e], static_cast<int>(j), v[e]});
  return out;
}

}  // namespace shellfrac::brittle
