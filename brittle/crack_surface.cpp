#include "brittle/crack_surface.hpp"

#include <algorithm>
#include <deque>
#include <functional>
#include <limits>
#include <map>
#include <queue>
#include <unordered_map>

#include "brittle/point_locator.hpp"
#include "brittle/strength.hpp"
#include "brittle/triangle_index.hpp"

namespace shellfrac::brittle {

namespace {

enum Tag : char { kUntagged = 0, kAdjacent = 1, kOpposite = 2 };
constexpr double kFacingCosine = 0.3;
constexpr double kParallelCosine = 0.3;

// Relative orientation of I cells `from` and `to` through the tags of Algorithm 1 (Algorithm 3): a
// search over (cell, parity) where adjacent tags keep the parity and opposite tags flip it. Algorithm 3
// expands breadth first; we expand by path length (Dijkstra over site distances), because where three
// sheets meet (a Y) the parity around the junction disagrees with the parity straight across, and only
// the geometrically shortest path gives the local answer. Returns 1 if `to` is first reached on the
// opposite side, 0 if on the same side, -1 if not reached within the budget. Answers are cached per
// pair (neighbouring extension cells share their representatives).
class OrientationSearch {
 public:
  OrientationSearch(const VoronoiDiagram& d, const std::vector<char>& tag, const std::vector<char>& is_I, int budget)
      : d_(d), tag_(tag), is_I_(is_I), budget_(budget), best_(2 * d.num_cells(), kUnseen) {}

  int operator()(int from, int to) {
    if (from == to) return 0;
    const auto key = std::make_pair(std::min(from, to), std::max(from, to));
    const auto hit = cache_.find(key);
    if (hit != cache_.end()) return hit->second;
    const int r = search(from, to);
    cache_.emplace(key, r);
    return r;
  }

 private:
  static constexpr double kUnseen = std::numeric_limits<double>::infinity();
  int search(int from, int to) {
    using Item = std::pair<double, long long>;  // (length, 2 cell + parity)
    std::priority_queue<Item, std::vector<Item>, std::greater<Item>> queue;
    auto relax = [&](long long state, double len) {
      if (best_[static_cast<size_t>(state)] <= len) return;
      if (best_[static_cast<size_t>(state)] == kUnseen) touched_.push_back(state);
      best_[static_cast<size_t>(state)] = len;
      queue.emplace(len, state);
    };
    relax(2LL * from, 0.0);
    int result = -1, budget = budget_;
    while (!queue.empty() && budget-- > 0) {
      const auto [len, state] = queue.top();
      queue.pop();
      const int cell = static_cast<int>(state / 2), parity = static_cast<int>(state % 2);
      if (cell == to) {
        result = parity;
        break;
      }
      if (len > best_[static_cast<size_t>(state)]) continue;
      for (int f : d_.cell_faces[static_cast<size_t>(cell)]) {
        const int other = d_.other(f, cell);
        if (other < 0 || !is_I_[static_cast<size_t>(other)] || tag_[static_cast<size_t>(f)] == kUntagged) continue;
        relax(2LL * other + (parity ^ (tag_[static_cast<size_t>(f)] == kOpposite ? 1 : 0)),
              len + (d_.sites[static_cast<size_t>(other)] - d_.sites[static_cast<size_t>(cell)]).norm());
      }
    }
    for (long long s : touched_) best_[static_cast<size_t>(s)] = kUnseen;
    touched_.clear();
    return result;
  }

