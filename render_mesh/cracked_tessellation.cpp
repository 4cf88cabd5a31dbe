#include "render_mesh/cracked_tessellation.hpp"
#include "core/union_find.hpp"
#include "render_mesh/plane_geometry.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <numeric>
#include <stdexcept>
#include <unordered_map>

namespace shellfrac::render_mesh {

using detail::cross2;
using detail::kTwoPi;

namespace {

// Liang-Barsky: crops the segment a-b to the rectangle; false if nothing is left.
bool clip_to_domain(Vec2& a, Vec2& b, const ParameterDomain& d) {
  double t0 = 0.0, t1 = 1.0;
  const Vec2 dir = b - a;
  auto keep = [&](double p, double q) {  // the part with p * t <= q
    if (p == 0.0) return q >= 0.0;
    const double r = q / p;
    if (p < 0.0) {
      if (r > t1) return false;
      t0 = std::max(t0, r);
    } else {
      if (r < t0) return false;
      t1 = std::min(t1, r);
    }
    return true;
  };
  if (!keep(-dir.x(), a.x() - d.u0) || !keep(dir.x(), d.u1 - a.x()) || !keep(-dir.y(), a.y() - d.v0) ||
      !keep(dir.y(), d.v1 - a.y()))
    return false;
  const Vec2 start = a + t0 * dir, end = a + t1 * dir;
  a = start;
  b = end;
  return true;
}

// Merge and snap distance, as a fraction of the smaller quad side. Crack graph vertices carry the
// round-off of the Voronoi medial axis (about 2e-9 in parameter units): with 1e-9 of a quad side
// (1.6e-11 at 64 quads) a crack through a grid vertex or along a grid line missed it and left faces
// 1e-9 wide in the exported mesh. 1e-6 of a quad side takes those in and stays far below the shadow
// offset Dv (1e-5 in parameter units, 6e-4 of a quad at 64 quads), which must separate the sides.
constexpr double kMergeFraction = 1e-6;

// The render grid and every vertex of the split mesh. Points closer than `tolerance` are one vertex,
// and points that close to a grid line are put exactly on it, so that the two quads beside an edge
// see the same vertices on it (no T-junctions).
class VertexRegistry {
 public:
  VertexRegistry(const ParameterDomain& d, int resolution_u, int resolution_v)
      : R_(resolution_u), S_(resolution_v) {
    // Same grid coordinates as tessellate(): u0 + (i / R) (u1 - u0).
    for (int i = 0; i <= R_; ++i) us_.push_back(d.u0 + static_cast<double>(i) / R_ * (d.u1 - d.u0));
    for (int j = 0; j <= S_; ++j) vs_.push_back(d.v0 + static_cast<double>(j) / S_ * (d.v1 - d.v0));
    du_ = (d.u1 - d.u0) / R_;
    dv_ = (d.v1 - d.v0) / S_;
    tolerance_ = kMergeFraction * std::min(du_, dv_);
    for (int j = 0; j <= S_; ++j)
      for (int i = 0; i <= R_; ++i) push(Vec2(us_[static_cast<size_t>(i)], vs_[static_cast<size_t>(j)]), i, j);
  }

  int resolution_u() const { return R_; }
  int resolution_v() const { return S_; }
  int num_grid_vertices() const { return (R_ + 1) * (S_ + 1); }
  int grid_vertex(int i, int j) const { return i + (R_ + 1) * j; }
  double grid_u(int i) const { return us_[static_cast<size_t>(i)]; }
  double grid_v(int j) const { return vs_[static_cast<size_t>(j)]; }
  double tolerance() const { return tolerance_; }
  int size() const { return static_cast<int>(points.size()); }

  // Quad column/row containing the coordinate (closed on the low side).
  int cell_u(double u) const { return cell(u, us_, du_); }
  int cell_v(double v) const { return cell(v, vs_, dv_); }

