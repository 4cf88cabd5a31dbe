// The crack side of ShellPatch: switching points whose NURBS support a crack cuts to MLS bases
// (thesis sec. 4.6) through the fallback chain of shell/basis_chain.hpp, and evaluating the cut surface
// for render meshes (sec. 4.9.3).
#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

#include "shell/shell_patch.hpp"

namespace shellfrac::shell {

namespace {

// Crack corners get their path portals this far from the vertex (a fraction of a cell): paths around a
// tip pass that close to it.
constexpr double kPortalOffset = 1e-7;

crack2d::Box box_around(const Vec2& c, double hu, double hv) {
  return {Vec2(c.x() - hu, c.y() - hv), Vec2(c.x() + hu, c.y() + hv)};
}

// A point's new basis after a crack update: unchanged, NURBS, or the chain's result in `support`.
struct PointResult {
  enum Kind : unsigned char { Unchanged, Nurbs, Chain } kind = Unchanged;
  PointFit fit;
  std::vector<int> index;
  std::vector<double> basis;
  Vec3 rigid_offset = Vec3::Zero();
};

// Stores the examined points' new bases, serially in point order (in-plane points, then shear particles),
// so that new slots are numbered the same way every run; counts them and names the first failure and
// the first sliver in `report`.
template <class Slots>
void merge_point_results(std::vector<PointResult>& results, size_t np, std::vector<int32_t>& point_slot,
                         std::vector<int32_t>& shear_slot, Slots& slots, CrackUpdate& report) {
  for (size_t i = 0; i < results.size(); ++i) {
    PointResult& res = results[i];
    if (res.kind == PointResult::Unchanged) continue;
    ++report.examined;
    const bool is_shear = i >= np;
    const size_t id = is_shear ? i - np : i;
    int32_t& slot = is_shear ? shear_slot[id] : point_slot[id];
    if (res.kind == PointResult::Nurbs) continue;  // the crack passes by without cutting its support
    const std::string who = (is_shear ? "shear particle " : "quadrature point ") + std::to_string(id);
    if (res.fit.chain_failed && report.first_failure.empty()) report.first_failure = who + ": " + res.fit.reason;
    if (res.fit.level >= BasisLevel::Rigid && report.first_sliver.empty())
      report.first_sliver = who + " at (" + std::to_string(res.fit.at.x()) + ", " + std::to_string(res.fit.at.y()) +
                            "): " + basis_level_name(res.fit.level);
    if (slot < 0) {
      slot = static_cast<int32_t>(slots.size());
      slots.emplace_back();
    }
    auto& m = slots[static_cast<size_t>(slot)];
    m.index = std::move(res.index);
    m.basis = std::move(res.basis);
    m.reach = res.fit.reach;
    m.level = res.fit.level;
    m.order = res.fit.order;
    m.rigid_offset = res.rigid_offset;
    m.nudged = res.fit.nudged;
    m.chain_failed = res.fit.chain_failed;
  }
}

}  // namespace

bool ShellPatch::nurbs_support_cut(const Vec2& xi, size_t cell, const crack2d::CrackIndex& index) const {
  const int* sup = support(cell);
  for (int s = 0; s < quad_.support_size; ++s)
    if (index.crosses(xi, quad_.control_grid.point(sup[s]))) return true;
  return false;
}

PointFit ShellPatch::fit_chain(const Vec2& xi, BasisChainWork& work) const {
  return fit_point_basis(xi, quad_.control_grid, *cut_.crack, cut_.portals, cut_.chain_settings, work);
}

void ShellPatch::fill_support(const PointFit& fit, const MlsBasis& b, MlsSupport& out) const {
  const size_t n = b.index.size();
  out.index.assign(b.index.begin(), b.index.end());
  out.basis.assign(n * kBasisStride, 0.0);
  for (size_t k = 0; k < n; ++k) {
    double* d = &out.basis[k * kBasisStride];
    d[0] = b.R[k];
    d[1] = b.R1[k];
    d[2] = b.R2[k];
    // A linear basis reproduces no curvature: its second derivatives are left at 0 (membrane only).
    if (fit.order == 2) {
      d[3] = b.R11[k];
      d[4] = b.R12[k];
      d[5] = b.R22[k];
    }
  }
  out.reach = fit.reach;
  out.level = fit.level;
  out.order = fit.order;
  out.rigid_offset.setZero();
  if (fit.level == BasisLevel::Rigid) {
    // Rigid translation: x(xi) = X(xi) + sum R_k (x_k - X_k), with the reference X of the patch.
    Vec3 mean_rest = Vec3::Zero();
    for (size_t k = 0; k < n; ++k) mean_rest += b.R[k] * reference_.control_points()[static_cast<size_t>(b.index[k])];
    out.rigid_offset = reference_.point(fit.at.x(), fit.at.y()) - mean_rest;
  }
}

Vec3 ShellPatch::support_position(const MlsSupport& m) const {
  Vec3 p = m.rigid_offset;
  for (size_t k = 0; k < m.index.size(); ++k) p += m.basis[k * kBasisStride] * x[static_cast<size_t>(m.index[k])];
  return p;
}

BasisLevel ShellPatch::point_level(size_t q) const {
  const int32_t s = cut_.point_slot[q];
  return s < 0 ? BasisLevel::Nurbs : cut_.slots[static_cast<size_t>(s)].level;
}

BasisLevel ShellPatch::shear_level(size_t c) const {
  const int32_t s = cut_.shear_slot[c];
  return s < 0 ? BasisLevel::Nurbs : cut_.slots[static_cast<size_t>(s)].level;
}

CrackUpdate ShellPatch::update_crack(const crack2d::CrackIndex& index, size_t first_new_edge,
                                     const MlsSettings& settings) {
  BasisChainSettings chain = cut_.chain_settings;
  chain.mls = settings;
  return update_crack(index, first_new_edge, chain);
}

CrackUpdate ShellPatch::update_crack(const crack2d::CrackIndex& index, size_t first_new_edge,
                                     const BasisChainSettings& chain) {
  cut_.crack = &index;
  cut_.chain_settings = chain;
  const double lu = quad_.control_grid.cell_u, lv = quad_.control_grid.cell_v;
  if (cut_.portals.built_for_segments() != index.num_segments() || index.num_segments() == 0)
    cut_.portals.build(index, kPortalOffset * std::min(lu, lv));
  CrackUpdate report;
  // Parameter points: in-plane points first, then shear particles (cell centres).
  const size_t np = quad_.param.size(), total = np + quad_.num_cells;
  std::vector<PointResult> results(total);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, total, 64), [&](const tbb::blocked_range<size_t>& r) {
    BasisChainWork work;
    MlsSupport support_out;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const bool is_shear = i >= np;
      const size_t id = is_shear ? i - np : i;
      const Vec2& xi = is_shear ? quad_.cell_center[id] : quad_.param[id];
      const int32_t slot = is_shear ? cut_.shear_slot[id] : cut_.point_slot[id];
      // Only points whose support the new segments touch are re-examined (thesis sec. 4.6); a slot's reach
      // covers every crack its basis depends on (paths and fragment searches included).
      const double reach = slot >= 0 ? cut_.slots[static_cast<size_t>(slot)].reach : 1.5 * (1.0 + 1e-9);
      if (!index.touches(box_around(xi, reach * lu, reach * lv), first_new_edge)) continue;
      PointResult& res = results[i];
      const size_t cell = is_shear ? id : cell_of(id);
      if (slot == -1 && !nurbs_support_cut(xi, cell, index)) {
        res.kind = PointResult::Nurbs;
        continue;
      }
      res.kind = PointResult::Chain;
      res.fit = fit_chain(xi, work);
      fill_support(res.fit, work.basis, support_out);
      res.index = support_out.index;
      res.basis = support_out.basis;
      res.rigid_offset = support_out.rigid_offset;
    }
  });

  merge_point_results(results, np, cut_.point_slot, cut_.shear_slot, cut_.slots, report);
  const BasisCensus census = count_bases();
  cut_.census = census;
  report.census = census;
  report.failures = census.failures;
  mark_near_crack(cut_, quad_.points_per_cell);
  lay_out_slot_forces(cut_.slots, gather_);
  build_mls_lanes();
  for (int32_t s : cut_.point_slot) report.mls_points += s >= 0 && cut_.slots[static_cast<size_t>(s)].level < BasisLevel::Rigid;
  for (int32_t s : cut_.shear_slot) report.mls_shear += s >= 0 && cut_.slots[static_cast<size_t>(s)].level < BasisLevel::Rigid;
  cut_.num_mls_points = report.mls_points;
  const BasisRows rows = basis_rows();
  choose_added_mass(rows, mass, stiffness_.reference, stiffness_.mass_scaling_budget, stiffness_.added_mass);
  stiffness_.current = stiffness_of(rows, mass, stiffness_.added_mass);
  return report;
}

