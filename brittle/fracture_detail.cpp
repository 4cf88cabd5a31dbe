#include "brittle/fracture_detail.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <string>
#include <type_traits>
#include <unordered_map>

#include "brittle/errors.hpp"
#include "brittle/triangle_index.hpp"

namespace shellfrac::brittle {
namespace {

// Quadratic B-spline weights (thesis Eq. 2.10) of x on the 3 x 3 x 3 nodes of spacing h from base.
struct Weights {
  long base[3];
  double w[3][3];
};
Weights weights_at(const Vec3& x, double h) {
  Weights s;
  for (int a = 0; a < 3; ++a) {
    const double q = x[a] / h;
    const long b = static_cast<long>(std::floor(q - 0.5));
    const double f = q - static_cast<double>(b);  // in [0.5, 1.5)
    s.base[a] = b;
    s.w[a][0] = 0.5 * (1.5 - f) * (1.5 - f);
    s.w[a][1] = 0.75 - (f - 1.0) * (f - 1.0);
    s.w[a][2] = 0.5 * (f - 0.5) * (f - 0.5);
  }
  return s;
}

constexpr long long kAxis = 1 << 20;  // node indices per axis in a key, centred on zero
long long node_key(long i, long j, long k) {
  return ((static_cast<long long>(i) + kAxis / 2) * kAxis + (static_cast<long long>(j) + kAxis / 2)) * kAxis +
         (static_cast<long long>(k) + kAxis / 2);
}

// A node grid accumulated from point values (scalars or vectors) with the quadratic weights, and read
// back with the same weights: the heights' and the normals' smoothing.
template <class T>
T zero_of() {
  if constexpr (std::is_same_v<T, double>)
    return 0.0;
  else
    return T::Zero();
}
template <class T>
class ScatterGrid {
 public:
  explicit ScatterGrid(double h) : h_(h) {}
  void add(const Vec3& x, const T& value) {
    const Weights s = weights_at(x, h_);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c) {
          auto it = nodes_.try_emplace(node_key(s.base[0] + a, s.base[1] + b, s.base[2] + c), zero_of<T>()).first;
          it->second += s.w[0][a] * s.w[1][b] * s.w[2][c] * value;
        }
  }
  T gather(const Vec3& x) const {
    const Weights s = weights_at(x, h_);
    T sum = zero_of<T>();
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c) {
          const auto it = nodes_.find(node_key(s.base[0] + a, s.base[1] + b, s.base[2] + c));
          if (it != nodes_.end()) sum += s.w[0][a] * s.w[1][b] * s.w[2][c] * it->second;
        }
    return sum;
  }

 private:
  double h_;
  std::unordered_map<long long, T> nodes_;
};

// Points hashed into cubes of side `cell` for nearest and range queries.
class PointHash {
 public:
  PointHash(const std::vector<Vec3>& points, double cell) : points_(points), cell_(cell) {
    for (size_t p = 0; p < points.size(); ++p) cells_[key_of(points[p])].push_back(p);
  }
  // The nearest point within `reach` of x, or SIZE_MAX.
  size_t nearest(const Vec3& x, double reach) const {
    size_t best = SIZE_MAX;
    double best_d2 = reach * reach;
    visit(x, reach, [&](size_t p) {
      const double d2 = (points_[p] - x).squaredNorm();
      if (d2 < best_d2 || (d2 == best_d2 && p < best)) {
        best_d2 = d2;
        best = p;
      }
    });
    return best;
  }
  // Calls f for every point in the cubes that a ball of radius r around x touches.
  template <class F>
  void visit(const Vec3& x, double r, F&& f) const {
    const long n = static_cast<long>(std::ceil(r / cell_));
    const std::array<long, 3> c = cell_of(x);
    for (long i = c[0] - n; i <= c[0] + n; ++i)
      for (long j = c[1] - n; j <= c[1] + n; ++j)
        for (long k = c[2] - n; k <= c[2] + n; ++k) {
          const auto it = cells_.find(node_key(i, j, k));
          if (it == cells_.end()) continue;
          for (size_t p : it->second) f(p);
        }
  }

