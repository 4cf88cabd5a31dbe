#pragma once
// The per-particle loops of SolidGrid's transfers (p2g scatter, g2p gather), compiled once for the build's
// baseline instruction set (solid_transfer_generic.cpp) and, on x86-64, once more for AVX2 with FMA
// (solid_transfer_avx2.cpp); solid_grid.cpp picks one at run time and runs it over ranges of particles
// inside its own TBB loops. Internal to the brittle library.
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

struct TransferKernels {
  ScatterKernel scatter;
  GatherKernel gather;
  const char* isa;
};

const TransferKernels& transfer_kernels_generic();
#if defined(SHELLFRAC_BRITTLE_AVX2)
const TransferKernels& transfer_kernels_avx2();
#endif

}  // namespace shellfrac::brittle::detail
