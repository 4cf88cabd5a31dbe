#pragma once
// The Type IV quadrature points of one patch and their NURBS bases (thesis sec. 4.3.2): laid out once
// when the patch is built and read by every force pass. Only a plastic patch rewrites its rest metrics.
#include <cstddef>
#include <vector>

#include "nurbs/nurbs_surface.hpp"
#include "shell/in_plane_stress.hpp"
#include "shell/mls_basis.hpp"
#include "shell/quadrature.hpp"
#include "shell/type4_kernel.hpp"

namespace shellfrac::shell {

using Vec2 = Eigen::Vector2d;

// Values per support control point in a point's basis: R, R_1, R_2, R_11, R_12, R_22.
inline constexpr int kBasisStride = 6;

struct PatchQuadrature {
  LayerRule layers;                 // through-thickness layers xi_3 and their weights
  int support_size = 0;             // (p + 1)(q + 1) control points per cell
  size_t num_cells = 0, points_per_cell = 0;
  std::vector<int> support;         // cells x support_size control point indices
  std::vector<Vec2> param;          // in-plane points, grouped by cell
  std::vector<Vec2> cell_center;    // parameter centre of each cell
  std::vector<double> basis;        // in-plane points x support x kBasisStride
  std::vector<ReferenceLayer> ref;  // in-plane points x layers: rest metric (rewritten by plasticity)
  std::vector<double> volume;       // in-plane points x layers: V_q (thesis Eq. 4.6)
  ControlGrid control_grid;         // the control points' Greville parameters

  size_t num_layers() const { return layers.xi3.size(); }
  size_t cell_of(size_t q) const { return q / points_per_cell; }
  const int* cell_support(size_t cell) const { return &support[cell * static_cast<size_t>(support_size)]; }
  // V_q summed over the layers of in-plane point q.
  double point_volume(size_t q) const;
};

// Gauss points per non-empty knot span of `reference`, their basis derivatives, and each layer point's rest
// metric and volume. Throws std::invalid_argument for a degree above 7 or a degenerate patch.
PatchQuadrature build_quadrature(const nurbs::NurbsSurface& reference, const LayerRule& layers,
                                 const QuadratureRule& rule);

// The NURBS points' basis derivatives R_1 .. R_22, rest metrics and volumes in the batched kernel's lane
// order (kType4Lanes consecutive points to a batch, the last one padded with zeros), so that the kernel loads
// them instead of gathering per lane.
struct BasisLanes {
  std::vector<double> basis;   // [batch][support][5][lane]
  std::vector<double> ref;     // [batch][layer][g11 g12 g22 1/sqrt_det][lane]
  std::vector<double> volume;  // [batch][layer][lane]
};
BasisLanes lay_out_basis_lanes(const PatchQuadrature& quad);

}  // namespace shellfrac::shell