 private:
  std::array<long, 3> cell_of(const Vec3& x) const {
    return {static_cast<long>(std::floor(x.x() / cell_)), static_cast<long>(std::floor(x.y() / cell_)),
            static_cast<long>(std::floor(x.z() / cell_))};
  }
  long long key_of(const Vec3& x) const {
    const auto c = cell_of(x);
    return node_key(c[0], c[1], c[2]);
  }
  const std::vector<Vec3>& points_;
  double cell_;
  std::unordered_map<long long, std::vector<size_t>> cells_;
};

// Exact position key: vertices of different fragments (and copies with other normals or UVs) weld by it.
using PositionKey = std::array<double, 3>;
PositionKey key_of(const Vec3& p) { return {p.x(), p.y(), p.z()}; }

// Triangle t's normal times its area.
Vec3 area_normal(const TriMesh& m, size_t t) {
  const Tri& tri = m.triangles[t];
  const Vec3& a = m.positions[static_cast<size_t>(tri[0])];
  return 0.5 * (m.positions[static_cast<size_t>(tri[1])] - a).cross(m.positions[static_cast<size_t>(tri[2])] - a);
}

// Smooth normals on the crack triangles: each corner averages the area normals of the crack triangles
// at its position that lie within 60 degrees of its own (sharper bends of the Voronoi sheets stay
// creases), and corners with different normals get their own vertex copies.
void smooth_crack_normals(TriMesh& mesh, const std::vector<char>& crack) {
  std::map<PositionKey, std::vector<size_t>> around;  // crack triangles per position
  std::vector<Vec3> normals(mesh.triangles.size(), Vec3::Zero());  // area-weighted
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!crack[t]) continue;
    normals[t] = area_normal(mesh, t);
    for (int k = 0; k < 3; ++k) around[key_of(mesh.positions[static_cast<size_t>(mesh.triangles[t][k])])].push_back(t);
  }
  const bool uvs = mesh.has_uvs();
  std::vector<char> claimed(mesh.positions.size(), 0);
  std::map<std::pair<int, std::array<double, 3>>, int> copy;  // (vertex, normal) -> vertex
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!crack[t] || !(normals[t].norm() > 0)) continue;
    const Vec3 own = normals[t].normalized();
    for (int k = 0; k < 3; ++k) {
      const int v = mesh.triangles[t][k];
      Vec3 sum = Vec3::Zero();
      for (size_t u : around[key_of(mesh.positions[static_cast<size_t>(v)])])
        if (normals[u].norm() > 0 && normals[u].normalized().dot(own) > 0.5) sum += normals[u];
      const Vec3 n = sum.normalized();
      const auto [it, added] = copy.try_emplace({v, {n.x(), n.y(), n.z()}}, v);
      if (added) {
        if (!claimed[static_cast<size_t>(v)]) {  // the vertex's first normal is its own
          claimed[static_cast<size_t>(v)] = 1;
          mesh.normals[static_cast<size_t>(v)] = n;
        } else {
          it->second = static_cast<int>(mesh.positions.size());
          mesh.positions.push_back(mesh.positions[static_cast<size_t>(v)]);
          mesh.normals.push_back(n);
          if (uvs) mesh.uvs.push_back(mesh.uvs[static_cast<size_t>(v)]);
        }
      }
      mesh.triangles[t][k] = it->second;
    }
  }
}

}  // namespace