  const VoronoiDiagram& d_;
  const std::vector<char>& tag_;
  const std::vector<char>& is_I_;
  int budget_;
  std::vector<double> best_;
  std::vector<long long> touched_;
  std::map<std::pair<int, int>, int> cache_;
};

// Sites: V u B' (sec. 3.3.2) without the B' nodes in front of crack exits (see CrackGrid), each moved off
// its node by a hashed jitter so that no four sites are co-spherical and no cells meet in an edge or a
// point only (lattice sites are maximally degenerate). Fills out.site_node and node_cell.
std::vector<Vec3> crack_sites(const CrackGrid& grid, const CrackExtractionOptions& o, CrackExtraction& out,
                              std::vector<long>& node_cell) {
  std::vector<Vec3> sites;
  node_cell.assign(grid.num_nodes(), -1);
  const double h = grid.spacing();
  for (size_t n = 0; n < grid.num_nodes(); ++n) {
    if (!grid.in(n, kSetV | kSetBd) || grid.in(n, kSetBdExit)) continue;
    Vec3 jitter;
    for (int a = 0; a < 3; ++a) jitter[a] = (2.0 * hashed_uniform(o.seed, 3 * n + static_cast<size_t>(a)) - 1.0) * o.site_jitter * h;
    node_cell[n] = static_cast<long>(sites.size());
    sites.push_back(grid.position(n) + jitter);
    out.site_node.push_back(static_cast<long>(n));
  }
  return sites;
}

// The container spans every B' node, the exit nodes left out of the sites included: the regions
// partition the container, and the fragments (region n object) sum to the object only if it covers
// the whole object. Where damage reaches most of the surface (a crushed contact zone, a shattered
// ball) the exit nodes are all of B' on that side, and a box around the sites alone cut the object off.
void container_box(const CrackGrid& grid, const std::vector<Vec3>& sites, const CrackExtractionOptions& o, Vec3& lo,
                   Vec3& hi) {
  lo = sites.front();
  hi = sites.front();
  for (const Vec3& s : sites) {
    lo = lo.cwiseMin(s);
    hi = hi.cwiseMax(s);
  }
  for (size_t n = 0; n < grid.num_nodes(); ++n) {
    if (!grid.in(n, kSetBd)) continue;
    lo = lo.cwiseMin(grid.position(n));
    hi = hi.cwiseMax(grid.position(n));
  }
  if ((o.cover_lo.array() <= o.cover_hi.array()).all()) {
    lo = lo.cwiseMin(o.cover_lo);
    hi = hi.cwiseMax(o.cover_hi);
  }
  lo -= Vec3::Constant(0.5 * grid.spacing());
  hi += Vec3::Constant(0.5 * grid.spacing());
}

// Algorithm 1's test: whether the grid nodes of two cells lie across the fully damaged region.
//
// Deciding "inside the fully damaged region" by interpolating rasterised damage alone misjudges
// oblique and thin bands: the kernel spreads a damaged layer over three or more nodes, so a chord
// between two nodes on the same side of a tilted band can dip into the rasterised interior, and one
// wrong "opposite" tag flips the orientation search below. A pair is opposite when either
//  (a) the particle nearest to the midpoint is fully damaged (the material point there is broken), or
//  (b) the rasterised interior holds the midpoint (trilinear >= 1/2) and the two nodes face each other:
//      the outward normals of the damaged region at them point away from each other (sum of their
//      cosines with the pair direction > 0.3) and not along each other (mutual cosine < 0.3).
// (a) keeps pairs across junctions, where a node's normal belongs to another sheet; (b) keeps pairs
// across thin oblique bands, whose midpoint can miss the one damaged particle layer.
class AcrossDamage {
 public:
  AcrossDamage(const CrackGrid& grid, const std::vector<Vec3>& rest, const std::vector<double>& c_his,
               const std::vector<long>& site_node, double threshold)
      : grid_(grid), particles_(rest), c_his_(c_his), site_node_(site_node), threshold_(threshold) {}

  bool operator()(int a, int b) const {
    const size_t na = static_cast<size_t>(site_node_[static_cast<size_t>(a)]);
    const size_t nb = static_cast<size_t>(site_node_[static_cast<size_t>(b)]);
    // Two nodes around one restored island (CrackGrid) face the same intact clump: the same side, even
    // when the chord between them passes beside a small clump through broken material.
    const int island = grid_.bordering_island(na);
    if (island >= 0 && island == grid_.bordering_island(nb)) return false;
    const Vec3 xa = grid_.position(na), xb = grid_.position(nb), mid = 0.5 * (xa + xb);
    const int p = particles_.nearest(mid);
    if (p >= 0 && c_his_[static_cast<size_t>(p)] >= threshold_) return true;
    if (grid_.interior_fraction(mid) < 0.5) return false;
    const Vec3 ab = (xb - xa).normalized();
    const Vec3 n_a = grid_.damage_normal(na), n_b = grid_.damage_normal(nb);
    return n_a.dot(-ab) + n_b.dot(ab) > kFacingCosine && n_a.dot(n_b) < kParallelCosine;
  }

