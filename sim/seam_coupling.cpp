// The coupling stage of a time step (thesis sec. 4.8): the leader's coupled rows projected onto the
// coupling constraint with both patches' rows (or, as in the thesis, left as the grid moved them), then
// the follower rows placed from the leader's, with the momentum-correction velocity carried to the
// neighbouring control points.
#include <algorithm>
#include <cstdint>

#include "coupling/row_projection.hpp"

#include "sim/seam_system.hpp"

namespace shellfrac::sim {

namespace {

// A control point whose velocity the seam sets or corrects after g2p keeps no APIC affine velocity
// (thesis Eq. 2.23): the C_p that g2p gave it belongs to the velocity the grid gave it, not to the one
// it now has. Carried into the next p2g, that stale C_p fed a growing mode on stretched multi-seam
// sheets under "apic" and "adaptive" (an L of three patches diverged at 0.30 s; PIC has no C_p).
// Dropping it changes no linear momentum: sum_i w_ip C_p (x_i - x_p) = 0 for B-spline weights.
void drop_affine(World& world, size_t patch, size_t point) {
  std::vector<Eigen::Matrix3d>& affine = world.affine(patch);
  if (!affine.empty()) affine[point].setZero();
}

}  // namespace

void SeamSystem::save_start_positions(const World& world) {
  for (const scene::model::InterfaceSpec& spec : model_.interfaces) {
    const auto f = static_cast<size_t>(spec.coupling.follower_patch), l = static_cast<size_t>(spec.coupling.leader_patch);
    start_positions_[f] = world.shell(f).x;
    start_positions_[l] = world.shell(l).x;
  }
}

const coupling::Interface& SeamSystem::operators(size_t i) const {
  return seams_[i].cut ? *seams_[i].cut : model_.interfaces[i].coupling;
}


void SeamSystem::correct_near_seam(World& world, const mpm::SparseGrid& grid, size_t patch,
                                   const std::vector<int>& rows, const std::vector<Eigen::Vector3d>& target,
                                   const std::vector<unsigned char>& released, const std::vector<int>& neighbours,
                                   double dt) {
  // Momentum correction (Eq. 4.30-4.32): the coupled rows' correction velocity dv = (target - xbar)/dt
  // goes to the grid once more, mass-weighted with the weights of this step (positions x^n), and every
  // control point of the patch near the seam takes the interpolated correction for its second advection.
  shell::ShellPatch& p = world.shell(patch);
  const std::vector<Eigen::Vector3d>& start = start_positions_[patch];
  // Per-node sums in a dense scratch array that is zero between uses; only touched nodes are reset
  // (a hash map here cost a third of the coupling stage).
  if (node_scratch_.size() < grid.num_nodes()) {
    node_scratch_.resize(grid.num_nodes(), Eigen::Vector3d::Zero());
    node_touched_.resize(grid.num_nodes(), 0);
  }
  std::vector<uint32_t> touched;
  const double inv_dx = 1.0 / grid.dx();
  for (size_t k = 0; k < rows.size(); ++k) {
    if (released[k]) continue;
    const auto c = static_cast<size_t>(rows[k]);
    const Eigen::Vector3d dv = (target[k] - p.x[c]) / dt;  // Eq. 4.30
    const double m = world.transfer_mass(patch)[c];
    const mpm::StencilWeights sw = mpm::stencil_weights(start[c], inv_dx);
    const auto nodes = grid.stencil_nodes(start[c]);
    for (int s = 0; s < 27; ++s) {
      const uint32_t node = nodes[static_cast<size_t>(s)];
      if (!node_touched_[node]) {
        node_touched_[node] = 1;
        touched.push_back(node);
      }
      node_scratch_[node] += (m * sw.weight(s % 3, (s / 3) % 3, s / 9)) * dv;
    }
  }
  for (uint32_t node : touched) {  // Eq. 4.31
    const double mi = grid.node_mass(node);
    node_scratch_[node] = mi > 0 ? Eigen::Vector3d(node_scratch_[node] / mi) : Eigen::Vector3d(Eigen::Vector3d::Zero());
  }
  for (int k : neighbours) {  // Eq. 4.32 and the second advection
    const auto c = static_cast<size_t>(k);
    const mpm::StencilWeights sw = mpm::stencil_weights(start[c], inv_dx);
    const auto nodes = grid.stencil_nodes(start[c]);
    Eigen::Vector3d dv = Eigen::Vector3d::Zero();
    for (int s = 0; s < 27; ++s) dv += sw.weight(s % 3, (s / 3) % 3, s / 9) * node_scratch_[nodes[static_cast<size_t>(s)]];
    p.v[c] += dv;
    p.x[c] += dt * dv;
    drop_affine(world, patch, c);
  }
  for (uint32_t node : touched) {
    node_scratch_[node].setZero();
    node_touched_[node] = 0;
  }
}

namespace {

// Held leader points weigh this many times their mass in the row projection, so that the projection
// works around them; their state is then restored exactly.
constexpr double kHeldWeight = 1e8;

std::vector<int> stacked_rows(const std::vector<int>& row1, const std::vector<int>& row2, bool c1) {
  std::vector<int> rows = row1;
  if (c1) rows.insert(rows.end(), row2.begin(), row2.end());
  return rows;
}

coupling::PointRows gather_rows(const std::vector<Eigen::Vector3d>& x, const std::vector<int>& rows) {
  coupling::PointRows out(static_cast<Eigen::Index>(rows.size()), 3);
  for (size_t k = 0; k < rows.size(); ++k) out.row(static_cast<Eigen::Index>(k)) = x[static_cast<size_t>(rows[k])].transpose();
  return out;
}

}  // namespace

void SeamSystem::build_projection(const World& world, size_t seam) {
  const scene::model::InterfaceSpec& spec = model_.interfaces[seam];
  SeamState& st = seams_[seam];
  const coupling::Interface& c = st.cut ? *st.cut : spec.coupling;
  const bool exact = c.exact;  // a cut exact seam keeps its rows in the segmented shared space
  st.projection.reset();
  if (!spec.project_both_sides && !exact) return;  // thesis: the leader's rows stay as the grid moved them
  const bool c1 = c.continuity == coupling::Continuity::C1;
  const auto lp = static_cast<size_t>(c.leader_patch), fp = static_cast<size_t>(c.follower_patch);
  const std::vector<int> lrows = stacked_rows(c.leader_row1, c.leader_row2, c1);
  const std::vector<int> frows = stacked_rows(c.follower_row1, c.follower_row2, c1);
  // Held leader points keep what the grid (or a pin, or another seam at a patch corner) gave them: the
  // projection moving them would open the other seam or break the pin.
  auto in_rows = [](const std::vector<int>& rows, int k) { return std::find(rows.begin(), rows.end(), k) != rows.end(); };
  auto other_seam_sets = [&](int k) {
    for (size_t j = 0; j < model_.interfaces.size(); ++j) {
      const coupling::Interface& o = model_.interfaces[j].coupling;
      if (j == seam) continue;
      if (static_cast<size_t>(o.follower_patch) == lp && (in_rows(o.follower_row1, k) || in_rows(o.follower_row2, k)))
        return true;
      if (static_cast<size_t>(o.leader_patch) == lp && (in_rows(o.leader_row1, k) || in_rows(o.leader_row2, k)))
        return true;
    }
    return false;
  };
  // Under exact closure a leader row point in no segment of a cut seam (its C1 tangent torn by the
  // crack, coupling::cut_exact_interface) is not constrained either.
  const auto nl = static_cast<Eigen::Index>(c.leader_row1.size());
  auto unconstrained = [&](size_t k) {
    if (!exact) return false;
    const auto r = static_cast<Eigen::Index>(k);
    return r < nl ? c.shared.E1.row(r).isZero(0.0) : c.shared.E2.row(r - nl).isZero(0.0);
  };
  st.leader_held.assign(lrows.size(), 0);
  for (size_t k = 0; k < lrows.size(); ++k)
    st.leader_held[k] = world.transfer_mass(lp)[static_cast<size_t>(lrows[k])] == 0 || other_seam_sets(lrows[k]) ||
                        unconstrained(k);
  // The correction reaches the leader's points near the seam except those another seam sets.
  st.leader_neighbours.clear();
  for (int k : spec.leader_neighbours)
    if (!other_seam_sets(k)) st.leader_neighbours.push_back(k);
  Eigen::VectorXd ml(static_cast<Eigen::Index>(lrows.size())), mf(static_cast<Eigen::Index>(frows.size()));
  for (size_t k = 0; k < lrows.size(); ++k)
    ml[static_cast<Eigen::Index>(k)] = world.shell(lp).mass[static_cast<size_t>(lrows[k])] * (st.leader_held[k] ? kHeldWeight : 1.0);
  for (size_t k = 0; k < frows.size(); ++k)  // rows a crack released move on their own: no say
    mf[static_cast<Eigen::Index>(k)] =
        spec.project_both_sides && !st.released[k] ? world.shell(fp).mass[static_cast<size_t>(frows[k])] : 0.0;
  st.projection.emplace(c, exact, ml, mf);
}

void SeamSystem::project_rows(World& world, const mpm::SparseGrid& grid, size_t seam, double dt) {
  // The leader's coupled rows take the state nearest (mass norm) to what the grid gave both patches'
  // rows among those the coupling allows (coupling/row_projection.hpp): the rows' momentum is kept, and
  // for exact closure the rows stay in the shared space. Their jump from where the grid put them reaches
  // the leader's neighbouring points through the grid, like the follower's correction (Eq. 4.30-4.32).
  const scene::model::InterfaceSpec& spec = model_.interfaces[seam];
  const SeamState& st = seams_[seam];
  const coupling::Interface& c = st.cut ? *st.cut : spec.coupling;
  const bool c1 = c.continuity == coupling::Continuity::C1;
  const auto lp = static_cast<size_t>(c.leader_patch);
  shell::ShellPatch& leader = world.shell(lp);
  const shell::ShellPatch& follower = world.shell(static_cast<size_t>(c.follower_patch));
  const std::vector<int> lrows = stacked_rows(c.leader_row1, c.leader_row2, c1);
  const std::vector<int> frows = stacked_rows(c.follower_row1, c.follower_row2, c1);
  const coupling::PointRows x = st.projection->apply(gather_rows(leader.x, lrows), gather_rows(follower.x, frows));
  const coupling::PointRows v = st.projection->apply(gather_rows(leader.v, lrows), gather_rows(follower.v, frows));
  std::vector<Eigen::Vector3d> target(lrows.size()), target_v(lrows.size());
  for (size_t k = 0; k < lrows.size(); ++k) {
    const auto p = static_cast<size_t>(lrows[k]);
    const bool held = st.leader_held[k];
    target[k] = held ? leader.x[p] : Eigen::Vector3d(x.row(static_cast<Eigen::Index>(k)).transpose());
    target_v[k] = held ? leader.v[p] : Eigen::Vector3d(v.row(static_cast<Eigen::Index>(k)).transpose());
  }
  if (spec.momentum_correction)
    correct_near_seam(world, grid, lp, lrows, target, std::vector<unsigned char>(lrows.size(), 0), st.leader_neighbours, dt);
  for (size_t k = 0; k < lrows.size(); ++k) {
    leader.x[static_cast<size_t>(lrows[k])] = target[k];
    leader.v[static_cast<size_t>(lrows[k])] = target_v[k];
    drop_affine(world, lp, static_cast<size_t>(lrows[k]));
  }
}

void SeamSystem::couple(World& world, const mpm::SparseGrid& grid, double dt) {
  for (size_t i : order_) {
    const scene::model::InterfaceSpec& spec = model_.interfaces[i];
    if (seams_[i].projection) project_rows(world, grid, i, dt);
    const coupling::Interface& c = seams_[i].cut ? *seams_[i].cut : spec.coupling;
    const shell::ShellPatch& leader = world.shell(static_cast<size_t>(c.leader_patch));
    shell::ShellPatch& follower = world.shell(static_cast<size_t>(c.follower_patch));
    // Targets of the coupled follower rows from the advected leader (thesis Eq. 4.29, 4.34), for
    // positions and (the operators are linear) velocities; rows a crack released move on their own.
    const std::vector<Eigen::Vector3d> target = c.follower_positions(leader.x);
    const std::vector<Eigen::Vector3d> target_v = c.follower_positions(leader.v);
    const std::vector<unsigned char>& released = seams_[i].released;
    std::vector<int> rows = c.follower_row1;
    if (c.continuity == coupling::Continuity::C1) rows.insert(rows.end(), c.follower_row2.begin(), c.follower_row2.end());
    if (!spec.momentum_correction) {
      // The uncorrected comparison of thesis sec. 4.8.1.1: Eq. 4.29 (and 4.34) set only the positions of
      // the coupled rows; their velocities stay what the grid gave them, so the momentum they carry back
      // to the grid next step is not that of their motion, and nothing moves the rows behind them along.
      for (size_t k = 0; k < rows.size(); ++k)
        if (!released[k]) follower.x[static_cast<size_t>(rows[k])] = target[k];
      continue;
    }
    correct_near_seam(world, grid, static_cast<size_t>(c.follower_patch), rows, target, released, spec.follower_neighbours, dt);
    for (size_t k = 0; k < rows.size(); ++k)  // the coupled rows sit exactly on their targets
      if (!released[k]) {
        follower.x[static_cast<size_t>(rows[k])] = target[k];
        follower.v[static_cast<size_t>(rows[k])] = target_v[k];
        drop_affine(world, static_cast<size_t>(c.follower_patch), static_cast<size_t>(rows[k]));
      }
  }
  // Where seams meet at a patch corner, a row-1 (C0) point of one seam can be a row-2 (C1) point of
  // another, and the later seam would open the earlier one. Closure wins: every seam's row 1 is placed
  // once more, in order, from its leader's final state.
  for (size_t i : order_) {
    const scene::model::InterfaceSpec& spec = model_.interfaces[i];
    if (!seams_[i].shares_points) continue;
    const coupling::Interface& c = seams_[i].cut ? *seams_[i].cut : spec.coupling;
    const shell::ShellPatch& leader = world.shell(static_cast<size_t>(c.leader_patch));
    shell::ShellPatch& follower = world.shell(static_cast<size_t>(c.follower_patch));
    const std::vector<Eigen::Vector3d> target = c.follower_positions(leader.x);
    const std::vector<Eigen::Vector3d> target_v = c.follower_positions(leader.v);
    for (size_t k = 0; k < c.follower_row1.size(); ++k)
      if (!seams_[i].released[k]) {
        follower.x[static_cast<size_t>(c.follower_row1[k])] = target[k];
        if (spec.momentum_correction) follower.v[static_cast<size_t>(c.follower_row1[k])] = target_v[k];
      }
  }
  // The shear particles of the cells those points span follow them (thesis Eq. 4.10), so their affine
  // velocity from g2p no longer describes the motion either (a seam stress ratio of 1.22 against the
  // one-patch drape's, 1.19 without it).
  for (size_t patch = 0; patch < world.num_shells(); ++patch) {
    std::vector<Eigen::Matrix3d>& affine = world.shear_affine(patch);
    if (!affine.empty())
      for (size_t cell : shear_near_seam_[patch]) affine[cell].setZero();
  }
}

}  // namespace shellfrac::sim
