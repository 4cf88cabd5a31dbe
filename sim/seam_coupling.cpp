// The coupling stage of a time step (thesis sec. 4.8): follower rows placed from their leaders, with
// the momentum-correction velocity carried to the neighbouring control points, and the optional exact
// closure that first keeps the leader's rows in the spline space both edges share.
#include <cstdint>

#include "sim/simulation.hpp"

namespace shellfrac::sim {

void Simulation::correct_near_seam(size_t patch, const std::vector<int>& rows,
                                   const std::vector<Eigen::Vector3d>& target,
                                   const std::vector<unsigned char>& released, const std::vector<int>& neighbours,
                                   double dt) {
  // Momentum correction (Eq. 4.30-4.32): the coupled rows' correction velocity dv = (target - xbar)/dt
  // goes to the grid once more, mass-weighted with the weights of this step (positions x^n), and every
  // control point of the patch near the seam takes the interpolated correction for its second advection.
  shell::ShellPatch& p = patches_[patch];
  const std::vector<Eigen::Vector3d>& start = start_positions_[patch];
  // Per-node sums in a dense scratch array that is zero between uses; only touched nodes are reset
  // (a hash map here cost a third of the coupling stage).
  if (node_scratch_.size() < grid_.num_nodes()) {
    node_scratch_.resize(grid_.num_nodes(), Eigen::Vector3d::Zero());
    node_touched_.resize(grid_.num_nodes(), 0);
  }
  std::vector<uint32_t> touched;
  const double inv_dx = 1.0 / grid_.dx();
  for (size_t k = 0; k < rows.size(); ++k) {
    if (released[k]) continue;
    const auto c = static_cast<size_t>(rows[k]);
    const Eigen::Vector3d dv = (target[k] - p.x[c]) / dt;  // Eq. 4.30
    const double m = transfer_mass_[patch][c];
    const mpm::StencilWeights sw = mpm::stencil_weights(start[c], inv_dx);
    const auto nodes = grid_.stencil_nodes(start[c]);
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
    const double mi = grid_.node_mass(node);
    node_scratch_[node] = mi > 0 ? Eigen::Vector3d(node_scratch_[node] / mi) : Eigen::Vector3d(Eigen::Vector3d::Zero());
  }
  for (int k : neighbours) {  // Eq. 4.32 and the second advection
    const auto c = static_cast<size_t>(k);
    const mpm::StencilWeights sw = mpm::stencil_weights(start[c], inv_dx);
    const auto nodes = grid_.stencil_nodes(start[c]);
    Eigen::Vector3d dv = Eigen::Vector3d::Zero();
    for (int s = 0; s < 27; ++s) dv += sw.weight(s % 3, (s / 3) % 3, s / 9) * node_scratch_[nodes[static_cast<size_t>(s)]];
    p.v[c] += dv;
    p.x[c] += dt * dv;
  }
  for (uint32_t node : touched) {
    node_scratch_[node].setZero();
    node_touched_[node] = 0;
  }
}

void Simulation::close_onto_shared_space(size_t seam, double dt) {
  // Exact closure (coupling/shared_space.hpp): the leader's coupled rows, positions and velocities, are
  // projected onto the shared spline space with their masses (centre of mass and momentum unchanged), so
  // that the follower rows of Eq. 4.29 / 4.34 reproduce the leader's edge exactly. The projection's jump
  // reaches the leader's neighbouring points through the grid like the follower's correction.
  const InterfaceSpec& spec = scene_.interfaces[seam];
  const coupling::Interface& c = spec.coupling;
  const SeamState& st = seams_[seam];
  const auto lp = static_cast<size_t>(c.leader_patch);
  shell::ShellPatch& leader = patches_[lp];
  std::vector<int> rows;
  std::vector<Eigen::Vector3d> target, target_v;
  auto project = [&](const std::vector<int>& row, const Eigen::MatrixXd& P) {
    const auto n = static_cast<Eigen::Index>(row.size());
    Eigen::Matrix<double, Eigen::Dynamic, 3> x(n, 3), v(n, 3);
    for (Eigen::Index k = 0; k < n; ++k) {
      x.row(k) = leader.x[static_cast<size_t>(row[static_cast<size_t>(k)])].transpose();
      v.row(k) = leader.v[static_cast<size_t>(row[static_cast<size_t>(k)])].transpose();
    }
    const Eigen::Matrix<double, Eigen::Dynamic, 3> px = P * x, pv = P * v;
    for (Eigen::Index k = 0; k < n; ++k) {
      rows.push_back(row[static_cast<size_t>(k)]);
      target.emplace_back(px.row(k).transpose());
      target_v.emplace_back(pv.row(k).transpose());
    }
  };
  project(c.leader_row1, st.leader_projector1);
  if (c.continuity == coupling::Continuity::C1) project(c.leader_row2, st.leader_projector2);
  if (spec.momentum_correction)
    correct_near_seam(lp, rows, target, std::vector<unsigned char>(rows.size(), 0), spec.leader_neighbours, dt);
  for (size_t k = 0; k < rows.size(); ++k) {
    leader.x[static_cast<size_t>(rows[k])] = target[k];
    leader.v[static_cast<size_t>(rows[k])] = target_v[k];
  }
}

void Simulation::stage_coupling(double dt) {
  if (scene_.interfaces.empty()) return;
  auto scope = timer_.time("coupling");
  for (size_t i = 0; i < scene_.interfaces.size(); ++i) {
    const InterfaceSpec& spec = scene_.interfaces[i];
    if (!spec.coupled) continue;
    // A seam a crack has cut falls back to its cut least-squares operators (seam_cracks.cpp).
    if (spec.coupling.exact && !seams_[i].cut) close_onto_shared_space(i, dt);
    const coupling::Interface& c = seams_[i].cut ? *seams_[i].cut : spec.coupling;
    const shell::ShellPatch& leader = patches_[static_cast<size_t>(c.leader_patch)];
    shell::ShellPatch& follower = patches_[static_cast<size_t>(c.follower_patch)];
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
    correct_near_seam(static_cast<size_t>(c.follower_patch), rows, target, released, spec.follower_neighbours, dt);
    for (size_t k = 0; k < rows.size(); ++k)  // the coupled rows sit exactly on their targets
      if (!released[k]) {
        follower.x[static_cast<size_t>(rows[k])] = target[k];
        follower.v[static_cast<size_t>(rows[k])] = target_v[k];
      }
  }
  // Where seams meet at a patch corner, a row-1 (C0) point of one seam can be a row-2 (C1) point of
  // another, and the later seam would open the earlier one. Closure wins: every seam's row 1 is placed
  // once more, in order, from its leader's final state.
  for (size_t i = 0; i < scene_.interfaces.size(); ++i) {
    const InterfaceSpec& spec = scene_.interfaces[i];
    if (!spec.coupled || !seams_[i].shares_points) continue;
    const coupling::Interface& c = seams_[i].cut ? *seams_[i].cut : spec.coupling;
    const shell::ShellPatch& leader = patches_[static_cast<size_t>(c.leader_patch)];
    shell::ShellPatch& follower = patches_[static_cast<size_t>(c.follower_patch)];
    const std::vector<Eigen::Vector3d> target = c.follower_positions(leader.x);
    const std::vector<Eigen::Vector3d> target_v = c.follower_positions(leader.v);
    for (size_t k = 0; k < c.follower_row1.size(); ++k)
      if (!seams_[i].released[k]) {
        follower.x[static_cast<size_t>(c.follower_row1[k])] = target[k];
        if (spec.momentum_correction) follower.v[static_cast<size_t>(c.follower_row1[k])] = target_v[k];
      }
  }
}

}  // namespace shellfrac::sim