DamageTimeGrid::DamageTimeGrid(const std::vector<Vec3>& rest, const std::vector<ParticleDamage>& damage, double h)
    : h_(h) {
  std::unordered_map<long long, Node> acc;
  for (size_t p = 0; p < rest.size() && p < damage.size(); ++p) {
    const double tau = damage[p].tau;
    if (!(tau >= 0)) continue;  // unbroken particles have no damage time
    const Weights s = weights_at(rest[p], h_);
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        for (int c = 0; c < 3; ++c) {
          const double w = s.w[0][a] * s.w[1][b] * s.w[2][c];
          Node& n = acc[node_key(s.base[0] + a, s.base[1] + b, s.base[2] + c)];
          n.weighted += w * tau;  // Eq. 3.13, numerator and denominator
          n.weight += w;
        }
  }
  nodes_.assign(acc.begin(), acc.end());
  std::sort(nodes_.begin(), nodes_.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
}

const DamageTimeGrid::Node* DamageTimeGrid::find(long i, long j, long k) const {
  const long long key = node_key(i, j, k);
  const auto it = std::lower_bound(nodes_.begin(), nodes_.end(), key, [](const auto& n, long long v) { return n.first < v; });
  return it != nodes_.end() && it->first == key && it->second.weight > 0 ? &it->second : nullptr;
}

std::optional<double> DamageTimeGrid::time(const Vec3& x) const {
  const Weights s = weights_at(x, h_);
  double sum = 0, weight = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c)
        if (const Node* n = find(s.base[0] + a, s.base[1] + b, s.base[2] + c)) {
          const double w = s.w[0][a] * s.w[1][b] * s.w[2][c];
          sum += w * n->weighted / n->weight;
          weight += w;
        }
  if (!(weight > 0)) return std::nullopt;
  return sum / weight;
}

Vec3 DamageTimeGrid::gradient(const Vec3& x) const {
  const std::optional<double> centre = time(x);
  if (!centre) return Vec3::Zero();
  const Weights s = weights_at(x, h_);
  const double inv_M = 4.0 / (h_ * h_);  // M = h_c^2 / 4 for the quadratic kernel
  Vec3 g = Vec3::Zero();
  double weight = 0;
  for (int a = 0; a < 3; ++a)
    for (int b = 0; b < 3; ++b)
      for (int c = 0; c < 3; ++c)
        if (const Node* n = find(s.base[0] + a, s.base[1] + b, s.base[2] + c)) {
          const double w = s.w[0][a] * s.w[1][b] * s.w[2][c];
          const Vec3 xi(static_cast<double>(s.base[0] + a) * h_, static_cast<double>(s.base[1] + b) * h_,
                        static_cast<double>(s.base[2] + c) * h_);
          g += w * inv_M * (xi - x) * (n->weighted / n->weight - *centre);  // Eq. 3.14
          weight += w;
        }
  return g / weight;
}

namespace {

using GeometricEdge = std::pair<PositionKey, PositionKey>;

// An edge by the positions of its ends, in canonical order: copies of one edge in different triangles
// (crack faces duplicate vertices) get the same key.
GeometricEdge geometric_edge(const TriMesh& mesh, int a, int b) {
  PositionKey pa = key_of(mesh.positions[static_cast<size_t>(a)]), pb = key_of(mesh.positions[static_cast<size_t>(b)]);
  if (pb < pa) std::swap(pa, pb);
  return std::make_pair(pa, pb);
}

// The midpoint vertex of each (vertex, vertex) pair, made once; its position from the canonical order of
// the ends, so that every copy of the edge gets the bit-identical midpoint. Normals and UVs interpolated.
class Midpoints {
 public:
  explicit Midpoints(TriMesh& mesh) : mesh_(mesh), normals_(mesh.has_normals()), uvs_(mesh.has_uvs()) {}
  int operator()(int a, int b) {
    const auto key = std::minmax(a, b);
    const auto it = made_.find(key);
    if (it != made_.end()) return it->second;
    const Vec3 &pa = mesh_.positions[static_cast<size_t>(a)], &pb = mesh_.positions[static_cast<size_t>(b)];
    const bool ordered = key_of(pa) < key_of(pb);
    const Vec3 m = ordered ? Vec3(0.5 * (pa + pb)) : Vec3(0.5 * (pb + pa));
    const int v = static_cast<int>(mesh_.positions.size());
    mesh_.positions.push_back(m);
    if (normals_) {
      const Vec3 n = mesh_.normals[static_cast<size_t>(a)] + mesh_.normals[static_cast<size_t>(b)];
      mesh_.normals.push_back(n.norm() > 0 ? Vec3(n.normalized()) : mesh_.normals[static_cast<size_t>(a)]);
    }
    if (uvs_) mesh_.uvs.push_back(0.5 * (mesh_.uvs[static_cast<size_t>(a)] + mesh_.uvs[static_cast<size_t>(b)]));
    made_.emplace(key, v);
    return v;
  }

