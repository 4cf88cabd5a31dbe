#include "brittle/breakage_order.hpp"

#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <numeric>
#include <optional>
#include <queue>
#include <tuple>

#include "brittle/crack_grid.hpp"
#include "brittle/errors.hpp"
#include "brittle/strength.hpp"
#include "brittle/voronoi.hpp"
#include "mpm/bspline_weights.hpp"

namespace shellfrac::brittle {

int count_pieces(const std::vector<size_t>& points_in_region, double min_share) {
  const size_t total = std::accumulate(points_in_region.begin(), points_in_region.end(), size_t{0});
  int n = 0;
  for (size_t c : points_in_region) n += (c > 0 && static_cast<double>(c) >= min_share * static_cast<double>(total)) ? 1 : 0;
  return n;
}

void merge_small_regions(const VoronoiDiagram& d, Regions& r, const std::vector<size_t>& points_in_region, double min_share) {
  const size_t R = static_cast<size_t>(r.count);
  if (R < 2) return;
  // Shared face area between regions (all faces between different regions are crack faces).
  std::vector<std::map<int, double>> shared(R);
  for (const VoronoiFace& f : d.faces) {
    if (f.wall()) continue;
    const int a = r.cell_region[static_cast<size_t>(f.cell_a)], b = r.cell_region[static_cast<size_t>(f.cell_b)];
    if (a == b) continue;
    shared[static_cast<size_t>(a)][b] += f.area;
    shared[static_cast<size_t>(b)][a] += f.area;
  }
  std::vector<size_t> count = points_in_region;
  const double total = static_cast<double>(std::accumulate(count.begin(), count.end(), size_t{0}));
  const double need = min_share * total;
  std::vector<int> into(R);
  std::iota(into.begin(), into.end(), 0);
  std::vector<char> alive(R, 1);
  for (;;) {
    // The smallest live region under the share that has a neighbour.
    int small = -1;
    for (size_t i = 0; i < R; ++i)
      if (alive[i] && static_cast<double>(count[i]) < need && !shared[i].empty() &&
          (small < 0 || count[i] < count[static_cast<size_t>(small)]))
        small = static_cast<int>(i);
    if (small < 0) break;
    const size_t s = static_cast<size_t>(small);
    const auto best = std::max_element(shared[s].begin(), shared[s].end(),
                                       [](const auto& x, const auto& y) { return x.second < y.second; });
    const size_t t = static_cast<size_t>(best->first);
    // Move s's adjacency into t; the face between them becomes interior.
    for (const auto& [k, area] : shared[s]) {
      const size_t u = static_cast<size_t>(k);
      shared[u].erase(small);
      if (u == t) continue;
      shared[t][k] += area;
      shared[u][static_cast<int>(t)] += area;
    }
    shared[s].clear();
    count[t] += count[s];
    alive[s] = 0;
    into[s] = static_cast<int>(t);
  }
  auto root = [&](int i) {
    while (into[static_cast<size_t>(i)] != i) i = into[static_cast<size_t>(i)];
    return i;
  };
  std::vector<int> renumber(R, -1);
  int next = 0;
  for (int& c : r.cell_region) {
    int& id = renumber[static_cast<size_t>(root(c))];
    if (id < 0) id = next++;
    c = id;
  }
  r.count = next;
}

int split_regions_at_empty_cells(const VoronoiDiagram& d, const std::vector<char>& crack_face, Regions& r,
                                 const std::vector<Vec3>& points) {
  const size_t n = d.num_cells();
  if (n == 0 || points.empty()) return 0;
  std::vector<char> held(n, 0);
  const SiteLocator locate(d);
  for (const Vec3& x : points) {
    const int c = locate.cell_of(x);
    if (c >= 0) held[static_cast<size_t>(c)] = 1;
  }
  std::vector<int> part(n, -1);
  int parts = 0;
  std::deque<int> queue;
  // Flood from the queued cells (only into cells holding points when `held_only`).
  auto flood = [&](bool held_only) {
    flood_cells(d, crack_face, part, queue, [&](int o) { return !held_only || held[static_cast<size_t>(o)]; });
  };
  for (size_t c = 0; c < n; ++c)
    if (held[c] && part[c] < 0) {
      part[c] = parts++;
      queue.push_back(static_cast<int>(c));
      flood(true);
    }
  for (size_t c = 0; c < n; ++c)
    if (part[c] >= 0) queue.push_back(static_cast<int>(c));
  flood(false);
  for (size_t c = 0; c < n; ++c)
    if (part[c] < 0) {  // a region without points
      part[c] = parts++;
      queue.push_back(static_cast<int>(c));
      flood(false);
    }
  // Renumber by lowest cell.
  std::vector<int> renumber(static_cast<size_t>(parts), -1);
  int next = 0;
  for (size_t c = 0; c < n; ++c) {
    int& id = renumber[static_cast<size_t>(part[c])];
    if (id < 0) id = next++;
    r.cell_region[c] = id;
  }
  const int added = next - r.count;
  r.count = next;
  return added;
}

namespace {

// The damage times on a box of grid nodes of spacing h_v (thesis Eq. 3.13).
struct DamageTimeGrid {
  double h = 0;
  Eigen::Vector3i base_lo, dims;
  std::vector<double> weight, tau;  // per node; weight 0: no particle reaches it
  std::vector<size_t> active;       // nodes with weight, in index order

