// The transfer kernels of SolidGrid for the baseline instruction set of the build (SSE2 on x86-64, NEON, ...).
#include <cmath>
#include <algorithm>
#include <cstring>

#include "brittle/solid_transfer.hpp"

namespace shellfrac::brittle::detail {
namespace {
#include "brittle/solid_transfer_impl.hpp"
#include "brittle/phase_field_kernels_impl.hpp"
}  // namespace

const TransferKernels& transfer_kernels_generic() {
  static const TransferKernels k{scatter_kernel, gather_kernel, phase_field_operator_kernel, phase_field_assembly_kernel,
                                     phase_field_gather_kernel, "generic"};
  return k;
}

}  // namespace shellfrac::brittle::detail
