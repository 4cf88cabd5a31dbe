#include "crack2d/damage_closing.hpp"

#include <algorithm>

namespace shellfrac::crack2d {

namespace {

// Closing = erosion of the dilation: a sample is in the closed set when every sample within r of it has
// a damaged sample within r (the disc around it lies inside the dilated set, as far as samples show).
void close_in_place(const SampleNeighbours& disc, std::vector<unsigned char>& flags, const std::vector<char>& at_edge) {
  const size_t n = flags.size();
  std::vector<unsigned char> dilated(n, 0);
  for (size_t j = 0; j < n; ++j)
    if (flags[j]) disc.for_each(j, [&](int i) { dilated[i] = 1; });
  std::vector<unsigned char> closed = flags;
  for (size_t i = 0; i < n; ++i) {
    if (flags[i] || !dilated[i] || at_edge[i]) continue;
    bool inside = true;
    disc.for_each(i, [&](int k) { inside = inside && dilated[k] != 0; });
    if (inside) closed[i] = 1;
  }
  flags.swap(closed);
}

// Intact groups of at most max_pocket samples become damaged. state: 0 unvisited, 1 part of a larger
// group, 2 filled.
void fill_pockets(const SampleNeighbours& adjacency, std::vector<unsigned char>& flags, size_t max_pocket,
                  const std::vector<char>& at_edge) {
  const size_t n = flags.size();
  std::vector<unsigned char> state(n, 0);
  std::vector<int> group, stack;
  for (size_t s = 0; s < n; ++s) {
    if (flags[s] || state[s]) continue;
    group.assign(1, static_cast<int>(s));
    stack.assign(1, static_cast<int>(s));
    state[s] = 3;  // in the current search
    bool large = false;
    while (!stack.empty() && !large) {
      const int i = stack.back();
      stack.pop_back();
      adjacency.for_each(i, [&](int k) {
        if (large || flags[k]) return;
        if (state[k] == 1) {
          large = true;
          return;
        }
        if (state[k] != 0) return;
        state[k] = 3;
        group.push_back(k);
        stack.push_back(k);
        if (group.size() > max_pocket) large = true;
      });
    }
    for (int i : group) large = large || at_edge[i];  // a patch at the edge is no pocket
    for (int i : group) state[i] = large ? 1 : 2;
    if (!large)
      for (int i : group) flags[i] = 1;
  }
}

}  // namespace

std::vector<unsigned char> close_damage(const std::vector<unsigned char>& damaged, const SampleNeighbours* disc,
                                        const SampleNeighbours& adjacency, size_t max_pocket,
                                        const std::vector<char>& at_edge) {
  std::vector<unsigned char> flags(damaged.size());
  bool any = false;
  for (size_t i = 0; i < damaged.size(); ++i) {
    flags[i] = damaged[i] ? 1 : 0;
    any = any || flags[i];
  }
  if (!any) return flags;
  if (disc) close_in_place(*disc, flags, at_edge);
  if (max_pocket > 0) fill_pockets(adjacency, flags, max_pocket, at_edge);
  return flags;
}

}  // namespace shellfrac::crack2d
