// The crack side of ShellPatch: switching points whose NURBS support a crack cuts to MLS bases
// (thesis sec. 4.6), and evaluating the cut surface for render meshes (sec. 4.9.3).
#include <tbb/parallel_for.h>

#include <algorithm>

#include "shell/shell_patch.hpp"

namespace shellfrac::shell {

namespace {

crack2d::Box box_around(const Vec2& c, double hu, double hv) {
  return {Vec2(c.x() - hu, c.y() - hv), Vec2(c.x() + hu, c.y() + hv)};
}

// A point's new basis after a crack update: unchanged, NURBS, MLS (in `support`) or failed.
struct PointResult {
  enum Kind : unsigned char { Unchanged, Nurbs, Mls, Failed } kind = Unchanged;
  std::vector<int> index;
  std::vector<double> basis;
  double reach = 0;  // MLS support factor
  std::string reason;
};

}  // namespace

bool ShellPatch::nurbs_support_cut(const Vec2& xi, size_t cell, const crack2d::CrackIndex& index) const {
  const int* sup = support(cell);
  for (int s = 0; s < support_size_; ++s)
    if (index.crosses(xi, control_grid_.point(sup[s]))) return true;
  return false;
}

bool ShellPatch::fit_mls(const Vec2& xi, const crack2d::CrackIndex& index, MlsBasis& work) const {
  // A control point is in the support only if the segment to it crosses no crack (thesis sec. 4.6).
  auto visible = [&](const Vec2& a, const Vec2& b) { return !index.crosses(a, b); };
  if (mls_basis(xi, control_grid_, visible, mls_settings_, work)) return true;
  // Pockets between crack branches can leave a point only a few, nearly aligned, visible control points.
  // Dropping it loses material, so accept a less accurate fit first: 6 points (the quadratic basis
  // size) and a moment matrix far from singular (rcond 1e-9); only then give up.
  MlsSettings relaxed = mls_settings_;
  relaxed.min_neighbours = 6;
  relaxed.min_rcond = std::min(mls_settings_.min_rcond, 1e-9);
  return mls_basis(xi, control_grid_, visible, relaxed, work);
}

bool ShellPatch::build_mls(const Vec2& xi, const crack2d::CrackIndex& index, MlsBasis& work, MlsSupport& out) const {
  if (!fit_mls(xi, index, work)) return false;
  const size_t n = work.index.size();
  out.index.assign(work.index.begin(), work.index.end());
  out.basis.resize(n * kBasisStride);
  for (size_t k = 0; k < n; ++k) {
    double* d = &out.basis[k * kBasisStride];
    d[0] = work.R[k];
    d[1] = work.R1[k];
    d[2] = work.R2[k];
    d[3] = work.R11[k];
    d[4] = work.R12[k];
    d[5] = work.R22[k];
  }
  out.force.assign(n, Vec3::Zero());
  return true;
}

CrackUpdate ShellPatch::update_crack(const crack2d::CrackIndex& index, size_t first_new_edge,
                                     const MlsSettings& settings) {
  crack_ = &index;
  mls_settings_ = settings;
  CrackUpdate report;
  const double lu = control_grid_.cell_u, lv = control_grid_.cell_v;
  // Parameter points: in-plane points first, then shear particles (cell centres).
  const size_t np = param_.size(), total = np + num_cells_;
  std::vector<PointResult> results(total);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, total, 64), [&](const tbb::blocked_range<size_t>& r) {
    MlsBasis work;
    MlsSupport support_out;
    for (size_t i = r.begin(); i != r.end(); ++i) {
      const bool is_shear = i >= np;
      const size_t id = is_shear ? i - np : i;
      const Vec2& xi = is_shear ? cell_center_[id] : param_[id];
      const int32_t slot = is_shear ? shear_slot_[id] : point_slot_[id];
      // Only points whose current support the new segments touch are re-examined (thesis sec. 4.6).
      const double reach = slot >= 0 ? slots_[static_cast<size_t>(slot)].reach : 1.5 * (1.0 + 1e-9);
      if (!index.touches(box_around(xi, reach * lu, reach * lv), first_new_edge)) continue;
      PointResult& res = results[i];
      const size_t cell = is_shear ? id : cell_of(id);
      if (slot == -1 && !nurbs_support_cut(xi, cell, index)) {
        res.kind = PointResult::Nurbs;
        continue;
      }
      if (build_mls(xi, index, work, support_out)) {
        res.kind = PointResult::Mls;
        res.index = support_out.index;
        res.basis = support_out.basis;
        res.reach = work.factor;
      } else {
        res.kind = PointResult::Failed;
        res.reason = work.reason;
      }
    }
  });

  // Serial merge in point order (deterministic slot numbering).
  for (size_t i = 0; i < total; ++i) {
    PointResult& res = results[i];
    if (res.kind == PointResult::Unchanged) continue;
    ++report.examined;
    const bool is_shear = i >= np;
    const size_t id = is_shear ? i - np : i;
    int32_t& slot = is_shear ? shear_slot_[id] : point_slot_[id];
    if (res.kind == PointResult::Nurbs) continue;  // the crack passes by without cutting its support
    if (res.kind == PointResult::Failed) {
      if (report.first_failure.empty())
        report.first_failure = (is_shear ? "shear particle " : "quadrature point ") + std::to_string(id) + ": " + res.reason;
      slot = kMlsFailed;  // its MLS slot, if any, stays allocated but unused
      continue;
    }
    if (slot < 0) {
      slot = static_cast<int32_t>(slots_.size());
      slots_.emplace_back();
    }
    MlsSupport& m = slots_[static_cast<size_t>(slot)];
    m.index = std::move(res.index);
    m.basis = std::move(res.basis);
    m.force.assign(m.index.size(), Vec3::Zero());
    m.reach = res.reach;
  }
  // Points whose support is singular now (a point can recover when the crack around it grows).
  num_mls_failures_ = 0;
  for (int32_t sl : point_slot_) num_mls_failures_ += sl == kMlsFailed;
  for (int32_t sl : shear_slot_) num_mls_failures_ += sl == kMlsFailed;
  report.failures = num_mls_failures_;
  rebuild_mls_gather();
  for (int32_t s : point_slot_) report.mls_points += s >= 0;
  for (int32_t s : shear_slot_) report.mls_shear += s >= 0;
  num_mls_points_ = report.mls_points;
  return report;
}

