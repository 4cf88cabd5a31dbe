#pragma once
// The adaptive particle-grid transfer (docs/shell-model.md, "Transfer"): each particle's FLIP share
// is chosen every step from the state of the material it carries.
//  - Intact elastic material keeps the share `intact` (default 1, affine-FLIP): its bending and swinging
//    energy is not dissipated by the transfer, which PIC and APIC do at a rate growing with cell / thickness.
//  - A control point or shear particle whose support holds a damaged or plastically deformed layer point,
//    or that takes part in an MLS basis beside a crack, keeps the share `active` (default 0, APIC). There,
//    velocity components the grid cannot see would otherwise never be damped and grow (pure FLIP diverged in
//    the plastic-dent and mode-I tear tests), and separated fragments would not meet through the grid.
//  - Control points that a coupled seam sets or corrects after g2p take `active`: the seam changes their
//    velocity where the grid cannot see it.
//  - Control points whose stencil may reach a grid node inside a collider take `active`: the collider
//    rewrites those nodes' velocities, and a FLIP share kept the part it removed in the particles (a cloth at
//    rest on a ball kept 100x the kinetic energy of its APIC rest state, and slid off it after 40 s).
//  - Shear particles (Type III) always take `active`: their positions follow the control points (thesis
//    Eq. 4.10), their velocity only carries their mass to the grid, and a FLIP share would let it drift away
//    from the motion it stands for (a clamped plate's support reaction was then 1.3% off its weight).
//    They keep the rotational part of their affine velocity (RPIC, World): without it they were PIC and
//    damped a swinging board's rotation; with the whole affine velocity a free sheet's energy grew 14x in
//    2 s beside affine-FLIP control points.
//  - Solid particles (Type I) take `active`: their Neo-Hookean bulk has no thin-shell bending to keep.
//  - A shell that can crack (fracture material or cuts) runs the same shares as an intact one, APIC beside
//    its cracks and cuts included, and the particles beside damage run PIC (grid.cracking_shells
//    "pic_where_damaged", the default): every control point in the support of a cell holding a damaged
//    layer point (c > 0), and that cell's shear particle, take share 0 and lose their affine velocity
//    after each g2p. A damaged particle's own kept affine velocity (even its rotation alone, RPIC) draws
//    fully damaged flaps and opening tips out; PIC's averaging does not (docs/shell-model.md, "Transfer").
//    "pic_while_damaged" runs the whole shell, and its seam group, as PIC while any point is damaged;
//    "rpic_while_damaged" keeps the rotational part of the affine velocity in that spell instead;
//    "adaptive_then_pic" / "adaptive_then_apic" turn a shell for good at its first damage or crack,
//    "adaptive" keeps the adaptive shares anyway, "pic" runs such shells as PIC throughout.
// The shares differ between particles, so the grid's g2p restores exact linear momentum (mpm/sparse_grid.cpp).
#include <utility>
#include <vector>

#include "mpm/colliders.hpp"
#include "sim/world.hpp"

namespace shellfrac::sim {

class TransferShares {
 public:
  // Points the world's particle sets at per-particle share arrays.
  void attach(World& world, const scene::Model& model);
  // Rewrites every share from the current damage, plastic strain and crack state.
  // A shell that turns to PIC loses its affine velocity here, hence the writable world.
  // Control points within `reach` of a collider take `active` (the stencil's reach: a node inside the
  // collider may be in it); each collider comes with the time to evaluate its pose at.
  using PosedCollider = std::pair<const mpm::Collider*, double>;
  void update(World& world, double intact, double active, const std::vector<PosedCollider>& colliders, double reach);
  // Whether shell i runs PIC (or APIC) instead of the adaptive shares at this step: for good since damage
  // or a crack appeared on it (GridSettings::turns_once_damaged), or while it is damaged
  // (GridSettings::pic_while_damaged).
  bool turned(size_t shell) const { return shell < turned_.size() && turned_[shell]; }
  // After g2p, under GridSettings::pic_where_damaged: drops the affine velocity of the particles update()
  // found next to damage, so that the next p2g sees them as PIC.
  void drop_damaged_affine(World& world) const;

 private:
  // Turns every shell that may leave the adaptive shares, and is damaged or cracked, with its seam group;
  // turns pic_while_damaged shells to PIC and back as their seam group's damage comes and goes.
  void turn_damaged_shells(World& world);
  void set_pic(World& world, size_t shell, bool pic);

  std::vector<std::vector<double>> control_, shear_, solid_;
  std::vector<unsigned char> pic_shell_;  // per shell: can crack, runs PIC (GridSettings::adaptive_shell)
  std::vector<unsigned char> turns_;      // per shell: leaves the adaptive shares once damaged
  std::vector<unsigned char> while_damaged_;  // per shell: runs PIC while its seam group is damaged
  bool turn_to_pic_ = true;               // ... for PIC (else APIC)
  bool damaged_rigid_ = false;            // while damaged: RPIC instead of PIC (rpic_while_damaged)
  std::vector<unsigned char> turned_;     // per shell: runs PIC/APIC now (turns_: for good)
  std::vector<unsigned char> where_damaged_;  // per shell: PIC only next to its damage (pic_where_damaged)
  // Per shell, found by update(): control points and shear particles (cells) next to damage.
  std::vector<std::vector<int>> damaged_control_, damaged_shear_;
  std::vector<size_t> seam_group_;        // per shell: the shells tied to it by coupled seams share a value
  std::vector<std::vector<unsigned char>> seam_held_;  // per shell and control point: set by a seam
  std::vector<unsigned char> group_damaged_;  // scratch, per seam group (its smallest shell index)
  std::vector<unsigned char> cell_active_;  // scratch, per cell of the shell being updated (2: damaged)
};

}  // namespace shellfrac::sim