 private:
  TriMesh& mesh_;
  bool normals_, uvs_;
  std::map<std::pair<int, int>, int> made_;
};

// Triangle `tri` with `count` of its edges cut (cut[e]: edge tri[e] tri[e + 1]) as 2, 3 or 4 triangles,
// passed to emit(a, b, c).
template <class Emit>
void split_triangle(const TriMesh& mesh, const Tri& tri, const bool (&cut)[3], int count, Midpoints& mid, Emit&& emit) {
  // Rotate so that edge 0 (v0 v1) is cut and, with two cuts, edge 2 (v2 v0) is the uncut one.
  int r = 0;
  if (count == 1) {
    while (!cut[r]) ++r;
  } else if (count == 2) {
    while (cut[(r + 2) % 3]) ++r;
  }
  const int v0 = tri[r], v1 = tri[(r + 1) % 3], v2 = tri[(r + 2) % 3];
  if (count == 1) {
    const int m = mid(v0, v1);
    emit(v0, m, v2);
    emit(m, v1, v2);
  } else if (count == 2) {
    const int m01 = mid(v0, v1), m12 = mid(v1, v2);
    emit(m01, v1, m12);
    // The quad v0 m01 m12 v2 along its shorter diagonal (a choice by geometry only).
    const auto P = [&](int v) -> const Vec3& { return mesh.positions[static_cast<size_t>(v)]; };
    if ((P(v0) - P(m12)).squaredNorm() <= (P(m01) - P(v2)).squaredNorm()) {
      emit(v0, m01, m12);
      emit(v0, m12, v2);
    } else {
      emit(v0, m01, v2);
      emit(m01, m12, v2);
    }
  } else {
    const int m01 = mid(v0, v1), m12 = mid(v1, v2), m20 = mid(v2, v0);
    emit(v0, m01, m20);
    emit(m01, v1, m12);
    emit(m20, m12, v2);
    emit(m01, m12, m20);
  }
}

// One round of refine_crack_faces: every geometric edge of a crack face longer than `edge` is split in
// every triangle that has it. False when there was none.
bool refine_round(TriMesh& mesh, std::vector<char>& crack, double edge) {
  std::map<GeometricEdge, char> split;
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!crack[t]) continue;
    const Tri& tri = mesh.triangles[t];
    for (int e = 0; e < 3; ++e) {
      const int a = tri[e], b = tri[(e + 1) % 3];
      if ((mesh.positions[static_cast<size_t>(a)] - mesh.positions[static_cast<size_t>(b)]).norm() > edge)
        split[geometric_edge(mesh, a, b)] = 1;
    }
  }
  if (split.empty()) return false;
  Midpoints mid(mesh);
  std::vector<Tri> triangles;
  std::vector<char> flags;
  triangles.reserve(mesh.triangles.size() * 2);
  for (size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Tri tri = mesh.triangles[t];
    const char flag = crack[t];
    auto emit = [&](int a, int b, int c) {
      triangles.emplace_back(a, b, c);
      flags.push_back(flag);
    };
    bool cut[3];
    int count = 0;
    for (int e = 0; e < 3; ++e) count += cut[e] = split.count(geometric_edge(mesh, tri[e], tri[(e + 1) % 3])) > 0;
    if (count == 0)
      emit(tri[0], tri[1], tri[2]);
    else
      split_triangle(mesh, tri, cut, count, mid, emit);
  }
  mesh.triangles = std::move(triangles);
  crack = std::move(flags);
  return true;
}

}  // namespace