  // Snaps to the grid lines, merges with an existing vertex within the tolerance, or adds one.
  int add(Vec2 p) {
    const int i = near_line(p.x(), us_, du_), j = near_line(p.y(), vs_, dv_);
    if (i >= 0) p.x() = us_[static_cast<size_t>(i)];
    if (j >= 0) p.y() = vs_[static_cast<size_t>(j)];
    if (i >= 0 && j >= 0) return grid_vertex(i, j);
    const long long cx = static_cast<long long>(std::floor(p.x() / tolerance_));
    const long long cy = static_cast<long long>(std::floor(p.y() / tolerance_));
    for (long long x = cx - 1; x <= cx + 1; ++x)
      for (long long y = cy - 1; y <= cy + 1; ++y) {
        const auto found = buckets_.find(key(x, y));
        if (found == buckets_.end()) continue;
        for (int id : found->second)
          if ((points[static_cast<size_t>(id)] - p).norm() <= tolerance_) return id;
      }
    const int id = push(p, i, j);
    buckets_[key(cx, cy)].push_back(id);
    return id;
  }

  std::vector<Vec2> points;
  std::vector<int> line_u, line_v;        // grid line the vertex lies on exactly, or -1
  std::vector<unsigned char> on_crack;    // lies on the crack: gets shadow copies (thesis 4.9.3)
  std::vector<unsigned char> used;        // referenced by a crack piece or bridge

 private:
  struct Key {
    long long x, y;
    bool operator==(const Key& o) const { return x == o.x && y == o.y; }
  };
  struct KeyHash {
    size_t operator()(const Key& k) const {
      return std::hash<long long>()(k.x * 0x9E3779B97F4A7C15LL ^ k.y);
    }
  };
  static Key key(long long x, long long y) { return Key{x, y}; }

  int push(const Vec2& p, int i, int j) {
    points.push_back(p);
    line_u.push_back(i);
    line_v.push_back(j);
    on_crack.push_back(0);
    used.push_back(0);
    return static_cast<int>(points.size()) - 1;
  }
  int near_line(double x, const std::vector<double>& lines, double h) const {
    const int n = static_cast<int>(lines.size()) - 1;
    const int guess = std::clamp(static_cast<int>(std::lround((x - lines[0]) / h)), 0, n);
    for (int k = std::max(0, guess - 1); k <= std::min(n, guess + 1); ++k)
      if (std::abs(x - lines[static_cast<size_t>(k)]) <= tolerance_) return k;
    return -1;
  }
  static int cell(double x, const std::vector<double>& lines, double h) {
    const int n = static_cast<int>(lines.size()) - 1;
    int k = std::clamp(static_cast<int>(std::floor((x - lines[0]) / h)), 0, n - 1);
    while (k > 0 && x < lines[static_cast<size_t>(k)]) --k;
    while (k < n - 1 && x >= lines[static_cast<size_t>(k) + 1]) ++k;
    return k;
  }

