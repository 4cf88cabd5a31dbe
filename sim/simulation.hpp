#pragma once
#include <tbb/enumerable_thread_specific.h>

#include <memory>
#include <optional>
#include <unordered_map>
#include <string>
#include <vector>

#include "coupling/row_projection.hpp"
#include "crack2d/consistent_extraction.hpp"
#include "mpm/phantom_nodes.hpp"
#include "mpm/solid_particles.hpp"
#include "mpm/sparse_grid.hpp"
#include "render_mesh/poly_mesh.hpp"
#include "shell/shell_patch.hpp"
#include "sim/scene.hpp"
#include "sim/stage_timer.hpp"

namespace shellfrac::sim {

// Counters of the crack machinery over a run (summary.json metrics.cracks).
struct CrackStats {
  long extractions = 0;            // consistent crack extractions run (all patches)
  size_t subset_violations = 0;    // extractions whose graph did not contain the previous one (must be 0)
  size_t crack_edges = 0;          // segments in all crack graphs now
  size_t mls_points = 0;           // in-plane points with MLS bases now
  size_t mls_failures = 0;         // points whose MLS support stayed singular (dropped)
  std::string first_mls_failure;
  size_t max_split_nodes = 0;      // largest number of grid nodes with phantom copies in one step
  size_t contact_pairs = 0;        // pairwise fragment contacts resolved (Eq. 4.23-4.26), all steps
  double max_contact_residual = 0; // largest approaching velocity left after contact
  size_t seam_continuations = 0;   // cracks continued across a coupled seam into the neighbour patch
};

// A running scene: the Kirchhoff-Love shell patches on a sparse MPM grid (thesis sec. 4.3.2), advanced
// by explicit symplectic Euler through named, timed stages:
//   p2g -> forces -> grid_update -> g2p -> cracks (every k steps)
// Near cracks p2g partitions grid nodes into phantom copies and grid_update resolves contact between
// them (thesis sec. 4.7). The constitutive updates run where their kinematics are at hand: the Type III director update and
// return mapping at the end of g2p, the Type IV plastic return mapping inside the force pass (on the
// trial state of the new positions, before the stress). Coupling and crack extraction join later.
class Simulation {
 public:
  explicit Simulation(const Scene& scene);
  Simulation(const Simulation&) = delete;  // the grid's particle views point into the patches
  Simulation& operator=(const Simulation&) = delete;

  // Largest stable step: cfl times the elastic-wave bound of the stiffest shell on the grid, further
  // limited so that no particle moves more than cfl grid cells per step at the current speeds.
  double stable_dt() const;
  // The elastic-wave part of the bound (without the cfl factor), for reports.
  double elastic_wave_bound() const { return elastic_bound_; }

  // One step of size dt through the stages. Throws NumericalError naming the particle, shell and step.
  void step(double dt);
  // Steps until time t (equal steps no larger than the allowed step), returns the steps taken.
  long advance_to(double t);

  double time() const { return time_; }
  long steps() const { return steps_; }
  double min_dt() const { return min_dt_; }
  double max_dt() const { return max_dt_; }
  double dx() const { return grid_.dx(); }
  const StageTimer& timer() const { return timer_; }
  std::vector<shell::ShellPatch>& patches() { return patches_; }
  const std::vector<shell::ShellPatch>& patches() const { return patches_; }

  size_t num_control_points() const;
  size_t num_quadrature_points() const;
  size_t num_shear_particles() const;
  size_t num_solid_particles() const;
  std::vector<mpm::SolidParticles>& solids() { return solids_; }
  double kinetic_energy() const;
  // Total force the pins exert on shell i (minus the elastic force on its pinned control points).
  const Eigen::Vector3d& pin_reaction(size_t shell) const { return pin_reaction_[shell]; }
  Eigen::Vector3d linear_momentum() const;
  // The render mesh of every shell at the current state (the scene's output resolution).
  std::vector<render_mesh::PolyMesh> render_meshes() const;
  const CrackStats& crack_stats() const { return crack_stats_; }
  // Pieces of material: shell control points joined through their patch's control grid where no crack
  // separates them, and across coupled seams through the coupling operators. A garment torn in two is
  // 2, however many patches each half has; separate, uncoupled shells count once each.
  size_t body_fragments() const;
  // Follower control points of scene interface i that a crack across the seam has released.
  size_t released_seam_points(size_t i) const;
  // Seam coordinates (leader edge parameter in [0, 1]) where cracks meet the seam of interface i.
  const std::vector<double>& seam_cracks(size_t i) const { return seams_[i].cracks; }
  // Crack graph of shell i, or null when the shell cannot crack.
  const crack2d::CrackGraph* crack_graph(size_t shell) const {
    return cracks_[shell] ? &cracks_[shell]->graph() : nullptr;
  }
  // Largest depth by which any render vertex is inside any collider now (0 if none).
  double collider_penetration(const std::vector<render_mesh::PolyMesh>& meshes) const;