void refine_crack_faces(TriMesh& mesh, std::vector<char>& crack, double edge) {
  if (!(edge > 0)) throw InputError("fracture detail: the refinement edge length must be positive");
  for (int round = 0; round < 64; ++round)
    if (!refine_round(mesh, crack, edge)) return;
}

std::vector<std::vector<size_t>> trace_chevron_lines(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                                     const std::vector<double>& time, const std::vector<Vec3>& gradient,
                                                     double step, int max_steps, double radius) {
  if (!(step > 0) || !(radius >= 0) || max_steps < 0)
    throw InputError("fracture detail: the chevron step must be positive and the radius and length not negative");
  const size_t n = points.size();
  std::vector<size_t> order(n);
  std::iota(order.begin(), order.end(), size_t{0});
  // Earliest first; points without a time (NaN) last, in index order.
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const bool ta = std::isfinite(time[a]), tb = std::isfinite(time[b]);
    if (ta != tb) return ta;
    return ta && time[a] < time[b];
  });
  const PointHash hash(points, std::max(step, radius));
  std::vector<char> visited(n, 0);
  std::vector<std::vector<size_t>> lines;
  size_t cursor = 0;
  while (true) {
    while (cursor < n && visited[order[cursor]]) ++cursor;
    if (cursor == n) break;
    size_t x = order[cursor];  // GetEarliest (Algorithm 4, line 5)
    std::vector<size_t> line{x};
    visited[x] = 1;
    for (int i = 0; i < max_steps; ++i) {
      // The direction of the crack front's motion, in the surface.
      Vec3 g = gradient[x] - gradient[x].dot(normals[x]) * normals[x];
      if (!(g.norm() > 0) || !std::isfinite(g.norm())) break;
      g.normalize();
      const Vec3 shifted = points[x] + step * g;                 // line 9
      const size_t near = hash.nearest(shifted, 1.5 * step);     // line 11
      if (near == SIZE_MAX || near == x || visited[near]) break; // lines 12, 22
      line.push_back(near);                                      // line 13
      visited[near] = 1;
      // Lines 15-19: the points across the line at `near`, within `radius` on either side.
      Vec3 across = g.cross(normals[near]);
      if (across.norm() > 0) {
        across.normalize();
        hash.visit(points[near], radius + step, [&](size_t p) {
          const Vec3 d = points[p] - points[near];
          if (std::abs(d.dot(across)) <= radius && std::abs(d.dot(g)) <= 0.5 * step) visited[p] = 1;
        });
      }
      x = near;  // line 20
    }
    lines.push_back(std::move(line));
  }
  return lines;
}