BasisCensus ShellPatch::count_bases() const {
  const size_t np = quad_.param.size();
  BasisCensus census;
  for (const int32_t* slot_of : {cut_.point_slot.data(), cut_.shear_slot.data()})
    for (size_t i = 0; i < (slot_of == cut_.point_slot.data() ? np : quad_.num_cells); ++i) {
      if (slot_of[i] < 0) continue;
      const MlsSupport& m = cut_.slots[static_cast<size_t>(slot_of[i])];
      census.nudged += m.nudged;
      census.failures += m.chain_failed;
    }
  for (size_t q = 0; q < np; ++q) {
    const BasisLevel level = point_level(q);
    ++census.points[static_cast<size_t>(level)];
    if (cut_.point_slot[q] >= 0 && cut_.slots[static_cast<size_t>(cut_.point_slot[q])].order == 1) ++census.membrane_only;
    if (level < BasisLevel::Rigid) continue;
    const double V = quad_.point_volume(q);
    (level == BasisLevel::Rigid ? census.rigid_area : census.removed_area) += V / material_.thickness;
    (level == BasisLevel::Rigid ? census.rigid_mass : census.removed_mass) += material_.density * V;
  }
  for (size_t c = 0; c < quad_.num_cells; ++c) ++census.shear[static_cast<size_t>(shear_level(c))];
  return census;
}

