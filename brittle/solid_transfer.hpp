#pragma once
// The per-particle loops of SolidGrid's transfers (p2g scatter, g2p gather) and of the phase field,
// compiled once for the build's baseline instruction set (solid_transfer_generic.cpp) and, on x86-64,
// once more for AVX2 with FMA (solid_transfer_avx2.cpp); solid_grid.cpp picks one at run time, and the
// callers run it over ranges of particles inside their own TBB loops. Internal to the brittle library.
#include <cstddef>
#include <cstdint>

#include "brittle/solid_grid.hpp"

namespace shellfrac::brittle::detail {

// What the kernels need of the grid: raw node arrays and the box. The scatter writes the nodes
// (TransferGrid); the gather only reads them (ConstTransferGrid).
template <class Node, class Real>
struct TransferGridOf {
  Node* field[2] = {nullptr, nullptr};  // field[1] is field[0] on a one-field grid
  Real* normal = nullptr;               // crack normal per node as 4 doubles (x, y, z, unused); null with one field
  long lo[3] = {0, 0, 0};               // integer coordinates of node 0
  long stride_y = 0, stride_z = 0;
  double dx = 0, inv_dx = 0;
};

// p2g of the particles order[begin..end) in that order (thesis Eq. 2.23, 2.24, 3.3-3.5).
using ScatterKernel = void (*)(const TransferGrid& g, const SolidView& s, double dt, const uint32_t* order, size_t begin,
                               size_t end);
// g2p of the particles begin..end (Eq. 2.20, 2.25, 2.26, 2.21).
using GatherKernel = void (*)(const ConstTransferGrid& g, const SolidView& s, double dt, size_t begin, size_t end);

// The phase field's operator (brittle/phase_field_kernels_impl.hpp): node vectors x (read) and y
// (accumulated), the particles' positions (3 doubles each) and volumes, and 4 l0^2 M_c.
struct PhaseFieldOperatorArgs {
  const double* x = nullptr;
  double* y = nullptr;
  const double* position = nullptr;
  const double* volume = nullptr;
  double scale = 0;
  bool mls_gradient = false;
};
// y += H x over the particles order[begin..end), in that order.
using PhaseFieldOperatorKernel = void (*)(const ConstTransferGrid& g, const PhaseFieldOperatorArgs& a,
                                          const uint32_t* order, size_t begin, size_t end);

// Its assembly: node arrays accumulated, the particles' arrays read, and the integrands' factors
// M_ii = V (history_factor Psi^H + mass_constant) w, r_i = V (source_constant + c inv_dt) w,
// H_ii = V stiffness |grad Theta_i|^2.
// `lumped` holds four doubles per node, 32-byte aligned: sum w, sum w c_p, M_ii and r_i (all weighted by
// w, so one vector multiply-add per node adds a particle's share); `precond` gets H_ii.
struct PhaseFieldAssemblyArgs {
  double *lumped = nullptr, *precond = nullptr;
  const double *position = nullptr, *volume = nullptr, *history = nullptr, *c = nullptr;
  double history_factor = 0, mass_constant = 0, source_constant = 0, inv_dt = 0, stiffness = 0;
  bool mls_gradient = false;
};
using PhaseFieldAssemblyKernel = void (*)(const ConstTransferGrid& g, const PhaseFieldAssemblyArgs& a,
                                          const uint32_t* order, size_t begin, size_t end);
// And the update of the particles' c from the node values before (c_old) and after (c_new) a solve.
struct PhaseFieldGatherArgs {
  const double *c_new = nullptr, *c_old = nullptr, *position = nullptr;
  double* c = nullptr;
};
using PhaseFieldGatherKernel = void (*)(const ConstTransferGrid& g, const PhaseFieldGatherArgs& a, size_t begin,
                                        size_t end);

struct TransferKernels {
  ScatterKernel scatter;
  GatherKernel gather;
  PhaseFieldOperatorKernel phase_field_operator;
  PhaseFieldAssemblyKernel phase_field_assembly;
  PhaseFieldGatherKernel phase_field_gather;
  const char* isa;
};

const TransferKernels& transfer_kernels_generic();
#if defined(SHELLFRAC_BRITTLE_AVX2)
const TransferKernels& transfer_kernels_avx2();
#endif

}  // namespace shellfrac::brittle::detail