  int R_, S_;
  std::vector<double> us_, vs_;
  double du_ = 0.0, dv_ = 0.0, tolerance_ = 0.0;
  std::unordered_map<Key, std::vector<int>, KeyHash> buckets_;
};

// A straight edge inside one quad: a crack piece (both sides are different material) or a bridge
// (a cut through the same material that ties a floating crack to the quad boundary).
struct Piece {
  int a, b;
  bool crack;
};

// The crack pieces of one quad (the per-quad bucket) and the quad's grid indices.
struct CrackedQuad {
  int i = 0, j = 0;
  std::vector<Piece> pieces;
};

void remove_duplicate_pieces(std::vector<Piece>& pieces) {
  for (Piece& p : pieces)
    if (p.a > p.b) std::swap(p.a, p.b);
  std::sort(pieces.begin(), pieces.end(), [](const Piece& x, const Piece& y) {
    return std::tie(x.a, x.b, x.crack) > std::tie(y.a, y.b, y.crack);  // crack before bridge
  });
  pieces.erase(std::unique(pieces.begin(), pieces.end(),
                           [](const Piece& x, const Piece& y) { return x.a == y.a && x.b == y.b; }),
               pieces.end());
  pieces.erase(std::remove_if(pieces.begin(), pieces.end(), [](const Piece& p) { return p.a == p.b; }),
               pieces.end());
}

// Adds a vertex at every crossing of two crack pieces and splits pieces at every crack vertex lying
// on them (T-junctions, collinear overlaps), so that pieces meet only at end points.
void make_pieces_planar(CrackedQuad& quad, VertexRegistry& reg) {
  remove_duplicate_pieces(quad.pieces);
  std::vector<int> vertices;
  for (const Piece& p : quad.pieces) vertices.insert(vertices.end(), {p.a, p.b});
  const double tol = reg.tolerance();
  const auto& P = reg.points;
  for (size_t k = 0; k < quad.pieces.size(); ++k)
    for (size_t l = k + 1; l < quad.pieces.size(); ++l) {
      const Piece& s = quad.pieces[k];
      const Piece& t = quad.pieces[l];
      if (s.a == t.a || s.a == t.b || s.b == t.a || s.b == t.b) continue;
      const Vec2 a = P[static_cast<size_t>(s.a)], d1 = P[static_cast<size_t>(s.b)] - a;
      const Vec2 c = P[static_cast<size_t>(t.a)], d2 = P[static_cast<size_t>(t.b)] - c;
      const double denom = cross2(d1, d2);
      if (std::abs(denom) <= 1e-14 * d1.norm() * d2.norm()) continue;  // parallel: handled below
      const double ts = cross2(c - a, d2) / denom, tt = cross2(c - a, d1) / denom;
      if (ts < 0.0 || ts > 1.0 || tt < 0.0 || tt > 1.0) continue;
      const int x = reg.add(a + ts * d1);
      reg.on_crack[static_cast<size_t>(x)] = reg.used[static_cast<size_t>(x)] = 1;
      vertices.push_back(x);
    }
  std::sort(vertices.begin(), vertices.end());
  vertices.erase(std::unique(vertices.begin(), vertices.end()), vertices.end());

  std::vector<Piece> split;
  for (const Piece& p : quad.pieces) {
    const Vec2 a = P[static_cast<size_t>(p.a)], d = P[static_cast<size_t>(p.b)] - a;
    const double length2 = d.squaredNorm();
    std::vector<std::pair<double, int>> on_piece{{0.0, p.a}, {1.0, p.b}};
    for (int w : vertices) {
      if (w == p.a || w == p.b) continue;
      const Vec2 r = P[static_cast<size_t>(w)] - a;
      const double t = r.dot(d) / length2;
      if (t <= 0.0 || t >= 1.0) continue;
      if (std::abs(cross2(d, r)) <= tol * std::sqrt(length2)) on_piece.emplace_back(t, w);
    }
    std::sort(on_piece.begin(), on_piece.end());
    for (size_t k = 0; k + 1 < on_piece.size(); ++k)
      split.push_back(Piece{on_piece[k].second, on_piece[k + 1].second, p.crack});
  }
  quad.pieces = std::move(split);
  remove_duplicate_pieces(quad.pieces);
}

// Crack pieces that lie on an interior quad edge, keyed by that edge (see GridEdges).
using EdgeCracks = std::unordered_map<long long, std::vector<std::pair<int, int>>>;

// Keys of the grid edges: vertical edge on line u_i of row j, horizontal edge on line v_j of column i.
struct GridEdges {
  int R, S;
  long long vertical(int i, int j) const { return static_cast<long long>(j) * (R + 1) + i; }
  long long horizontal(int i, int j) const {
    return static_cast<long long>(R + 1) * S + static_cast<long long>(j) * R + i;
  }
  // The edge a non-grid vertex on a grid line lies on, or -1.
  long long of_vertex(const VertexRegistry& reg, int id) const {
    const Vec2& p = reg.points[static_cast<size_t>(id)];
    if (reg.line_u[static_cast<size_t>(id)] >= 0 && reg.line_v[static_cast<size_t>(id)] < 0)
      return vertical(reg.line_u[static_cast<size_t>(id)], reg.cell_v(p.y()));
    if (reg.line_v[static_cast<size_t>(id)] >= 0 && reg.line_u[static_cast<size_t>(id)] < 0)
      return horizontal(reg.cell_u(p.x()), reg.line_v[static_cast<size_t>(id)]);
    return -1;
  }
};

// A crack component inside a quad that touches none of its edges, by its leftmost and rightmost vertices.
struct FloatingCrack {
  int left, right;
};

// The floating components of the quad's pieces, ordered left to right (by u, then v, then vertex id).
std::vector<FloatingCrack> floating_cracks(const CrackedQuad& quad, const VertexRegistry& reg) {
  const auto& P = reg.points;
  std::unordered_map<int, int> local;
  std::vector<int> global;
  auto local_of = [&](int id) {
    const auto [it, inserted] = local.emplace(id, static_cast<int>(global.size()));
    if (inserted) global.push_back(id);
    return it->second;
  };
  for (const Piece& p : quad.pieces) {
    local_of(p.a);
    local_of(p.b);
  }
  core::UnionFind sets(global.size());
  for (const Piece& p : quad.pieces) sets.unite(static_cast<size_t>(local_of(p.a)), static_cast<size_t>(local_of(p.b)));
  auto on_quad_boundary = [&](int id) {
    const int lu = reg.line_u[static_cast<size_t>(id)], lv = reg.line_v[static_cast<size_t>(id)];
    return lu == quad.i || lu == quad.i + 1 || lv == quad.j || lv == quad.j + 1;
  };
  std::map<size_t, bool> anchored;  // component root -> touches the quad boundary
  for (size_t k = 0; k < global.size(); ++k) anchored[sets.find(k)] |= on_quad_boundary(global[k]);

  auto less_uv = [&](int x, int y) {
    const Vec2 &px = P[static_cast<size_t>(x)], &py = P[static_cast<size_t>(y)];
    return std::tie(px.x(), px.y(), x) < std::tie(py.x(), py.y(), y);
  };
  std::map<size_t, FloatingCrack> by_root;
  for (size_t k = 0; k < global.size(); ++k) {
    const size_t root = sets.find(k);
    if (anchored[root]) continue;
    const int id = global[k];
    auto [it, inserted] = by_root.emplace(root, FloatingCrack{id, id});
    if (!inserted) {
      if (less_uv(id, it->second.left)) it->second.left = id;
      if (less_uv(it->second.right, id)) it->second.right = id;
    }
  }
  std::vector<FloatingCrack> floating;
  for (const auto& entry : by_root) floating.push_back(entry.second);
  std::sort(floating.begin(), floating.end(),
            [&](const FloatingCrack& x, const FloatingCrack& y) { return less_uv(x.left, y.left); });
  return floating;
}

// The vertex where a horizontal ray from vertex `from` first meets an edge of the quad (side -1: to the
// left): an end point on the ray, a piece it crosses (split there), or the quad boundary (a new vertex,
// on the crack if a crack runs along that edge there).
int cast_bridge(CrackedQuad& quad, VertexRegistry& reg, const GridEdges& edges, const EdgeCracks& edge_cracks,
                int from, int side) {
  const auto& P = reg.points;
  const double tol = reg.tolerance();
  const Vec2 o = P[static_cast<size_t>(from)];
  double best = reg.grid_u(side < 0 ? quad.i : quad.i + 1);
  int best_piece = -1, best_vertex = -1;
  for (size_t k = 0; k < quad.pieces.size(); ++k) {
    const Piece& p = quad.pieces[k];
    for (int end : {p.a, p.b}) {  // end points on the ray, e.g. of pieces along it
      const Vec2& e = P[static_cast<size_t>(end)];
      if (end != from && std::abs(e.y() - o.y()) <= tol && side * (e.x() - o.x()) > tol &&
          side * (best - e.x()) >= 0.0) {
        best = e.x();
        best_vertex = end;
        best_piece = -1;
      }
    }
    const Vec2 a = P[static_cast<size_t>(p.a)], b = P[static_cast<size_t>(p.b)];
    if ((a.y() - o.y()) * (b.y() - o.y()) >= 0.0) continue;  // no proper crossing of the ray
    const double u = a.x() + (o.y() - a.y()) / (b.y() - a.y()) * (b.x() - a.x());
    if (side * (u - o.x()) > tol && side * (best - u) > 0.0) {
      best = u;
      best_piece = static_cast<int>(k);
      best_vertex = -1;
    }
  }
  if (best_vertex >= 0) return best_vertex;
  const int hit = reg.add(Vec2(best, o.y()));
  reg.used[static_cast<size_t>(hit)] = 1;
  if (best_piece >= 0) {
    Piece& p = quad.pieces[static_cast<size_t>(best_piece)];
    if (hit != p.a && hit != p.b) {
      const Piece tail{hit, p.b, p.crack};
      p.b = hit;
      if (tail.crack) reg.on_crack[static_cast<size_t>(hit)] = 1;
      quad.pieces.push_back(tail);
    }
    return hit;
  }
  const long long edge = edges.of_vertex(reg, hit);
  const auto found = edge_cracks.find(edge);
  if (found != edge_cracks.end())
    for (const auto& [a, b] : found->second) {
      const Vec2 &pa = reg.points[static_cast<size_t>(a)], &pb = reg.points[static_cast<size_t>(b)],
                 &h = reg.points[static_cast<size_t>(hit)];
      if ((h - pa).dot(h - pb) <= 0.0) reg.on_crack[static_cast<size_t>(hit)] = 1;
    }
  return hit;
}

// A crack that lies in the interior of a quad touches none of its edges; the polygon tracing would
// make it a hole. Each such floating component gets two bridges, horizontally to the left from its
// leftmost vertex and to the right from its rightmost one, up to the first edge hit. Then the edge
// graph of the quad is connected and every traced face is a polygon without holes.
void bridge_floating_cracks(CrackedQuad& quad, VertexRegistry& reg, const GridEdges& edges,
                            const EdgeCracks& edge_cracks) {
  for (const FloatingCrack& f : floating_cracks(quad, reg)) {
    quad.pieces.push_back(Piece{f.left, cast_bridge(quad, reg, edges, edge_cracks, f.left, -1), false});
    quad.pieces.push_back(Piece{f.right, cast_bridge(quad, reg, edges, edge_cracks, f.right, +1), false});
  }
  remove_duplicate_pieces(quad.pieces);
}

// Traces the polygons of one quad (thesis 4.9.2): the boundary counter-clockwise plus every piece in
// both directions; from each unused directed edge, walk on taking at every vertex the outgoing edge
// with the smallest clockwise turn from the way back. Faces come out counter-clockwise.
// A polygon as its corners, each with the flag "the edge to the next corner lies on the crack".
using Polygon = std::vector<std::pair<int, bool>>;

void trace_polygons(const Polygon& boundary, const std::vector<Piece>& pieces, const VertexRegistry& reg,
                    std::vector<Polygon>& polygons) {
  struct HalfEdge {
    int from, to;
    bool crack, visited;
  };
  std::vector<HalfEdge> half_edges;
  for (size_t k = 0; k < boundary.size(); ++k)
    half_edges.push_back({boundary[k].first, boundary[(k + 1) % boundary.size()].first, boundary[k].second, false});
  for (const Piece& p : pieces) {
    half_edges.push_back({p.a, p.b, p.crack, false});
    half_edges.push_back({p.b, p.a, p.crack, false});
  }
  std::unordered_map<int, std::vector<int>> outgoing;
  for (size_t h = 0; h < half_edges.size(); ++h) outgoing[half_edges[h].from].push_back(static_cast<int>(h));
  const auto& P = reg.points;
  auto next_of = [&](int h) {
    const int at = half_edges[static_cast<size_t>(h)].to;
    const Vec2 back = P[static_cast<size_t>(half_edges[static_cast<size_t>(h)].from)] - P[static_cast<size_t>(at)];
    int best = -1;
    double best_turn = 0.0;
    for (int candidate : outgoing[at]) {
      const Vec2 d = P[static_cast<size_t>(half_edges[static_cast<size_t>(candidate)].to)] - P[static_cast<size_t>(at)];
      double turn = std::atan2(cross2(d, back), d.dot(back));  // clockwise angle from back to d
      if (turn <= 0.0) turn += kTwoPi;                         // straight back only at a crack tip
      if (best < 0 || turn < best_turn) {
        best = candidate;
        best_turn = turn;
      }
    }
    return best;
  };
  for (size_t start = 0; start < half_edges.size(); ++start) {
    if (half_edges[start].visited) continue;
    Polygon polygon;
    int h = static_cast<int>(start);
    for (size_t guard = 0; guard <= half_edges.size(); ++guard) {
      half_edges[static_cast<size_t>(h)].visited = true;
      polygon.emplace_back(half_edges[static_cast<size_t>(h)].from, half_edges[static_cast<size_t>(h)].crack);
      h = next_of(h);
      if (h == static_cast<int>(start) || half_edges[static_cast<size_t>(h)].visited) break;
    }
    if (polygon.size() >= 3) polygons.push_back(std::move(polygon));
  }
}

}  // namespace

namespace {

// Algorithm 5 lines 7-12: cuts every crack segment at the grid lines; each piece falls in one quad's
// bucket (`quads`, by i + R j), or lies on an interior quad edge (`edge_cracks`).
void cut_at_grid_lines(const std::vector<CrackSegment2>& crack, const ParameterDomain& domain, const GridEdges& edges,
                       VertexRegistry& reg, std::map<int, CrackedQuad>& quads, EdgeCracks& edge_cracks) {
  const int R = edges.R, S = edges.S;
  const double tol = reg.tolerance();
  auto mark = [&](int id) { reg.on_crack[static_cast<size_t>(id)] = reg.used[static_cast<size_t>(id)] = 1; };
  for (const CrackSegment2& segment : crack) {
    Vec2 a = segment.a, b = segment.b;
    if (!a.allFinite() || !b.allFinite() || !clip_to_domain(a, b, domain) || (b - a).norm() <= tol) continue;
    const int ia = reg.add(a), ib = reg.add(b);
    if (ia == ib) continue;
    a = reg.points[static_cast<size_t>(ia)];
    b = reg.points[static_cast<size_t>(ib)];
    std::vector<std::pair<double, Vec2>> cuts;
    auto cut_lines = [&](int axis, double (VertexRegistry::*line)(int) const, int n) {
      const double lo = std::min(a[axis], b[axis]), hi = std::max(a[axis], b[axis]);
      if (hi - lo <= 0.0) return;
      for (int k = 0; k <= n; ++k) {
        const double x = (reg.*line)(k);
        if (x <= lo || x >= hi) continue;
        const double t = (x - a[axis]) / (b[axis] - a[axis]);
        Vec2 p = a + t * (b - a);
        p[axis] = x;
        cuts.emplace_back(t, p);
      }
    };
    cut_lines(0, &VertexRegistry::grid_u, R);
    cut_lines(1, &VertexRegistry::grid_v, S);
    std::sort(cuts.begin(), cuts.end(), [](const auto& x, const auto& y) { return x.first < y.first; });
    std::vector<int> chain{ia};
    for (const auto& cut : cuts) {
      const int id = reg.add(cut.second);
      if (id != chain.back()) chain.push_back(id);
    }
    if (ib != chain.back()) chain.push_back(ib);
    for (size_t k = 0; k + 1 < chain.size(); ++k) {
      const int p = chain[k], q = chain[k + 1];
      const int lu = reg.line_u[static_cast<size_t>(p)], lv = reg.line_v[static_cast<size_t>(p)];
      const Vec2 mid = 0.5 * (reg.points[static_cast<size_t>(p)] + reg.points[static_cast<size_t>(q)]);
      if (lu >= 0 && lu == reg.line_u[static_cast<size_t>(q)]) {  // along a vertical quad edge
        if (lu == 0 || lu == R) continue;                         // the patch boundary cuts nothing
        edge_cracks[edges.vertical(lu, reg.cell_v(mid.y()))].emplace_back(p, q);
      } else if (lv >= 0 && lv == reg.line_v[static_cast<size_t>(q)]) {
        if (lv == 0 || lv == S) continue;
        edge_cracks[edges.horizontal(reg.cell_u(mid.x()), lv)].emplace_back(p, q);
      } else {
        const int i = reg.cell_u(mid.x()), j = reg.cell_v(mid.y());
        CrackedQuad& quad = quads[i + R * j];
        quad.i = i;
        quad.j = j;
        quad.pieces.push_back(Piece{p, q, true});
      }
      mark(p);
      mark(q);
    }
  }
}

// The faces of the split grid, quad by quad: untouched quads as in tessellate(), the others as the
// polygons their boundary and crack pieces enclose.
class QuadFaces {
 public:
  QuadFaces(const VertexRegistry& reg, const GridEdges& edges, const std::map<int, CrackedQuad>& quads,
            const EdgeCracks& edge_cracks, const std::vector<int>& index, ParameterMesh& mesh)
      : reg_(reg), edges_(edges), quads_(quads), edge_cracks_(edge_cracks), index_(index), mesh_(mesh) {
    // Vertices inside quad edges, shared by the quads on both sides.
    for (int id = reg.num_grid_vertices(); id < reg.size(); ++id)
      if (reg.used[static_cast<size_t>(id)]) on_edge_[edges.of_vertex(reg, id)].push_back(id);
  }