BasisRows ShellPatch::basis_rows() const {
  const double lu = quad_.control_grid.cell_u, lv = quad_.control_grid.cell_v;
  std::vector<double> membrane(x.size(), 0.0), bending(x.size(), 0.0);
  std::vector<double> a, b;
  // One point's share of the row sums: V a_i (sum_j a_j) for every support control point i.
  auto add_point = [&](const BasisView& view, double V, bool curvature) {
    a.assign(static_cast<size_t>(view.n), 0.0);
    b.assign(static_cast<size_t>(view.n), 0.0);
    double sum_a = 0, sum_b = 0;
    for (int s = 0; s < view.n; ++s) {
      const double* d = view.basis + s * view.stride;
      a[static_cast<size_t>(s)] = std::hypot(lu * d[1], lv * d[2]);
      if (curvature)
        b[static_cast<size_t>(s)] = std::sqrt(std::pow(lu * lu * d[3], 2) + 2 * std::pow(lu * lv * d[4], 2) +
                                              std::pow(lv * lv * d[5], 2));
      sum_a += a[static_cast<size_t>(s)];
      sum_b += b[static_cast<size_t>(s)];
    }
    for (int s = 0; s < view.n; ++s) {
      const size_t i = static_cast<size_t>(view.index[s]);
      membrane[i] += V * a[static_cast<size_t>(s)] * sum_a;
      bending[i] += V * b[static_cast<size_t>(s)] * sum_b;
    }
  };
  for (size_t q = 0; q < quad_.param.size(); ++q) {
    const int32_t slot = cut_.point_slot.empty() ? -1 : cut_.point_slot[q];
    const MlsSupport* m = slot >= 0 ? &cut_.slots[static_cast<size_t>(slot)] : nullptr;
    if (m && m->level >= BasisLevel::Rigid) continue;  // carries no stress
    add_point(point_basis(q), quad_.point_volume(q), !(m && m->order == 1));
  }
  for (size_t c = 0; c < quad_.num_cells; ++c) {  // Type III: first derivatives only (tangents a_1, a_2)
    const int32_t slot = cut_.shear_slot.empty() ? -1 : cut_.shear_slot[c];
    if (slot >= 0 && cut_.slots[static_cast<size_t>(slot)].level >= BasisLevel::Rigid) continue;
    add_point(shear_basis(c), shear.volume[c], false);
  }
  return {std::move(membrane), std::move(bending)};
}

double ShellPatch::added_mass_total() const {
  double sum = 0;
  for (double m : stiffness_.added_mass) sum += m;
  return sum;
}

double ShellPatch::control_mass_total() const {
  double sum = 0;
  for (double m : mass) sum += m;
  return sum;
}

double ShellPatch::membrane_step_scale() const {
  if (!(stiffness_.current.membrane > stiffness_.reference.membrane)) return 1.0;
  return std::sqrt(stiffness_.reference.membrane / stiffness_.current.membrane);
}

double ShellPatch::bending_step_scale() const {
  if (!(stiffness_.current.bending > stiffness_.reference.bending)) return 1.0;
  return std::sqrt(stiffness_.reference.bending / stiffness_.current.bending);
}