  size_t size() const { return weight.size(); }
  long index(int i, int j, int k) const {
    if (i < 0 || j < 0 || k < 0 || i >= dims.x() || j >= dims.y() || k >= dims.z()) return -1;
    return i + static_cast<long>(dims.x()) * (j + static_cast<long>(dims.y()) * k);
  }
  Eigen::Vector3i coords(size_t m) const {
    const long sx = dims.x(), sxy = static_cast<long>(dims.x()) * dims.y(), i = static_cast<long>(m);
    return Eigen::Vector3i(static_cast<int>(i % sx), static_cast<int>((i / sx) % dims.y()), static_cast<int>(i / sxy));
  }
  Vec3 position(size_t m) const { return (coords(m) + base_lo).cast<double>() * h; }
  // f(j) for the grid nodes j among the 26 neighbours of node m (and m itself) that lie on the grid.
  template <class F>
  void for_neighbours(size_t m, F&& f) const {
    const Eigen::Vector3i c = coords(m);
    for (int dz = -1; dz <= 1; ++dz)
      for (int dy = -1; dy <= 1; ++dy)
        for (int dx = -1; dx <= 1; ++dx) {
          const long j = index(c.x() + dx, c.y() + dy, c.z() + dz);
          if (j >= 0) f(static_cast<size_t>(j));
        }
  }
};

// thesis Eq. 3.13: tau_i = sum_p w_ip tau_p / sum_p w_ip, with intact particles at `never`.
DamageTimeGrid damage_time_grid(const std::vector<Vec3>& rest, const std::vector<ParticleDamage>& damage,
                                const CrackGridOptions& o, double never) {
  DamageTimeGrid g;
  g.h = o.spacing;
  Vec3 lo = rest.front(), hi = rest.front();
  for (const Vec3& x : rest) {
    lo = lo.cwiseMin(x);
    hi = hi.cwiseMax(x);
  }
  const double bytes = CrackGrid::memory_estimate(lo, hi, g.h);
  if (bytes > static_cast<double>(o.memory_limit))
    throw InputError("damage-time crack: h_v = " + std::to_string(g.h) + " m needs about " + std::to_string(bytes / 1e9) +
                     " GB, more than the memory limit");
  const double inv_h = 1.0 / g.h;
  for (int a = 0; a < 3; ++a) {
    g.base_lo[a] = static_cast<int>(std::floor(lo[a] * inv_h - 0.5)) - 1;
    g.dims[a] = static_cast<int>(std::floor(hi[a] * inv_h - 0.5)) + 3 - g.base_lo[a] + 1;
  }
  const size_t n = static_cast<size_t>(g.dims.x()) * g.dims.y() * g.dims.z();
  g.weight.assign(n, 0.0);
  g.tau.assign(n, 0.0);
  for (size_t p = 0; p < rest.size(); ++p) {
    const mpm::StencilWeights sw = mpm::stencil_weights(rest[p], inv_h);  // Eq. 2.10
    const int base[3] = {sw.ax[0].base, sw.ax[1].base, sw.ax[2].base};
    const ParticleDamage& d = damage[p];
    const double tp = d.c_his >= o.damage_threshold ? std::max(d.tau, 0.0) : never;
    for (int k = 0; k < 3; ++k)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i) {
          const double wt = sw.weight(i, j, k);
          const long id = g.index(base[0] + i - g.base_lo.x(), base[1] + j - g.base_lo.y(), base[2] + k - g.base_lo.z());
          if (!(wt > 0) || id < 0) continue;
          g.weight[static_cast<size_t>(id)] += wt;
          g.tau[static_cast<size_t>(id)] += wt * tp;
        }
  }
  for (size_t m = 0; m < n; ++m)
    if (g.weight[m] > 0) {
      g.tau[m] /= g.weight[m];
      g.active.push_back(m);
    }
  return g;
}

// The watershed of the damage times: each active node's basin. Flooding runs from the latest-breaking
// nodes down (ties by node index: deterministic); basins are union-find sets with the damage time of
// their peak, and a basin whose peak rises less than `depth` above the node that meets it joins the
// higher one.
std::vector<int> watershed(const DamageTimeGrid& g, double depth) {
  std::vector<size_t> order = g.active;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return g.tau[a] != g.tau[b] ? g.tau[a] > g.tau[b] : a < b; });
  std::vector<int> label(g.size(), -1), parent;
  std::vector<double> peak;
  auto root = [&](int b) {
    while (parent[static_cast<size_t>(b)] != b) b = parent[static_cast<size_t>(b)] = parent[static_cast<size_t>(parent[static_cast<size_t>(b)])];
    return b;
  };
  std::vector<int> near;
  for (size_t m : order) {
    near.clear();
    g.for_neighbours(m, [&](size_t j) {
      if (label[j] < 0) return;
      const int r = root(label[j]);
      if (std::find(near.begin(), near.end(), r) == near.end()) near.push_back(r);
    });
    if (near.empty()) {
      label[m] = static_cast<int>(parent.size());
      parent.push_back(label[m]);
      peak.push_back(g.tau[m]);
      continue;
    }
    // Highest peak first.
    std::sort(near.begin(), near.end(), [&](int a, int b) { return peak[static_cast<size_t>(a)] > peak[static_cast<size_t>(b)]; });
    for (size_t k = 1; k < near.size(); ++k)
      if (peak[static_cast<size_t>(near[k])] - g.tau[m] < depth) parent[static_cast<size_t>(near[k])] = near[0];
    label[m] = near[0];
  }
  // The basins' cores (nodes within half the depth of their basin's peak) keep their basin; the rest
  // is flooded again from the cores, latest damage time first and first come first served among equal
  // times, so that a valley of equal times is shared by the basins on either side instead of going to
  // whichever was numbered first.
  using Item = std::tuple<double, long, size_t, int>;  // tau, -order, node, basin
  std::priority_queue<Item> queue;
  long pushed = 0;
  std::vector<int> basin_of(g.size(), -1);
  for (size_t m : order) {
    const int b = root(label[m]);
    if (g.tau[m] >= peak[static_cast<size_t>(b)] - 0.5 * depth) basin_of[m] = b;
  }
  auto push_neighbours = [&](size_t m) {
    g.for_neighbours(m, [&](size_t j) {
      if (g.weight[j] > 0 && basin_of[j] < 0) queue.emplace(g.tau[j], -(pushed++), j, basin_of[m]);
    });
  };
  for (size_t m : order)  // latest first: the order sets the tie-breaks
    if (basin_of[m] >= 0) push_neighbours(m);
  while (!queue.empty()) {
    const size_t m = std::get<2>(queue.top());
    const int b = std::get<3>(queue.top());
    queue.pop();
    if (basin_of[m] >= 0) continue;
    basin_of[m] = b;
    push_neighbours(m);
  }
  return basin_of;
}

}  // namespace

