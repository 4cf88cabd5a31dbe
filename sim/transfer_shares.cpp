#include "sim/transfer_shares.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <stdexcept>

namespace shellfrac::sim {

void TransferShares::attach(World& world, const scene::Model& model) {
  // Control points a seam sets or corrects after g2p (both rows on either side and the neighbours of the
  // momentum correction, thesis Eq. 4.29-4.34): their velocities change outside the grid.
  seam_held_.assign(world.num_shells(), {});
  for (size_t i = 0; i < world.num_shells(); ++i) seam_held_[i].assign(world.shell(i).num_control_points(), 0);
  for (const scene::model::InterfaceSpec& spec : model.interfaces) {
    if (!spec.coupled) continue;
    const coupling::Interface& c = spec.coupling;
    auto mark = [&](int patch, const std::vector<int>& points) {
      for (int k : points) seam_held_[static_cast<size_t>(patch)][static_cast<size_t>(k)] = 1;
    };
    for (const auto* rows : {&c.leader_row1, &c.leader_row2, &spec.leader_neighbours}) mark(c.leader_patch, *rows);
    for (const auto* rows : {&c.follower_row1, &c.follower_row2, &spec.follower_neighbours}) mark(c.follower_patch, *rows);
  }
  pic_shell_.assign(world.num_shells(), 0);
  turns_.assign(world.num_shells(), 0);
  while_damaged_.assign(world.num_shells(), 0);
  turned_.assign(world.num_shells(), 0);
  where_damaged_.assign(world.num_shells(), 0);
  damaged_control_.assign(world.num_shells(), {});
  damaged_shear_.assign(world.num_shells(), {});
  for (size_t i = 0; i < world.num_shells() && i < model.shells.size(); ++i) {
    pic_shell_[i] = !model.grid.adaptive_shell(model.shells[i]);
    turns_[i] = model.grid.turns_once_damaged(model.shells[i]);
    while_damaged_[i] = model.grid.pic_while_damaged(model.shells[i]);
    where_damaged_[i] = model.grid.pic_where_damaged(model.shells[i]);
  }
  turn_to_pic_ = model.grid.cracking != scene::model::GridSettings::CrackingShells::AdaptiveThenApic;
  damaged_rigid_ = model.grid.cracking == scene::model::GridSettings::CrackingShells::RpicWhileDamaged;
  // Shells joined by coupled seams, directly or through others, share one group (the smallest index).
  seam_group_.resize(world.num_shells());
  for (size_t i = 0; i < seam_group_.size(); ++i) seam_group_[i] = i;
  for (bool changed = true; changed;) {
    changed = false;
    for (const scene::model::InterfaceSpec& spec : model.interfaces) {
      if (!spec.coupled) continue;
      size_t& a = seam_group_[static_cast<size_t>(spec.coupling.leader_patch)];
      size_t& b = seam_group_[static_cast<size_t>(spec.coupling.follower_patch)];
      if (a == b) continue;
      a = b = std::min(a, b);
      changed = true;
    }
  }
  control_.resize(world.num_shells());
  shear_.resize(world.num_shells());
  solid_.resize(world.num_solids());
  for (size_t i = 0; i < world.num_shells(); ++i) {
    control_[i].assign(world.shell(i).num_control_points(), 0.0);
    shear_[i].assign(world.shell(i).shear.x.size(), 0.0);
    world.particle_sets()[world.control_set(i)].flip_share = control_[i].data();
    world.particle_sets()[world.shear_set(i)].flip_share = shear_[i].data();
  }
  for (size_t s = 0; s < world.particle_sets().size(); ++s) {
    const SetRef& r = world.set(s);
    if (r.kind != SetKind::SolidParticles) continue;
    solid_[r.body].assign(world.solid(r.body).size(), 0.0);
    world.particle_sets()[s].flip_share = solid_[r.body].data();
  }
}

namespace {

// Whether any layer point of the patch is damaged (c > 0).
bool damaged(const shell::ShellPatch& patch) {
  const std::vector<double>& damage = patch.damage_values();
  return std::any_of(damage.begin(), damage.end(), [](double c) { return c > 0; });
}

// Whether the patch is damaged, or any point has left the plain NURBS basis (a crack or cut runs through
// its support), or a control point takes part in an MLS basis beside a crack.
bool damaged_or_cracked(const shell::ShellPatch& patch) {
  if (damaged(patch)) return true;
  for (size_t q = 0; q < patch.num_inplane_points(); ++q)
    if (patch.point_level(q) != shell::BasisLevel::Nurbs) return true;
  const std::vector<unsigned char>& near = patch.control_near_crack();
  return std::find(near.begin(), near.end(), 1) != near.end();
}

}  // namespace

void TransferShares::set_pic(World& world, size_t shell, bool pic) {
  turned_[shell] = pic;
  mpm::ParticleSet& control = world.particle_sets()[world.control_set(shell)];
  mpm::ParticleSet& shear = world.particle_sets()[world.shear_set(shell)];
  std::vector<Eigen::Matrix3d>& affine = world.affine(shell);
  std::vector<Eigen::Matrix3d>& shear_affine = world.shear_affine(shell);
  if (damaged_rigid_) {
    // RPIC while damaged: the affine velocities stay and g2p keeps their rotational part only, so they are
    // never stale; the shear particles are RPIC anyway.
    control.rigid_affine = pic;
  } else if (pic) {
    control.affine = nullptr;  // p2g reads no affine velocity and g2p writes none
    shear.affine = nullptr;
  } else if (!affine.empty()) {
    // Back to APIC/affine-FLIP: the affine velocities left from before the PIC spell are stale.
    std::fill(affine.begin(), affine.end(), Eigen::Matrix3d::Zero());
    std::fill(shear_affine.begin(), shear_affine.end(), Eigen::Matrix3d::Zero());
    control.affine = affine.data();
    shear.affine = shear_affine.data();
  }
}

void TransferShares::turn_damaged_shells(World& world) {
  // pic_while_damaged: a seam group is PIC exactly while some member is damaged (a seam between a PIC and
  // an adaptive patch would set velocities that one side's FLIP part does not know).
  group_damaged_.assign(world.num_shells(), 0);
  for (size_t j = 0; j < world.num_shells(); ++j)
    if (while_damaged_[j] && damaged(world.shell(j))) group_damaged_[seam_group_[j]] = 1;
  for (size_t j = 0; j < world.num_shells(); ++j)
    if (while_damaged_[j] && turned_[j] != group_damaged_[seam_group_[j]]) set_pic(world, j, group_damaged_[seam_group_[j]]);
  for (size_t i = 0; i < world.num_shells(); ++i) {
    if (!turns_[i] || turned_[i] || !damaged_or_cracked(world.shell(i))) continue;
    // The shell and every shell a coupled seam ties to it turn together: a seam between a PIC and an
    // adaptive patch would set velocities that one side's FLIP part does not know.
    for (size_t j = 0; j < world.num_shells(); ++j) {
      if (seam_group_[j] != seam_group_[i] || turned_[j] || !turns_[j]) continue;
      if (turn_to_pic_) {
        set_pic(world, j, true);
      } else {
        turned_[j] = 1;  // APIC: the affine velocity stays
      }
    }
  }
}

void TransferShares::update(World& world, double intact, double active, const std::vector<PosedCollider>& colliders,
                            double reach) {
  turn_damaged_shells(world);
  std::vector<Eigen::Isometry3d> to_local;
  for (const auto& [collider, t] : colliders) to_local.push_back(collider->motion.pose(t).inverse());
  auto touches_collider = [&](const Eigen::Vector3d& x) {
    for (size_t c = 0; c < colliders.size(); ++c)
      if (colliders[c].first->shape->signed_distance(to_local[c] * x) <= reach) return true;
    return false;
  };
  for (size_t i = 0; i < world.num_shells(); ++i) {
    const shell::ShellPatch& patch = world.shell(i);
    if (pic_shell_[i]) continue;  // shares stay 0, and the shell has no affine velocity: PIC
    std::vector<double>& control = control_[i];
    if (turned_[i]) {  // every particle of a torn shell takes the same share: no scan of its state
      std::fill(control.begin(), control.end(), active);
      std::fill(shear_[i].begin(), shear_[i].end(), active);
      continue;
    }
    const size_t layers = static_cast<size_t>(patch.num_layers());
    const std::vector<double>& damage = patch.damage_values();
    const std::vector<double>& plastic = patch.plastic_strain_values();
    // A cell is active when any of its layer points is damaged, has flowed plastically, or no longer uses
    // the plain NURBS basis (a crack runs through its support).
    // Every step reads every layer point (480K on a 100 x 100 sheet), so cells are scanned in parallel;
    // a cell's points are contiguous (ShellPatch::cell_of).
    cell_active_.assign(patch.num_cells(), 0);
    const size_t per_cell = patch.num_cells() ? patch.num_inplane_points() / patch.num_cells() : 0;
    if (per_cell * patch.num_cells() != patch.num_inplane_points() || (per_cell && patch.cell_of(per_cell - 1) != 0))
      throw std::logic_error("TransferShares: a patch's quadrature points are not grouped by cell");
    // 2: some layer point is damaged; 1: cut or plastic; 0: neither. Branch-free "any" over the cell's
    // contiguous layer values, so the compiler can vectorise the scan.
    const std::vector<unsigned char>& cut_cells = patch.cut_cells();
    const size_t per_cell_values = per_cell * layers;
    auto any_positive = [per_cell_values](const std::vector<double>& values, size_t c) {
      if (values.empty()) return false;
      const double* v = values.data() + c * per_cell_values;
      bool any = false;
      for (size_t k = 0; k < per_cell_values; ++k) any |= v[k] > 0;
      return any;
    };
    tbb::parallel_for(tbb::blocked_range<size_t>(0, patch.num_cells(), 64), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t c = r.begin(); c != r.end(); ++c)
        cell_active_[c] = any_positive(damage, c) ? 2 : (cut_cells[c] || any_positive(plastic, c)) ? 1 : 0;
    });
    const std::vector<unsigned char>& control_near = patch.control_near_crack();
    tbb::parallel_for(tbb::blocked_range<size_t>(0, control.size(), 256), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k)
        control[k] = control_near[k] || seam_held_[i][k] || touches_collider(patch.x[k]) ? active : intact;
    });
    const int support = patch.support_size();
    const bool local = where_damaged_[i];
    std::vector<int>& damaged_control = damaged_control_[i];
    std::vector<int>& damaged_shear = damaged_shear_[i];
    damaged_control.clear();
    damaged_shear.clear();
    for (size_t c = 0; c < patch.num_cells(); ++c) {
      if (!cell_active_[c]) continue;
      const int* ids = patch.support(c);
      for (int j = 0; j < support; ++j) control[static_cast<size_t>(ids[j])] = active;
      if (local && cell_active_[c] == 2) {
        damaged_control.insert(damaged_control.end(), ids, ids + support);
        damaged_shear.push_back(static_cast<int>(c));
      }
    }
    // A control point lies in the support of up to (p + 1)^2 damaged cells: list it once.
    std::sort(damaged_control.begin(), damaged_control.end());
    damaged_control.erase(std::unique(damaged_control.begin(), damaged_control.end()), damaged_control.end());
    std::fill(shear_[i].begin(), shear_[i].end(), active);
  }
  for (std::vector<double>& s : solid_) std::fill(s.begin(), s.end(), active);
}

void TransferShares::drop_damaged_affine(World& world) const {
  for (size_t i = 0; i < damaged_control_.size(); ++i) {
    std::vector<Eigen::Matrix3d>& affine = world.affine(i);
    std::vector<Eigen::Matrix3d>& shear_affine = world.shear_affine(i);
    if (!affine.empty())
      for (int k : damaged_control_[i]) affine[static_cast<size_t>(k)].setZero();
    if (!shear_affine.empty())
      for (int c : damaged_shear_[i]) shear_affine[static_cast<size_t>(c)].setZero();
  }
}

}  // namespace shellfrac::sim
