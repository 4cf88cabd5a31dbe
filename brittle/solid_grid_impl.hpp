#pragma once
// Template members of SolidGrid (included by solid_grid.hpp).
#include <tbb/parallel_for.h>

namespace shellfrac::brittle {

template <class Fn>
void SolidGrid::for_slabs_coloured(Fn&& fn) const {
  const size_t slabs = slab_offsets_.empty() ? 0 : slab_offsets_.size() - 1;
  for (size_t colour = 0; colour < 2; ++colour) {
    const size_t count = (slabs + 1 - colour) / 2;
    tbb::parallel_for(tbb::blocked_range<size_t>(0, count, 1), [&](const tbb::blocked_range<size_t>& r) {
      for (size_t k = r.begin(); k != r.end(); ++k) fn(2 * k + colour);
    });
  }
}

template <class Fn>
void SolidGrid::for_particles_coloured(Fn&& fn) const {
  for_slabs_coloured([&](size_t slab) {
    for (uint32_t e = slab_offsets_[slab]; e < slab_offsets_[slab + 1]; ++e) fn(slab_order_[e]);
  });
}

}  // namespace shellfrac::brittle