namespace {

bool has_crack(const Fragment& f) { return f.crack_faces.size() == f.mesh.triangles.size() && f.crack_triangles > 0; }

const Vec3& corner(const TriMesh& m, size_t t, int k) { return m.positions[static_cast<size_t>(m.triangles[t][k])]; }

const double kTriangleArea = std::sqrt(3.0) / 4.0;  // an equilateral triangle of unit edge

// The refinement's edge, bounded before it runs: past max_triangles the edge grows to fit (the event keeps
// its fragments; the report says which edge was used).
double detail_edge(const FragmentSet& set, const FractureDetailOptions& o) {
  double crack_area = 0;
  for (const Fragment& frag : set.fragments)
    if (has_crack(frag))
      for (size_t t = 0; t < frag.mesh.triangles.size(); ++t)
        if (frag.crack_faces[t]) crack_area += area_normal(frag.mesh, t).norm();
  // Halving every edge longer than d leaves edges between d/2 and d, and the splits of one or two edges
  // make some triangles skinny: their mean area measured 0.15 of the equilateral one at d (1.3x the
  // budget with a factor of 4), so 8 keeps the count below the budget.
  return std::max(o.edge, std::sqrt(8.0 * crack_area / (kTriangleArea * o.max_triangles)));
}

// The crack vertices of all fragments, welded by position.
struct CrackPoints {
  std::map<PositionKey, size_t> index;
  std::vector<Vec3> points;
  std::vector<std::vector<size_t>> users;  // fragments per point, ascending
  std::vector<char> rim;                   // the object's surface uses the point too
  std::vector<double> area;                // a third of the crack triangles around the point, over its fragments
};

// Step 1: refines every fragment's crack faces to `edge` and welds their vertices across the fragments.
CrackPoints weld_crack_points(FragmentSet& set, double edge) {
  CrackPoints c;
  for (size_t f = 0; f < set.fragments.size(); ++f) {
    Fragment& frag = set.fragments[f];
    if (!has_crack(frag)) continue;
    refine_crack_faces(frag.mesh, frag.crack_faces, edge);
    for (size_t t = 0; t < frag.mesh.triangles.size(); ++t) {
      if (!frag.crack_faces[t]) continue;
      const double third = area_normal(frag.mesh, t).norm() / 3.0;
      for (int k = 0; k < 3; ++k) {
        const auto [it, added] = c.index.emplace(key_of(corner(frag.mesh, t, k)), c.points.size());
        if (added) {
          c.points.push_back(corner(frag.mesh, t, k));
          c.users.emplace_back();
          c.rim.push_back(0);
          c.area.push_back(0.0);
        }
        c.area[it->second] += third;
        std::vector<size_t>& u = c.users[it->second];
        if (u.empty() || u.back() != f) u.push_back(f);
      }
    }
  }
  for (const Fragment& frag : set.fragments) {
    if (!has_crack(frag)) continue;
    for (size_t t = 0; t < frag.mesh.triangles.size(); ++t) {
      if (frag.crack_faces[t]) continue;
      for (int k = 0; k < 3; ++k) {
        const auto it = c.index.find(key_of(corner(frag.mesh, t, k)));
        if (it != c.index.end()) c.rim[it->second] = 1;
      }
    }
  }
  return c;
}

// Step 2: an oriented normal field. Each crack triangle of fragment f faces some fragment g across the
// crack (the nearest crack triangle of another fragment); it adds its area normal to a grid, pointing from
// the lower-numbered fragment of the two to the higher, so both faces of a crack add the same normal.
// Everything that moves a vertex later is a function of its position only (grid fields and the distance to
// the fixed points), so copies of a point on either side move alike even where the two sides were
// triangulated differently.
class CrackNormalField {
 public:
  CrackNormalField(const FragmentSet& set, double edge, double grid) : normal_(grid), area_(grid) {
    std::vector<TriangleIndex> crack_index(set.fragments.size());
    std::vector<std::pair<Vec3, Vec3>> box(set.fragments.size());
    const double reach = 2.0 * edge;
    for (size_t f = 0; f < set.fragments.size(); ++f) {
      const Fragment& frag = set.fragments[f];
      if (!has_crack(frag)) continue;
      std::vector<Tri> tris;
      for (size_t t = 0; t < frag.mesh.triangles.size(); ++t)
        if (frag.crack_faces[t]) tris.push_back(frag.mesh.triangles[t]);
      crack_index[f] = TriangleIndex(frag.mesh.positions, tris, edge, reach);
      bounding_box(frag.mesh, box[f].first, box[f].second);
    }
    for (size_t f = 0; f < set.fragments.size(); ++f) {
      const Fragment& frag = set.fragments[f];
      if (!has_crack(frag)) continue;
      for (size_t t = 0; t < frag.mesh.triangles.size(); ++t) {
        if (!frag.crack_faces[t]) continue;
        const Vec3 an = area_normal(frag.mesh, t);
        const Vec3 centre = (corner(frag.mesh, t, 0) + corner(frag.mesh, t, 1) + corner(frag.mesh, t, 2)) / 3.0;
        size_t across = SIZE_MAX;
        double best = reach;
        for (size_t g = 0; g < set.fragments.size(); ++g) {
          if (g == f || crack_index[g].empty()) continue;
          if (((centre.array() < box[g].first.array() - reach) || (centre.array() > box[g].second.array() + reach)).any())
            continue;
          const TriangleIndex::Hit hit = crack_index[g].closest(centre, best);
          if (hit.found && hit.distance < best) {
            best = hit.distance;
            across = g;
          }
        }
        if (across == SIZE_MAX) continue;  // no other fragment across (a crack ending inside this one)
        normal_.add(centre, f < across ? an : Vec3(-an));
        area_.add(centre, an.norm());
      }
    }
  }
  // The area-weighted mean oriented normal at x (shorter where normals cancel).
  Vec3 mean(const Vec3& x) const {
    const double w = area_.gather(x);
    return w > 0 ? Vec3(normal_.gather(x) / w) : Vec3(Vec3::Zero());
  }