  void add(int i, int j) {
    const int c0 = reg_.grid_vertex(i, j), c1 = reg_.grid_vertex(i + 1, j);
    const int c2 = reg_.grid_vertex(i + 1, j + 1), c3 = reg_.grid_vertex(i, j + 1);
    const auto found = quads_.find(i + edges_.R * j);
    const long long sides[4] = {edges_.horizontal(i, j), edges_.vertical(i + 1, j), edges_.horizontal(i, j + 1),
                                edges_.vertical(i, j)};
    if (found == quads_.end() && std::none_of(sides, sides + 4, [&](long long e) {
          return on_edge_.count(e) > 0 || edge_cracks_.count(e) > 0;
        })) {  // untouched quad, as in tessellate()
      for (int id : {c0, c1, c2, c3}) mesh_.face_vertices.push_back(index_[static_cast<size_t>(id)]);
      mesh_.crack_edge.insert(mesh_.crack_edge.end(), 4, 0);
      mesh_.face_offsets.push_back(static_cast<int>(mesh_.face_vertices.size()));
      return;
    }
    // The boundary counter-clockwise about du x dv as in tessellate(), with the quad side each
    // boundary piece lies on.
    std::vector<int> loop;
    std::vector<long long> side_of;
    auto add_side = [&](int corner, long long edge, int axis, bool ascending) {
      loop.push_back(corner);
      for (int id : edge_points(edge, axis, ascending)) loop.push_back(id);
      side_of.resize(loop.size(), edge);
    };
    add_side(c0, sides[0], 0, true);
    add_side(c1, sides[1], 1, true);
    add_side(c2, sides[2], 0, false);
    add_side(c3, sides[3], 1, false);
    Polygon boundary;
    for (size_t k = 0; k < loop.size(); ++k)
      boundary.emplace_back(loop[k], along_edge_crack(side_of[k], loop[k], loop[(k + 1) % loop.size()]));
    polygons_.clear();
    if (found == quads_.end())
      polygons_.push_back(boundary);
    else
      trace_polygons(boundary, found->second.pieces, reg_, polygons_);
    for (const Polygon& polygon : polygons_) {
      for (const auto& [id, crack_edge] : polygon) {
        mesh_.face_vertices.push_back(index_[static_cast<size_t>(id)]);
        mesh_.crack_edge.push_back(crack_edge ? 1 : 0);
      }
      mesh_.face_offsets.push_back(static_cast<int>(mesh_.face_vertices.size()));
    }
  }

