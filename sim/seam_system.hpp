#pragma once
// The coupled seams of a running scene (thesis sec. 4.8): per interface the coupling operators (cut where
// a crack crosses the seam), the optional projection of the leader's rows, and the state the coupling
// stage and the crack continuation share.
#include <Eigen/Core>
#include <optional>
#include <vector>

#include "coupling/interface.hpp"
#include "coupling/row_projection.hpp"
#include "mpm/sparse_grid.hpp"
#include "scene/model.hpp"
#include "sim/world.hpp"

namespace shellfrac::sim {

class CrackSystem;

class SeamSystem {
 public:
  // `model` must outlive the seam system (the simulation owns both).
  SeamSystem(const scene::Model& model, const World& world);

  bool empty() const { return seams_.empty(); }
  // Control-point positions x^n of the coupled patches before this step's advection: the momentum
  // correction transfers with this step's weights (Eq. 4.31). Called in g2p.
  void save_start_positions(const World& world);
  // The coupling stage: leader rows projected (exact closure, or both sides' velocity), follower rows
  // placed from the leader (Eq. 4.29, 4.34) with the momentum correction (Eq. 4.30-4.32).
  void couple(World& world, const mpm::SparseGrid& grid, double dt);
  // After the crack graphs grew: cracks that reach a coupled seam continue into the neighbour patch (as a
  // short cut added through `cracks`), and the operators let go of the follower points they separate.
  void update_cracks(World& world, CrackSystem& cracks);

  // Whether points of two coupled patches are joined through a seam without crossing a crack.
  bool connected(const World& world, size_t patch_a, const Eigen::Vector2d& uv_a, size_t patch_b,
                 const Eigen::Vector2d& uv_b) const;
  // The operators of interface i as they act now (cut where cracks cross the seam).
  const coupling::Interface& operators(size_t i) const;
  // Follower control points of interface i that a crack across the seam has released.
  size_t released_points(size_t i) const;
  // Seam coordinates (leader edge parameter in [0, 1]) where cracks meet the seam of interface i.
  const std::vector<double>& crack_positions(size_t i) const { return seams_[i].cracks; }

 private:
  struct SeamState {
    std::vector<double> leader_along;    // seam coordinate of each leader edge control point
    std::vector<double> follower_along;  // of each follower edge control point (row 1)
    std::vector<double> cracks;          // seam coordinates where a crack of either patch meets the seam
    std::vector<unsigned char> released; // per follower row entry: the crack separated it from its leaders
    std::optional<coupling::Interface> cut;  // the operators with the crack's connections dropped
    bool shares_points = false;  // a row-1 point is also a coupled row point of another seam (corner)
    // The leader rows' projection onto the coupling constraint; none in the thesis's leader-only mode
    // without exact closure.
    std::optional<coupling::RowProjection> projection;
    std::vector<unsigned char> leader_held;  // per stacked leader row point: pinned or set by another seam
    std::vector<int> leader_neighbours;      // of the interface's, those no other seam sets
  };
  void build_projection(const World& world, size_t seam);
  void project_rows(World& world, const mpm::SparseGrid& grid, size_t seam, double dt);
  void correct_near_seam(World& world, const mpm::SparseGrid& grid, size_t patch, const std::vector<int>& rows,
                         const std::vector<Eigen::Vector3d>& target, const std::vector<unsigned char>& released,
                         const std::vector<int>& neighbours, double dt);

  const scene::Model& model_;
  std::vector<SeamState> seams_;
  // The order the coupling stage handles the seams in: a seam whose leader rows another seam sets (a
  // patch that follows on one seam and leads on another) comes after that seam, so that it projects and
  // passes on the rows as they end up.
  std::vector<size_t> order_;
  std::vector<std::vector<Eigen::Vector3d>> start_positions_;  // x^n of coupled patches
  // Per patch: the cells whose shear particle follows a control point the coupling stage sets or
  // corrects; they drop their affine velocity with it.
  std::vector<std::vector<size_t>> shear_near_seam_;
  std::vector<Eigen::Vector3d> node_scratch_;  // momentum correction per grid node, zero between uses
  std::vector<unsigned char> node_touched_;
};

}  // namespace shellfrac::sim