 private:
  ScatterGrid<Vec3> normal_;
  ScatterGrid<double> area_;
};

// Step 3: the damage time and its gradient (Eq. 3.13, 3.14) at the points, the chevron lines of
// Algorithm 4, and their heights on a grid: 1 on every line, 2 - r on the longest share `enhanced` of them
// (r: arc length from the source over the length).
ScatterGrid<double> chevron_heights(const CrackPoints& c, const CrackNormalField& normals, const DamageTimeGrid& grid,
                                    const FractureDetailOptions& o, double edge, FractureDetailReport& report) {
  const size_t n = c.points.size();
  std::vector<double> time(n, std::numeric_limits<double>::quiet_NaN());
  std::vector<Vec3> gradient(n, Vec3::Zero()), normal(n, Vec3::Zero());
  for (size_t p = 0; p < n; ++p) {
    const Vec3 m = normals.mean(c.points[p]);
    if (m.norm() > 0) normal[p] = m.normalized();
    if (const std::optional<double> t = grid.time(c.points[p])) {
      time[p] = *t;
      gradient[p] = grid.gradient(c.points[p]);
      ++report.timed_vertices;
    }
  }
  const std::vector<std::vector<size_t>> lines =
      trace_chevron_lines(c.points, normal, time, gradient, o.step, o.max_steps, o.radius);
  std::vector<double> length(lines.size(), 0.0);
  for (size_t l = 0; l < lines.size(); ++l)
    for (size_t k = 1; k < lines[l].size(); ++k) length[l] += (c.points[lines[l][k]] - c.points[lines[l][k - 1]]).norm();
  std::vector<size_t> by_length(lines.size());
  std::iota(by_length.begin(), by_length.end(), size_t{0});
  std::stable_sort(by_length.begin(), by_length.end(), [&](size_t a, size_t b) { return length[a] > length[b]; });
  // m is a share of the lines that mark something (two or more points); they come first by length.
  const size_t marking = static_cast<size_t>(std::count_if(lines.begin(), lines.end(), [](const auto& l) { return l.size() >= 2; }));
  const size_t enhanced = static_cast<size_t>(std::floor(o.enhanced * static_cast<double>(marking)));
  ScatterGrid<double> heights(o.grid);  // beta_i = sum_v w_iv beta_v
  const double reference_area = kTriangleArea * edge * edge;  // a vertex's share at edge d
  for (size_t rank = 0; rank < by_length.size(); ++rank) {
    const std::vector<size_t>& line = lines[by_length[rank]];
    if (line.size() < 2) continue;  // a lone point marks nothing
    ++report.lines;
    report.longest_line = std::max(report.longest_line, line.size());
    const bool enhance = rank < enhanced && length[by_length[rank]] > 0;
    report.enhanced_lines += enhance;
    double along = 0;
    for (size_t k = 0; k < line.size(); ++k) {
      if (k) along += (c.points[line[k]] - c.points[line[k - 1]]).norm();
      // Each vertex stands for its share of the surface: with the refinement's uneven vertex density an
      // unweighted sum would add noise of that density to the marks (the thesis refines uniformly).
      const double share = c.area[line[k]] / (static_cast<double>(c.users[line[k]].size()) * reference_area);
      heights.add(c.points[line[k]], share * (1.0 + (enhance ? 1.0 - along / length[by_length[rank]] : 0.0)));
    }
  }
  return heights;
}

// Step 4: moves every copy of every crack point to `moved`, counts the crack triangles that folded over,
// gives crack triangles smooth normals, and computes the fragments' mass properties again.
void move_crack_points(FragmentSet& set, const CrackPoints& c, const std::vector<Vec3>& moved, double density,
                       FractureDetailReport& report) {
  for (Fragment& frag : set.fragments) {
    if (!has_crack(frag)) continue;
    TriMesh& mesh = frag.mesh;
    std::vector<Vec3> before_normal(mesh.triangles.size(), Vec3::Zero());
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      if (frag.crack_faces[t]) before_normal[t] = area_normal(mesh, t);
    for (Vec3& x : mesh.positions) {
      const auto it = c.index.find(key_of(x));
      if (it != c.index.end()) x = moved[it->second];
    }
    for (size_t t = 0; t < mesh.triangles.size(); ++t)
      if (frag.crack_faces[t] && area_normal(mesh, t).dot(before_normal[t]) <= 0) ++report.folded_triangles;
    if (mesh.has_normals()) smooth_crack_normals(mesh, frag.crack_faces);
    frag.crack_triangles = static_cast<size_t>(std::count(frag.crack_faces.begin(), frag.crack_faces.end(), 1));
    frag.properties = mass_properties(mesh, density);
  }
}

}  // namespace