 private:
  // The vertices inside a quad edge, sorted along it.
  std::vector<int> edge_points(long long edge, int axis, bool ascending) const {
    std::vector<int> ids;
    const auto found = on_edge_.find(edge);
    if (found == on_edge_.end()) return ids;
    ids = found->second;
    std::sort(ids.begin(), ids.end(), [&](int x, int y) {
      const double px = reg_.points[static_cast<size_t>(x)][axis], py = reg_.points[static_cast<size_t>(y)][axis];
      return ascending ? px < py : px > py;
    });
    return ids;
  }

  // A boundary piece of a quad is a crack edge where a crack runs along that quad edge.
  bool along_edge_crack(long long edge, int a, int b) const {
    const auto found = edge_cracks_.find(edge);
    if (found == edge_cracks_.end()) return false;
    const Vec2 mid = 0.5 * (reg_.points[static_cast<size_t>(a)] + reg_.points[static_cast<size_t>(b)]);
    for (const auto& [p, q] : found->second)
      if ((mid - reg_.points[static_cast<size_t>(p)]).dot(mid - reg_.points[static_cast<size_t>(q)]) < 0.0) return true;
    return false;
  }

  const VertexRegistry& reg_;
  const GridEdges& edges_;
  const std::map<int, CrackedQuad>& quads_;
  const EdgeCracks& edge_cracks_;
  const std::vector<int>& index_;
  ParameterMesh& mesh_;
  std::unordered_map<long long, std::vector<int>> on_edge_;
  std::vector<Polygon> polygons_;
};

}  // namespace

ParameterMesh split_parameter_grid(const ParameterDomain& domain, const std::vector<CrackSegment2>& crack,
                                   const CrackedTessellationSettings& settings) {
  const int R = settings.resolution_u, S = settings.resolution_v;
  if (R < 1 || S < 1) throw std::invalid_argument("render resolution must be at least 1 x 1");
  if (!(domain.u1 > domain.u0) || !(domain.v1 > domain.v0))
    throw std::invalid_argument("patch parameter domain must satisfy u0 < u1 and v0 < v1");
  VertexRegistry reg(domain, R, S);
  const GridEdges edges{R, S};
  std::map<int, CrackedQuad> quads;  // ordered: deterministic output
  EdgeCracks edge_cracks;
  cut_at_grid_lines(crack, domain, edges, reg, quads, edge_cracks);
  for (auto& entry : quads) {
    make_pieces_planar(entry.second, reg);
    bridge_floating_cracks(entry.second, reg, edges, edge_cracks);
  }

  // Compact numbering: grid vertices as in tessellate(), then the used extra vertices.
  std::vector<int> index(static_cast<size_t>(reg.size()), -1);
  ParameterMesh mesh;
  for (int id = 0; id < reg.size(); ++id)
    if (id < reg.num_grid_vertices() || reg.used[static_cast<size_t>(id)]) {
      index[static_cast<size_t>(id)] = mesh.num_vertices();
      mesh.uv.push_back(reg.points[static_cast<size_t>(id)]);
      mesh.on_crack.push_back(reg.on_crack[static_cast<size_t>(id)]);
    }
  mesh.source_vertex.resize(mesh.uv.size());
  std::iota(mesh.source_vertex.begin(), mesh.source_vertex.end(), 0);
  QuadFaces faces(reg, edges, quads, edge_cracks, index, mesh);
  for (int j = 0; j < S; ++j)
    for (int i = 0; i < R; ++i) faces.add(i, j);
  return mesh;
}

PolyMesh assemble_render_mesh(const ParameterMesh& mesh, const ParameterDomain& domain,
                              std::vector<Vec3> positions, std::vector<Vec3> normals,
                              const std::string& name) {
  if (positions.size() != mesh.uv.size())
    throw std::invalid_argument("assemble_render_mesh: one position per parameter vertex is required");
  if (!normals.empty() && normals.size() != mesh.uv.size())
    throw std::invalid_argument("assemble_render_mesh: normals must be empty or one per vertex");
  PolyMesh out;
  out.name = name;
  out.face_offsets = mesh.face_offsets;
  out.face_vertices = mesh.face_vertices;
  out.uvs.reserve(mesh.uv.size());
  for (const Vec2& uv : mesh.uv)
    out.uvs.emplace_back((uv.x() - domain.u0) / (domain.u1 - domain.u0), (uv.y() - domain.v0) / (domain.v1 - domain.v0));
  if (normals.empty()) {
    // Area-weighted: each polygon adds its vector area (Newell) to its corners.
    normals.assign(positions.size(), Vec3::Zero());
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const int begin = mesh.face_offsets[static_cast<size_t>(f)], end = mesh.face_offsets[static_cast<size_t>(f) + 1];
      Vec3 area = Vec3::Zero();
      for (int k = begin; k < end; ++k) {
        const int next = k + 1 < end ? k + 1 : begin;
        area += positions[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(k)])].cross(
            positions[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(next)])]);
      }
      for (int k = begin; k < end; ++k) normals[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(k)])] += 0.5 * area;
    }
    for (Vec3& n : normals) {
      const double length = n.norm();
      n = length > 0.0 ? Vec3(n / length) : Vec3::UnitZ();
    }
  }
  out.positions = std::move(positions);
  out.normals = std::move(normals);
  return out;
}

}  // namespace shellfrac::render_mesh