void ShellPatch::rebuild_mls_gather() {
  // Control point -> (slot, entry) in slot order: a fixed summation order for the force gather.
  std::fill(mls_gather_offsets_.begin(), mls_gather_offsets_.end(), 0);
  std::fill(control_near_crack_.begin(), control_near_crack_.end(), 0);
  for (const MlsSupport& m : slots_)
    for (int k : m.index) ++mls_gather_offsets_[static_cast<size_t>(k) + 1];
  for (size_t i = 0; i < x.size(); ++i) mls_gather_offsets_[i + 1] += mls_gather_offsets_[i];
  mls_gather_.resize(static_cast<size_t>(mls_gather_offsets_.back()));
  std::vector<int> cursor(mls_gather_offsets_.begin(), mls_gather_offsets_.end() - 1);
  for (size_t s = 0; s < slots_.size(); ++s)
    for (size_t e = 0; e < slots_[s].index.size(); ++e) {
      const auto k = static_cast<size_t>(slots_[s].index[e]);
      mls_gather_[static_cast<size_t>(cursor[k]++)] = {static_cast<int>(s), static_cast<int>(e)};
      control_near_crack_[k] = 1;
    }
  for (size_t c = 0; c < num_cells_; ++c) shear_near_crack_[c] = shear_slot_[c] != -1;
}

Vec3 ShellPatch::position_at(const Vec2& uv, MlsBasis& work) const {
  nurbs::SurfaceBasis basis;
  reference_.rational_basis(uv.x(), uv.y(), basis);
  bool cut = false;
  if (crack_ && crack_->num_segments() > 0)
    for (int k = 0; k < basis.count && !cut; ++k)
      cut = crack_->crosses(uv, control_grid_.point(basis.index[static_cast<size_t>(k)]));
  // Near the crack: MLS over the visible control points. If even the relaxed fit fails (a vertex in a
  // sliver between crack branches) the NURBS position is the best there is.
  if (cut && fit_mls(uv, *crack_, work)) {
    Vec3 p = Vec3::Zero();
    for (size_t k = 0; k < work.index.size(); ++k) p += work.R[k] * x[static_cast<size_t>(work.index[k])];
    return p;
  }
  Vec3 p = Vec3::Zero();
  for (int k = 0; k < basis.count; ++k)
    p += basis.R[static_cast<size_t>(k)] * x[static_cast<size_t>(basis.index[static_cast<size_t>(k)])];
  return p;
}

}  // namespace shellfrac::shell