FractureDetailReport add_fracture_detail(FragmentSet& set, const std::vector<Vec3>& rest,
                                         const std::vector<ParticleDamage>& damage, const FractureDetailOptions& o,
                                         double density) {
  FractureDetailReport report;
  if (!o.enabled()) return report;
  if (!(o.edge > 0) || !(o.step > 0) || !(o.grid > 0) || !(o.radius >= 0) || o.max_steps < 0 || !(o.max_triangles >= 1) ||
      !(o.enhanced >= 0 && o.enhanced <= 1))
    throw InputError("fracture detail: edge, step and grid must be positive, radius and max_steps not negative, "
                     "enhanced in [0, 1]");
  const auto t0 = std::chrono::steady_clock::now();
  const double edge = detail_edge(set, o);
  report.edge = edge;
  const CrackPoints c = weld_crack_points(set, edge);
  const size_t n = c.points.size();
  report.crack_vertices = n;
  if (n == 0) return report;
  const CrackNormalField normals(set, edge, o.grid);
  const ScatterGrid<double> heights = chevron_heights(c, normals, DamageTimeGrid(rest, damage, o.grid), o, edge, report);

  // x' = x + n beta' G (beta'_v = sum_i w_iv beta_i, unnormalised), faded to zero within 2 d of the fixed
  // points: rims and points where three or more fragments meet.
  std::vector<Vec3> fixed_points;
  for (size_t p = 0; p < n; ++p)
    if (c.rim[p] || c.users[p].size() >= 3) fixed_points.push_back(c.points[p]);
  const double fade = 2.0 * edge;
  const PointHash fixed_hash(fixed_points, fade);
  std::vector<Vec3> moved(n);
  for (size_t p = 0; p < n; ++p) {
    const Vec3& x = c.points[p];
    const size_t near = fixed_hash.nearest(x, fade);
    const double taper = near == SIZE_MAX ? 1.0 : (fixed_points[near] - x).norm() / fade;
    const Vec3 d = normals.mean(x) * (heights.gather(x) * o.height * taper);
    moved[p] = x + d;
    if (d.squaredNorm() > 0) ++report.moved_vertices;
    report.max_displacement = std::max(report.max_displacement, d.norm());
  }
  move_crack_points(set, c, moved, density, report);
  report.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return report;
}

}  // namespace shellfrac::brittle
