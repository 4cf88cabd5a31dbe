// The batched Type IV kernel for the baseline instruction set of the build (SSE2 on x86-64, NEON, ...).
#include "shell/type4_kernel.hpp"

namespace shellfrac::shell::detail {
namespace {
#include "shell/type4_batch_impl.hpp"
}  // namespace

void type4_force_batch_generic(const Type4Data& d, const Type4Batch& batch, Type4BatchResult& out) {
  batch_kernel(d, batch, out);
}

}  // namespace shellfrac::shell::detail