CrackExtraction damage_time_crack(const std::vector<Vec3>& rest, const std::vector<ParticleDamage>& damage,
                                  const CrackExtractionOptions& o, double dynamics, SheetRegions sheets) {
  CrackExtraction out;
  const double h = o.grid.spacing, threshold = o.grid.damage_threshold;
  if (!(h > 0)) throw InputError("damage-time crack: grid spacing h_v must be > 0");
  if (damage.size() != rest.size()) throw InputError("damage-time crack: one damage state per particle is needed");
  // Damage times of the broken particles (a broken particle without a time, set directly, broke first).
  double first = std::numeric_limits<double>::infinity(), last = -first;
  for (const ParticleDamage& d : damage)
    if (d.c_his >= threshold) {
      first = std::min(first, std::max(d.tau, 0.0));
      last = std::max(last, std::max(d.tau, 0.0));
    }
  if (rest.empty() || !std::isfinite(first)) return out;
  // Intact particles count as breaking one span after the last broken one (a flat span of 0: 1).
  const double span = last > first ? last - first : 1.0;
  const double never = last + span;
  const DamageTimeGrid g = damage_time_grid(rest, damage, o.grid, never);
  const std::vector<int> basin_of = watershed(g, dynamics * (never - first));

  // One Voronoi site per active node (jittered), labelled by its basin and, with a sheet crack, by the
  // sheets' region it lies in.
  const bool with_sheets = sheets.crack && sheets.regions && !sheets.crack->diagram.sites.empty();
  std::optional<SiteLocator> sheet_cell;
  if (with_sheets) sheet_cell.emplace(sheets.crack->diagram);
  std::map<std::pair<int, int>, int> piece_id;  // (basin, sheets' region) -> label
  std::vector<Vec3> sites;
  std::vector<int> basin;
  for (size_t m : g.active) {
    Vec3 jitter;
    for (int a = 0; a < 3; ++a) jitter[a] = (2.0 * hashed_uniform(o.seed, 3 * m + static_cast<size_t>(a)) - 1.0) * o.site_jitter * h;
    const Vec3 x = g.position(m);
    sites.push_back(x + jitter);
    const int sheet = with_sheets ? sheets.regions->cell_region[static_cast<size_t>(sheet_cell->cell_of(x))] : 0;
    basin.push_back(piece_id.try_emplace({basin_of[m], sheet}, static_cast<int>(piece_id.size())).first->second);
    out.site_node.push_back(static_cast<long>(m));
  }
  Vec3 box_lo = g.base_lo.cast<double>() * h, box_hi = (g.base_lo + g.dims).cast<double>() * h;
  if ((o.cover_lo.array() <= o.cover_hi.array()).all()) {
    box_lo = box_lo.cwiseMin(o.cover_lo - Vec3::Constant(0.5 * h));
    box_hi = box_hi.cwiseMax(o.cover_hi + Vec3::Constant(0.5 * h));
  }
  out.grid_lower = box_lo;
  out.diagram = compute_voronoi(sites, box_lo, box_hi);
  out.crack_face.assign(out.diagram.faces.size(), 0);
  for (size_t f = 0; f < out.diagram.faces.size(); ++f) {
    const VoronoiFace& face = out.diagram.faces[f];
    if (face.wall() || basin[static_cast<size_t>(face.cell_a)] == basin[static_cast<size_t>(face.cell_b)]) continue;
    out.crack_face[f] = 1;
    ++out.interior_faces;
  }
  out.count_V = sites.size();
  return out;
}
}  // namespace shellfrac::brittle
