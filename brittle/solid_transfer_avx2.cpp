// The transfer kernels of SolidGrid compiled for AVX2 with FMA (x86-64 only; solid_grid.cpp picks them at
// run time when the processor has both).
#include <immintrin.h>

#include <cmath>
#include <algorithm>
#include <cstring>

#include "brittle/solid_transfer.hpp"

namespace shellfrac::brittle::detail {
namespace {
#include "brittle/solid_transfer_impl.hpp"
#include "brittle/phase_field_kernels_impl.hpp"
}  // namespace

const TransferKernels& transfer_kernels_avx2() {
  static const TransferKernels k{scatter_kernel, gather_kernel, phase_field_operator_kernel, phase_field_assembly_kernel,
                                     phase_field_gather_kernel, "avx2-fma"};
  return k;
}

}  // namespace shellfrac::brittle::detail
