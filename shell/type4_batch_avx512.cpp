// The batched Type IV kernel compiled for AVX-512 (F, VL, DQ) with FMA: eight-double lanes, a whole batch in
// one pass (shell/simd_lanes.hpp), and 32 vector registers for the jet, the normal derivatives and the four
// accumulated dPsi/dg vectors that live across the layer loop. Picked at run time by type4_force_batch when
// the processor has AVX-512 F, VL and DQ.
#include "shell/type4_kernel.hpp"

namespace shellfrac::shell::detail {
namespace {
#include "shell/type4_batch_impl.hpp"
}  // namespace

void type4_force_batch_avx512(const Type4Data& d, const Type4Batch& batch, Type4BatchResult& out) {
  batch_kernel(d, batch, out);
}

}  // namespace shellfrac::shell::detail
