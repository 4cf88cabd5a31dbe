#pragma once
// The bases of the points a crack cut off from part of their NURBS support (thesis sec. 4.6, docs/mls.md):
// per point a slot with its fallback basis, the census of levels, the crack portals for fragment paths,
// and which control points, shear particles and cells a crack touches.
#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "crack2d/crack_index.hpp"
#include "crack2d/crack_paths.hpp"
#include "shell/basis_chain.hpp"
#include "shell/kinematics.hpp"
#include "shell/type4_kernel.hpp"

namespace shellfrac::shell {

// Which basis every point of a patch uses (shell/basis_chain.hpp, docs/mls.md "Fallback chain").
struct BasisCensus {
  std::array<size_t, kNumBasisLevels> points{};  // in-plane quadrature points per BasisLevel
  std::array<size_t, kNumBasisLevels> shear{};   // shear particles per BasisLevel
  size_t nudged = 0;         // points (either kind) that lay exactly on a crack line
  size_t membrane_only = 0;  // in-plane points with a linear basis: membrane stress, no bending
  // Points left without a basis although their fragment spans a plane (the chain failed; they are
  // treated as Rigid). Material without a basis: 0 unless something is wrong.
  size_t failures = 0;
  // Material of the in-plane points at levels Rigid and Removed: it carries no stress. Area = sum V_q /
  // thickness, mass = density * sum V_q. Its mass is not lost: it was lumped onto control points and
  // shear particles when the patch was built and stays there.
  double rigid_area = 0, rigid_mass = 0;
  double removed_area = 0, removed_mass = 0;
  size_t slivers() const { return points[static_cast<size_t>(BasisLevel::Rigid)] + points[static_cast<size_t>(BasisLevel::Removed)]; }
};

// What one crack update changed (thesis sec. 4.6: bases are rebuilt only where new segments touch).
struct CrackUpdate {
  size_t examined = 0;     // points whose support new crack segments touch
  size_t mls_points = 0;   // in-plane points with an MLS basis after the update (levels Quadratic..Fragment)
  size_t mls_shear = 0;    // shear particles with an MLS basis after the update
  size_t failures = 0;     // census.failures: material without a basis (0 unless the chain failed)
  std::string first_failure;  // the first point of this update the chain failed for, with the reason
  std::string first_sliver;   // the first point of this update that became Rigid or Removed
  BasisCensus census;      // the whole patch after the update
};

// The fallback basis of one point (stride kBasisStride: R, R_1, R_2, R_11, R_12, R_22 per support control
// point); the forces on its support control points from the last force pass are ForceGather::slot_force
// from force_offset on, one per support control point.
struct MlsSupport {
  std::vector<int> index;
  std::vector<double> basis;
  size_t force_offset = 0;
  double reach = 1.5;  // half-width in cells of the box whose cracks the basis depends on
  BasisLevel level = BasisLevel::Quadratic;
  int order = 2;                     // 1: linear basis, second derivatives zero (membrane only)
  Vec3 rigid_offset = Vec3::Zero();  // Rigid: reference position minus sum R_k X_k (a translation)
  bool nudged = false;               // the point lay on a crack line (evaluated 1e-9 cells to one side)
  bool chain_failed = false;         // Rigid although its fragment spans a plane (census.failures)
};

struct CrackBases {
  const crack2d::CrackIndex* crack = nullptr;  // the patch's crack graph (owned by the caller)
  BasisChainSettings chain_settings;           // from the last update_crack
  crack2d::CrackPortals portals;               // crack corners for the fragment paths, rebuilt with the crack
  BasisCensus census;
  std::vector<int32_t> point_slot, shear_slot;  // per in-plane point / shear particle: slot, or -1 for NURBS
  std::vector<MlsSupport> slots;
  // Per control point / shear particle: non-zero when it takes part in a fallback basis (the particles
  // whose grid nodes get phantom copies, thesis sec. 4.7.1).
  std::vector<unsigned char> control_near_crack, shear_near_crack;
  std::vector<unsigned char> cut_cells;  // per cell: some in-plane point of it has a fallback basis
  size_t num_mls_points = 0;
};

// Empty slots for a patch without cracks.
CrackBases uncut_bases(size_t num_control_points, size_t num_points, size_t num_cells);

// Rebuilds the near-crack flags and the cut cells from the slots (in-plane points grouped by cell,
// points_per_cell to a cell).
void mark_near_crack(CrackBases& cut, size_t points_per_cell);

// MLS points with stress and curvature, sorted by support size and then by point, kType4Lanes to a batch
// for the batched kernel (the last one padded with inactive lanes). A lane whose support is smaller than
// the batch's n repeats its first control point with zero basis derivatives, which adds exact zeros.
struct MlsLaneBatch {
  int n = 0;
  unsigned active = 0;
  size_t q[kType4Lanes] = {};
  size_t first = 0;  // offset of the batch's lanes in MlsLanes::support (n per lane) and MlsLanes::basis
};

struct MlsLanes {
  std::vector<MlsLaneBatch> batches;
  std::vector<int> support;             // [batch][lane][n]
  std::vector<double> basis;            // [batch][n][5][lane], as BasisLanes::basis
  std::vector<unsigned char> batched;   // per in-plane point: its force comes from `batches`
};

}  // namespace shellfrac::shell