void ShellPatch::build_mls_lanes() {
  mls_lanes_.batches.clear();
  mls_lanes_.support.clear();
  mls_lanes_.basis.clear();
  mls_lanes_.batched.assign(quad_.param.size(), 0);
  // Membrane-only (linear) bases keep the scalar kernel, which drops the curvature for them; so do
  // supports larger than the kernel's result holds.
  std::vector<std::pair<size_t, size_t>> points;  // (support size, point)
  for (size_t q = 0; q < quad_.param.size(); ++q) {
    const int32_t slot = cut_.point_slot[q];
    if (slot < 0) continue;
    const MlsSupport& m = cut_.slots[static_cast<size_t>(slot)];
    if (m.level >= BasisLevel::Rigid || m.order == 1 || m.index.empty() ||
        m.index.size() > static_cast<size_t>(kType4MaxSupport))
      continue;
    points.emplace_back(m.index.size(), q);
  }
  // Sorted by support size, so that a batch pads few entries.
  std::sort(points.begin(), points.end());
  const size_t lanes = kType4Lanes;
  for (size_t b = 0; b < points.size(); b += lanes) {
    const size_t used = std::min(lanes, points.size() - b);
    MlsLaneBatch batch;
    batch.n = static_cast<int>(points[b + used - 1].first);
    batch.first = mls_lanes_.support.size();
    const size_t n = static_cast<size_t>(batch.n);
    mls_lanes_.support.resize(batch.first + lanes * n);
    mls_lanes_.basis.resize(5 * (batch.first + lanes * n), 0.0);
    double* basis = mls_lanes_.basis.data() + 5 * batch.first;
    for (size_t i = 0; i < lanes; ++i) {
      // Padding lanes repeat the first point (valid data, never written back).
      const size_t q = points[b + (i < used ? i : 0)].second;
      batch.q[i] = q;
      if (i < used) {
        batch.active |= 1u << i;
        mls_lanes_.batched[q] = 1;
      }
      const MlsSupport& m = cut_.slots[static_cast<size_t>(cut_.point_slot[q])];
      int* support = mls_lanes_.support.data() + batch.first + i * n;
      for (size_t s = 0; s < n; ++s) support[s] = m.index[s < m.index.size() ? s : 0];
      for (size_t s = 0; s < m.index.size(); ++s)
        for (size_t k = 0; k < 5; ++k) basis[(s * 5 + k) * lanes + i] = m.basis[s * kBasisStride + 1 + k];
    }
    mls_lanes_.batches.push_back(batch);
  }
}

void ShellPatch::surface_stencil(const Vec2& uv, BasisChainWork& work, SurfaceStencil& out) const {
  nurbs::SurfaceBasis basis;
  reference_.rational_basis(uv.x(), uv.y(), basis);
  bool cut = false;
  if (cut_.crack && cut_.crack->num_segments() > 0)
    for (int k = 0; k < basis.count && !cut; ++k)
      cut = cut_.crack->crosses(uv, quad_.control_grid.point(basis.index[static_cast<size_t>(k)]));
  out.offset.setZero();
  if (cut) {  // near the crack: the quadrature points' fallback chain, never the NURBS average
    const PointFit fit = fit_chain(uv, work);
    out.level = fit.level;
    if (fit.level != BasisLevel::Removed) {
      const MlsBasis& b = work.basis;
      out.index.assign(b.index.begin(), b.index.end());
      out.R.assign(b.R.begin(), b.R.begin() + static_cast<std::ptrdiff_t>(b.index.size()));
      if (fit.level == BasisLevel::Rigid) {  // a translation: the rest point minus where the weights put it
        Vec3 mean_rest = Vec3::Zero();
        for (size_t k = 0; k < b.index.size(); ++k)
          mean_rest += b.R[k] * reference_.control_points()[static_cast<size_t>(b.index[k])];
        out.offset = reference_.point(fit.at.x(), fit.at.y()) - mean_rest;
      }
      return;
    }
  } else {
    out.level = BasisLevel::Nurbs;
  }
  // NURBS, or the NURBS position of a Removed point (meaningless; its faces are dropped).
  out.index.assign(basis.index.begin(), basis.index.begin() + basis.count);
  out.R.assign(basis.R.begin(), basis.R.begin() + basis.count);
}

ShellPatch::SurfacePoint ShellPatch::surface_point(const Vec2& uv, BasisChainWork& work) const {
  thread_local SurfaceStencil stencil;
  surface_stencil(uv, work, stencil);
  return {stencil_position(stencil.index.data(), stencil.R.data(), stencil.index.size(), stencil.offset), stencil.level};
}

Vec3 ShellPatch::position_at(const Vec2& uv, MlsBasis&) const {
  thread_local BasisChainWork work;
  return surface_point(uv, work).position;
}

}  // namespace shellfrac::shell
