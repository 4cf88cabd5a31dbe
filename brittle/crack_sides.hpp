#pragma once
#include <vector>

#include "brittle/solid_grid.hpp"
#include "brittle/triangle_index.hpp"

namespace shellfrac::brittle {

// Which side of the crack surface each particle lies on at each of its grid nodes (thesis sec. 3.4.1).
//
// The crack lives in material space, so each particle's crack normal n_p = X_p - X_c^p (X_c^p its closest
// crack point) is found once per crack update with a spatial index (through the closest points of a grid
// of nodes, see set_crack). At every node the thesis compares
// n_p with the node's own normal n_i = x_i - x_c^i; we take n_i from the particle nearest the node (its
// largest weight) instead, so that the test needs no material position of the grid node and holds while
// the solid translates or rotates. Particle p is in field 1 at node i when n_p . n_ref < -1/4 (clearly
// opposite; near a crack front where normals turn it stays in field 0, so material ahead of the front is
// not split). Particles farther than `radius` from the crack keep field 0: with radius >= 3 sqrt(3) h no
// such particle shares a node with a particle across the crack.
class CrackSides {
 public:
  // Threshold on n_p . n_ref below which a particle is on the other side.
  static constexpr double kOppositeCosine = -0.25;

  void clear();
  // crack: triangles in material space; rest: X_p of every particle; spacing: of the lookup grid (the
  // MPM grid spacing h is fine).
  void set_crack(const TriMesh& crack, const std::vector<Vec3>& rest, double radius, double spacing);
  bool active() const { return !near_.empty(); }
  size_t near_count() const { return near_.size(); }

  // Field masks of the near particles for the current positions (after grid.rebuild).
  void classify(const SolidGrid& grid, const Vec3* x);

  const FieldMask* masks() const { return active() ? mask_.data() : nullptr; }
  const int32_t* slots() const { return active() ? slot_.data() : nullptr; }
  const Vec3* normals() const { return active() ? normal_.data() : nullptr; }
  // The field of a point with crack normal n at grid node `index` (for ghost particles): compares n with
  // the node's reference particle, as for particles. 0 where the node has no near particle.
  int field_at(size_t index, const Vec3& n) const;
  // Slot (index into normals()) of particle p, -1 if far.
  int32_t slot(size_t p) const { return active() ? slot_[p] : -1; }

 private:
  std::vector<uint32_t> near_;   // near particles in index order
  std::vector<Vec3> normal_;     // per slot: unit n_p (material space)
  std::vector<int32_t> slot_;    // per particle: slot or -1
  std::vector<FieldMask> mask_;  // per particle
  std::vector<double> best_w_;   // per node scratch: largest weight of a near particle
  std::vector<int32_t> best_slot_;
  std::vector<double> ref_normal_[3];  // per node scratch: n of the reference particle per axis, 0 without one
};

}  // namespace shellfrac::brittle