 private:
  const CrackGrid& grid_;
  const PointLocator particles_;
  const std::vector<double>& c_his_;
  const std::vector<long>& site_node_;
  double threshold_;
};

// What each cell's grid node is: in I, in the extension E (or B' near the damage), in B' near the damage.
struct CellSets {
  std::vector<char> is_I, is_ext, is_outer;
};

// Algorithms 2-3: faces of the extension cells E that separate cells lying on opposite sides of the
// medial surface, judged through their nearest I nodes (Algorithm 2) and the tags (Algorithm 3).
//
// We also orient the cells of B' near the damaged surface (not in the thesis): a B' site just outside
// the exit of a crack has a cell that reaches back into the object on both sides of the crack, which
// would join the fragments. A B' node lies too far from I for Algorithm 2 to be reliable (the nearest I
// can lie across the crack), so it takes the orientation of its nearest node of V (an E or I node just
// inside, on one of the two boundary sheets of the damaged band). Each cell is oriented once, so all
// its faces agree even when its site lies on the crack plane.
void mark_extension_faces(const CrackGrid& grid, const CellSets& cells, const std::vector<char>& tag,
                          const std::vector<long>& node_cell, const AcrossDamage& across_damage,
                          const CrackExtractionOptions& o, CrackExtraction& out) {
  const VoronoiDiagram& d = out.diagram;
  const std::vector<char>& is_I = cells.is_I;
  const std::vector<char>& is_ext = cells.is_ext;
  std::vector<long> nearest(d.num_cells(), -2);  // representative I cell, -1 none, -2 not computed
  auto representative = [&](int c) -> long {
    if (is_I[static_cast<size_t>(c)]) return c;
    long& r = nearest[static_cast<size_t>(c)];
    if (r != -2) return r;
    r = -1;
    long node = static_cast<long>(out.site_node[static_cast<size_t>(c)]);
    if (cells.is_outer[static_cast<size_t>(c)]) node = grid.nearest_in(static_cast<size_t>(node), kSetV);
    if (node >= 0 && !grid.in(static_cast<size_t>(node), kSetI)) node = grid.nearest_in_I(static_cast<size_t>(node));
    if (node >= 0) r = node_cell[static_cast<size_t>(node)];
    return r;
  };
  OrientationSearch orientation(d, tag, is_I, o.orientation_search);
  for (size_t f = 0; f < d.faces.size(); ++f) {
    const VoronoiFace& face = d.faces[f];
    if (face.wall() || out.crack_face[f]) continue;
    const int a = face.cell_a, b = face.cell_b;
    const bool a_ok = is_ext[static_cast<size_t>(a)] || is_I[static_cast<size_t>(a)];
    const bool b_ok = is_ext[static_cast<size_t>(b)] || is_I[static_cast<size_t>(b)];
    if (!a_ok || !b_ok || (is_I[static_cast<size_t>(a)] && is_I[static_cast<size_t>(b)])) continue;
    const long start = representative(a), end = representative(b);
    if (start < 0 || end < 0) continue;
    // The parity of Algorithm 3 cannot tell diagonal sectors of a junction of four sheets apart (two
    // crossings: even), so an even or missing answer is checked once more with the test of Algorithm 1
    // on the two representatives.
    const int side = orientation(static_cast<int>(start), static_cast<int>(end));
    if (side < 0) ++out.undecided_pairs;
    if (side == 1 || (start != end && across_damage(static_cast<int>(start), static_cast<int>(end)))) {
      out.crack_face[f] = 2;
      ++out.extension_faces;
    }
  }
}

}  // namespace

CrackExtraction extract_crack(const std::vector<Vec3>& rest, const std::vector<double>& c_his, const CrackExtractionOptions& o) {
  CrackExtraction out;
  const CrackGrid grid(rest, c_his, o.grid);
  out.count_D = grid.count(kSetD);
  out.count_B = grid.count(kSetB);
  out.count_Bd = grid.count(kSetBd);
  out.count_S = grid.count(kSetS);
  out.count_V = grid.count(kSetV);
  out.count_I = grid.count(kSetI);
  out.count_E = grid.count(kSetE);
  out.count_N = grid.count(kSetN);
  std::vector<long> node_cell;
  const std::vector<Vec3> sites = crack_sites(grid, o, out, node_cell);
  if (sites.empty()) return out;
  Vec3 lo, hi;
  container_box(grid, sites, o, lo, hi);
  out.diagram = compute_voronoi(sites, lo, hi);
  const VoronoiDiagram& d = out.diagram;
  CellSets cells{std::vector<char>(sites.size(), 0), std::vector<char>(sites.size(), 0), std::vector<char>(sites.size(), 0)};
  for (size_t c = 0; c < sites.size(); ++c) {
    const size_t node = static_cast<size_t>(out.site_node[c]);
    cells.is_I[c] = grid.in(node, kSetI);
    cells.is_ext[c] = grid.in(node, kSetE | kSetBdNear);
    cells.is_outer[c] = grid.in(node, kSetBdNear);
  }
  // Algorithm 1: a face between two I cells is a medial (crack) face iff the midpoint of their grid
  // nodes lies inside the fully damaged region; the tags record which pairs face each other across it.
  const AcrossDamage across_damage(grid, rest, c_his, out.site_node, o.grid.damage_threshold);
  out.crack_face.assign(d.faces.size(), 0);
  std::vector<char> tag(d.faces.size(), kUntagged);
  for (size_t f = 0; f < d.faces.size(); ++f) {
    const VoronoiFace& face = d.faces[f];
    if (face.wall() || !cells.is_I[static_cast<size_t>(face.cell_a)] || !cells.is_I[static_cast<size_t>(face.cell_b)]) continue;
    if (across_damage(face.cell_a, face.cell_b)) {
      tag[f] = kOpposite;
      out.crack_face[f] = 1;
      ++out.interior_faces;
    } else {
      tag[f] = kAdjacent;
    }
  }
  mark_extension_faces(grid, cells, tag, node_cell, across_damage, o, out);
  return out;
}

TriMesh crack_surface_mesh(const CrackExtraction& crack, std::vector<char>* kinds) {
  TriMesh m;
  m.name = "crack_surface";
  const VoronoiDiagram& d = crack.diagram;
  std::vector<int> remap(d.vertices.size(), -1);
  if (kinds) kinds->clear();
  for (size_t f = 0; f < d.faces.size(); ++f) {
    if (!crack.crack_face[f]) continue;
    const std::vector<int>& v = d.faces[f].vertices;
    for (int id : v)
      if (remap[static_cast<size_t>(id)] < 0) {
        remap[static_cast<size_t>(id)] = static_cast<int>(m.positions.size());
        m.positions.push_back(d.vertices[static_cast<size_t>(id)]);
      }
    if (d.faces[f].bent) {  // smoothed: the star the fragments' faces use
      const int centre = static_cast<int>(m.positions.size());
      m.positions.push_back(face_centre(d.vertices, d.faces[f]));
      for_face_triangles(d.faces[f], [&](int, int b, int c) {
        m.triangles.emplace_back(centre, remap[static_cast<size_t>(b)], remap[static_cast<size_t>(c)]);
        if (kinds) kinds->push_back(crack.crack_face[f]);
      });
      continue;
    }
    for (size_t i = 1; i + 1 < v.size(); ++i) {
      m.triangles.emplace_back(remap[static_cast<size_t>(v[0])], remap[static_cast<size_t>(v[i])], remap[static_cast<size_t>(v[i + 1])]);
      if (kinds) kinds->push_back(crack.crack_face[f]);
    }
  }
  return m;
}

}  // namespace shellfrac::brittle
