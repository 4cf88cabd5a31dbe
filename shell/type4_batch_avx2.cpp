// The batched Type IV kernel compiled for AVX2 with FMA (x86-64 only; picked at run time by
// type4_force_batch when the processor has both).
#include "shell/type4_kernel.hpp"

namespace shellfrac::shell::detail {
namespace {
#include "shell/type4_batch_impl.hpp"
}  // namespace

void type4_force_batch_avx2(const Type4Data& d, const Type4Batch& batch, Type4BatchResult& out) {
  batch_kernel(d, batch, out);
}

}  // namespace shellfrac::shell::detail
