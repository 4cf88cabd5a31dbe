#pragma once
// The crack side of a running scene (thesis sec. 4.4-4.7): per shell the consistent crack graph
// (prescribed cuts and cracks extracted from the damage history), the MLS settings of the bases near it,
// and per step the phantom-node partition of the grid with its visibility cache.
#include <Eigen/Core>
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "crack2d/consistent_extraction.hpp"
#include "mpm/partition_memo.hpp"
#include "mpm/phantom_nodes.hpp"
#include "mpm/sparse_grid.hpp"
#include "scene/model.hpp"
#include "shell/mls_basis.hpp"
#include "sim/crack_counters.hpp"
#include "sim/world.hpp"

namespace shellfrac::sim {

class SeamSystem;

// The crack machinery's counters over a run, and where the first failure of each kind happened.
struct CrackStats : CrackCounters {
  std::string first_mls_failure;
  std::string first_sliver;        // the first point that fell into a piece too small for a basis
};

class CrackSystem {
 public:
  // The crack graphs of the shells that can crack, with their prescribed cuts and the MLS bases those
  // cuts require (the strengths of the damage law are set before, sim/fracture_setup.hpp). Throws
  // SceneError for a cut that cannot be placed.
  CrackSystem(const scene::Model& model, World& world);
  ~CrackSystem();
  CrackSystem(const CrackSystem&) = delete;
  CrackSystem& operator=(const CrackSystem&) = delete;

  bool any() const;  // some shell can crack
  // Crack graph of shell i, or null when the shell cannot crack.
  const crack2d::CrackGraph* graph(size_t shell) const { return cracks_[shell] ? &cracks_[shell]->graph() : nullptr; }

  // Extends every fracturing shell's crack graph from its damage history (thesis sec. 4.4.2) and
  // rebuilds the bases the new segments touch (sec. 4.6). Returns true when any graph gained edges.
  bool extract(World& world);
  // Adds a straight cut to shell i (a crack continued across a seam) and rebuilds the bases it touches.
  // Returns false when the cut is degenerate (nothing is added).
  bool add_cut(World& world, size_t shell, const Eigen::Vector2d& from, const Eigen::Vector2d& to);

  // Splits the grid nodes near cracks into one copy per fragment side (thesis sec. 4.7.1): particles of one
  // shell share a copy when the parameter segment between them crosses no crack; coupled patches are one
  // body through their seams (`seams`); a solid is one body.
  void partition(const World& world, mpm::SparseGrid& grid, const SeamSystem& seams);
  const mpm::PhantomLayout& phantoms() const { return phantoms_; }
  bool has_phantoms() const { return !phantoms_.copy_parent.empty(); }

  const CrackStats& stats() const { return stats_; }
  // Counts a crack continued across a coupled seam (SeamSystem) and one step's phantom contact.
  void count_seam_continuation() { ++stats_.seam_continuations; }
  void count_contact(size_t pairs_resolved, double residual) {
    stats_.contact_pairs += pairs_resolved;
    stats_.max_contact_residual = std::max(stats_.max_contact_residual, residual);
  }
  // Recounts crack_segments, mls_points and mls_failures from the current state.
  void count_state(const World& world);

 private:
  // Notes the update's first failures and refreshes the shell's control-point masses (mass scaling).
  void record_update(World& world, size_t shell, const shell::CrackUpdate& u);

  std::vector<std::unique_ptr<crack2d::ConsistentCrackExtractor>> cracks_;  // per shell, null if it cannot crack
  shell::MlsSettings mls_settings_;
  bool phantom_nodes_ = true;  // false: one velocity field (comparison runs)
  std::vector<size_t> damaged_count_;  // per shell: fully damaged points at the last extraction
  std::vector<unsigned char> coupled_patch_;  // per shell: on a coupled seam (one body with its neighbours)
  mpm::PhantomLayout phantoms_;
  // Visibility between particle pairs depends only on their parameter coordinates and the crack, so it
  // is cached across steps (per thread) and dropped when any crack grows.
  struct VisibilityCache;
  std::unique_ptr<VisibilityCache> visibility_;
  // What the last partition found (its layout, its nodes' components); cleared with the visibility cache.
  mpm::PartitionMemo partition_memo_;
  CrackStats stats_;
};

}  // namespace shellfrac::sim