 private:
  void stage_p2g();
  void rebuild_grid();
  void stage_forces();
  void stage_grid_update(double dt);
  void stage_g2p(double dt);
  void stage_cracks();
  void stage_coupling(double dt);
  void correct_near_seam(size_t patch, const std::vector<int>& rows, const std::vector<Eigen::Vector3d>& target,
                         const std::vector<unsigned char>& released, const std::vector<int>& neighbours, double dt);
  void build_seam_projection(size_t seam);
  void project_seam_rows(size_t seam, double dt);
  void init_cracks();
  void count_crack_state();  // crack_stats_ counts of the current graphs and MLS points
  void init_seams();
  void update_seam_cracks();
  bool seam_connected(size_t patch_a, const Eigen::Vector2d& uv_a, size_t patch_b, const Eigen::Vector2d& uv_b) const;
  void partition_phantom_nodes();
  void apply_pins(double t_new);
  void check_finite() const;

  Scene scene_;
  std::vector<shell::ShellPatch> patches_;
  std::vector<std::vector<Eigen::Vector3d>> initial_positions_;  // for pins
  std::vector<std::vector<Eigen::Matrix3d>> affine_;              // APIC C_p per control point
  std::vector<std::vector<double>> transfer_mass_;                // control point mass, zero where pinned
  std::vector<Eigen::Vector3d> pin_reaction_;                     // per shell, from the last force stage
  std::vector<mpm::SolidParticles> solids_;
  std::vector<mpm::Collider> colliders_;
  mpm::SparseGrid grid_;
  std::vector<mpm::ParticleSet> sets_;
  StageTimer timer_;
  std::vector<std::unique_ptr<crack2d::ConsistentCrackExtractor>> cracks_;  // per shell, null if it cannot crack
  shell::MlsSettings mls_settings_;
  std::vector<size_t> damaged_count_;  // per shell: fully damaged points at the last extraction
  std::vector<std::vector<Eigen::Vector3d>> start_positions_;  // x^n of coupled patches (momentum correction)
  // Per scene interface: where cracks meet the seam and which coupled follower rows they released.
  struct SeamState {
    std::vector<double> leader_along;    // seam coordinate of each leader edge control point
    std::vector<double> follower_along;  // of each follower edge control point (row 1)
    std::vector<double> cracks;          // seam coordinates where a crack of either patch meets the seam
    std::vector<unsigned char> released; // per follower row entry: the crack separated it from its leaders
    std::optional<coupling::Interface> cut;  // the operators with the crack's connections dropped
    bool shares_points = false;  // a row-1 point is also a coupled row point of another seam (corner)
    // The leader rows' projection onto the coupling constraint (seam_coupling.cpp); none in the thesis's
    // leader-only mode without exact closure.
    std::optional<coupling::RowProjection> projection;
    std::vector<unsigned char> leader_held;  // per stacked leader row point: pinned or set by another seam
    std::vector<int> leader_neighbours;      // of the interface's, those no other seam sets
  };
  std::vector<SeamState> seams_;
  std::vector<Eigen::Vector3d> node_scratch_;  // momentum correction per grid node, zero between uses
  std::vector<unsigned char> node_touched_;
  mpm::PhantomLayout phantoms_;
  // Visibility between particle pairs depends only on their parameter coordinates and the crack, so it
  // is cached across steps (per thread) and dropped when any crack grows.
  using VisibilityCache = std::unordered_map<uint64_t, bool>;
  std::unique_ptr<tbb::enumerable_thread_specific<VisibilityCache>> visibility_cache_;
  size_t visibility_cache_segments_ = 0;
  CrackStats crack_stats_;
  double elastic_bound_ = 0;
  double time_ = 0;
  long steps_ = 0;
  double min_dt_ = 0, max_dt_ = 0;
};

}  // namespace shellfrac::sim
