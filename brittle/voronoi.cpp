#include "brittle/voronoi.hpp"

#include <voro++/voro++.hh>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>
#include <unordered_map>

#include "brittle/errors.hpp"

namespace shellfrac::brittle {

namespace {

std::string describe(size_t i, const Vec3& p) {
  std::ostringstream m;
  m << "site " << i << " at (" << p.transpose() << ")";
  return m.str();
}

// Welds points closer than `tol` (hash grid of cell tol, neighbouring cells searched).
class Welder {
 public:
  explicit Welder(double tol) : tol_(tol), inv_(1.0 / tol) {}
  int add(const Vec3& p, std::vector<Vec3>& out) {
    const Eigen::Array3d q = (p.array() * inv_).floor();
    const Key k{static_cast<long long>(q.x()), static_cast<long long>(q.y()), static_cast<long long>(q.z())};
    for (long long dz = -1; dz <= 1; ++dz)
      for (long long dy = -1; dy <= 1; ++dy)
        for (long long dx = -1; dx <= 1; ++dx) {
          const auto it = map_.find(Key{k.x + dx, k.y + dy, k.z + dz});
          if (it == map_.end()) continue;
          for (int id : it->second)
            if ((out[static_cast<size_t>(id)] - p).norm() <= tol_) return id;
        }
    const int id = static_cast<int>(out.size());
    out.push_back(p);
    map_[k].push_back(id);
    return id;
  }

 private:
  struct Key {
    long long x, y, z;
    bool operator==(const Key& o) const { return x == o.x && y == o.y && z == o.z; }
  };
  struct Hash {
    size_t operator()(const Key& k) const {
      unsigned long long h = static_cast<unsigned long long>(k.x) * 0x9E3779B97F4A7C15ULL;
      h ^= static_cast<unsigned long long>(k.y) * 0xC2B2AE3D27D4EB4FULL + (h << 6) + (h >> 2);
      h ^= static_cast<unsigned long long>(k.z) * 0x165667B19E3779F9ULL + (h << 6) + (h >> 2);
      return static_cast<size_t>(h);
    }
  };
  double tol_, inv_;
  std::unordered_map<Key, std::vector<int>, Hash> map_;
};

// Newell normal (times 2 area) of a polygon.
Vec3 polygon_normal(const std::vector<Vec3>& p) {
  Vec3 n = Vec3::Zero();
  for (size_t i = 0; i < p.size(); ++i) n += p[i].cross(p[(i + 1) % p.size()]);
  return n;
}

struct CellFace {
  int cell, neighbour;
  std::vector<int> vertices;  // outward from `cell`
};

// Finite sites strictly inside the box, no two within 1e-9 of its diagonal (coincident sites would give
// voro++ an empty cell): the offenders are named.
void check_sites(const std::vector<Vec3>& sites, const Vec3& lo, const Vec3& hi) {
  const size_t n = sites.size();
  for (size_t i = 0; i < n; ++i) {
    if (!sites[i].allFinite()) throw NumericalError("Voronoi diagram: " + describe(i, sites[i]) + " is not finite");
    if ((sites[i].array() <= lo.array()).any() || (sites[i].array() >= hi.array()).any())
      throw NumericalError("Voronoi diagram: " + describe(i, sites[i]) + " lies outside the container box");
  }
  std::vector<size_t> order(n);
  for (size_t i = 0; i < n; ++i) order[i] = i;
  std::sort(order.begin(), order.end(), [&](size_t a, size_t b) { return sites[a].x() < sites[b].x(); });
  const double tol = 1e-9 * (hi - lo).norm();
  for (size_t a = 0; a < n; ++a)
    for (size_t b = a + 1; b < n && sites[order[b]].x() - sites[order[a]].x() <= tol; ++b)
      if ((sites[order[a]] - sites[order[b]]).norm() <= tol)
        throw NumericalError("Voronoi diagram: " + describe(order[a], sites[order[a]]) + " and " +
                             describe(order[b], sites[order[b]]) + " coincide");
}

// Gives every vertex of every cell one index in the diagram's vertex list. A vertex where exactly three
// faces of a cell meet is the point shared by that cell and the three neighbours across those faces: the
// sorted four site ids name it exactly, whichever cell computes it. Other vertices (degenerate, or on the
// container walls) are welded by position.
class SharedVertices {
 public:
  SharedVertices(double tol, std::vector<Vec3>& vertices) : welder_(tol), vertices_(vertices) {}

  // The diagram indices of one cell's vertices (coords: x, y, z per vertex).
  std::vector<int> weld(int id, const std::vector<int>& neighbours, const std::vector<int>& face_vertices,
                        const std::vector<double>& coords) {
    const size_t nv = coords.size() / 3;
    std::vector<std::array<int, 4>> around(nv, {id, 0, 0, 0});
    std::vector<int> degree(nv, 0);
    for (size_t f = 0, k = 0; f < neighbours.size(); ++f) {
      const int count = face_vertices[k++];
      for (int c = 0; c < count; ++c) {
        const size_t v = static_cast<size_t>(face_vertices[k++]);
        if (degree[v] < 3) around[v][static_cast<size_t>(1 + degree[v])] = neighbours[f];
        ++degree[v];
      }
    }
    std::vector<int> welded(nv);
    for (size_t v = 0; v < nv; ++v) {
      const Vec3 p(coords[3 * v], coords[3 * v + 1], coords[3 * v + 2]);
      std::array<int, 4> key = around[v];
      if (degree[v] == 3 && key[1] >= 0 && key[2] >= 0 && key[3] >= 0) {
        std::sort(key.begin(), key.end());
        const auto [it, added] = by_sites_.try_emplace(key, 0);
        if (added) it->second = welder_.add(p, vertices_);
        welded[v] = it->second;
      } else {
        welded[v] = welder_.add(p, vertices_);
      }
    }
    return welded;
  }

 private:
  Welder welder_;
  std::vector<Vec3>& vertices_;
  std::map<std::array<int, 4>, int> by_sites_;
};

// One cell's faces as polygons of welded vertices, oriented away from its site; faces collapsed by the
// welding are dropped.
void add_cell_faces(int id, const Vec3& site, const std::vector<int>& neighbours, const std::vector<int>& face_vertices,
                    const std::vector<int>& welded, const std::vector<Vec3>& vertices, std::vector<CellFace>& records) {
  size_t k = 0;
  for (size_t f = 0; f < neighbours.size(); ++f) {
    const int count = face_vertices[k++];
    CellFace rec{id, neighbours[f], {}};
    for (int c = 0; c < count; ++c) {
      const int v = welded[static_cast<size_t>(face_vertices[k++])];
      if (rec.vertices.empty() || rec.vertices.back() != v) rec.vertices.push_back(v);
    }
    while (rec.vertices.size() > 1 && rec.vertices.front() == rec.vertices.back()) rec.vertices.pop_back();
    if (rec.vertices.size() < 3) continue;  // zero area
    std::vector<Vec3> poly;
    for (int v : rec.vertices) poly.push_back(vertices[static_cast<size_t>(v)]);
    Vec3 centre = Vec3::Zero();
    for (const Vec3& p : poly) centre += p / static_cast<double>(poly.size());
    if (polygon_normal(poly).dot(centre - site) < 0) std::reverse(rec.vertices.begin(), rec.vertices.end());
    records.push_back(std::move(rec));
  }
}

// Appends the face between cells a and b (b < 0: a container wall) with its area and centroid.
void add_face(VoronoiDiagram& d, int a, int b, std::vector<int> verts) {
  VoronoiFace f;
  f.cell_a = a;
  f.cell_b = b;
  f.vertices = std::move(verts);
  std::vector<Vec3> poly;
  for (int v : f.vertices) poly.push_back(d.vertices[static_cast<size_t>(v)]);
  f.area = 0.5 * polygon_normal(poly).norm();
  // Area-weighted centroid of the fan.
  Vec3 c = Vec3::Zero();
  double a2 = 0;
  for (size_t i = 1; i + 1 < poly.size(); ++i) {
    const double t = (poly[i] - poly[0]).cross(poly[i + 1] - poly[0]).norm();
    c += t * (poly[0] + poly[i] + poly[i + 1]) / 3.0;
    a2 += t;
  }
  f.centroid = a2 > 0 ? Vec3(c / a2) : poly[0];
  const int id = static_cast<int>(d.faces.size());
  d.faces.push_back(std::move(f));
  d.cell_faces[static_cast<size_t>(a)].push_back(id);
  if (b >= 0) d.cell_faces[static_cast<size_t>(b)].push_back(id);
}

// One face per cell pair: the lower cell's polygon where it has one, else the other's reversed; then
// the container walls.
void add_faces(const std::vector<CellFace>& records, VoronoiDiagram& d) {
  std::map<std::pair<int, int>, std::pair<int, int>> by_pair;  // (lo, hi) -> (record from lo, from hi)
  for (size_t r = 0; r < records.size(); ++r) {
    const CellFace& rec = records[r];
    if (rec.neighbour < 0) continue;
    const auto key = std::minmax(rec.cell, rec.neighbour);
    auto it = by_pair.emplace(std::make_pair(key.first, key.second), std::make_pair(-1, -1)).first;
    (rec.cell == key.first ? it->second.first : it->second.second) = static_cast<int>(r);
  }
  for (const auto& [key, recs] : by_pair) {
    if (recs.first >= 0) {
      add_face(d, key.first, key.second, records[static_cast<size_t>(recs.first)].vertices);
    } else {
      std::vector<int> v = records[static_cast<size_t>(recs.second)].vertices;
      std::reverse(v.begin(), v.end());
      add_face(d, key.first, key.second, v);
    }
  }
  for (const CellFace& rec : records)
    if (rec.neighbour < 0) add_face(d, rec.cell, rec.neighbour, rec.vertices);
  for (auto& faces : d.cell_faces) std::sort(faces.begin(), faces.end());
}

}  // namespace

VoronoiDiagram compute_voronoi(const std::vector<Vec3>& sites, const Vec3& lo, const Vec3& hi) {
  VoronoiDiagram d;
  d.sites = sites;
  d.box_lo = lo;
  d.box_hi = hi;
  const size_t n = sites.size();
  d.cell_faces.assign(n, {});
  d.cell_volume.assign(n, 0.0);
  if (n == 0) return d;
  if (!((hi - lo).minCoeff() > 0)) throw NumericalError("Voronoi diagram: the container box is empty");
  check_sites(sites, lo, hi);
  // About five sites per voro++ block.
  const double per_block = std::cbrt(static_cast<double>(n) / 5.0);
  const Vec3 ext = hi - lo;
  const double scale = per_block / std::cbrt(ext.prod());
  int nb[3];
  for (int a = 0; a < 3; ++a) nb[a] = std::max(1, std::min(256, static_cast<int>(std::ceil(ext[a] * scale))));
  voro::container con(lo.x(), hi.x(), lo.y(), hi.y(), lo.z(), hi.z(), nb[0], nb[1], nb[2], false, false, false, 8);
  for (size_t i = 0; i < n; ++i) con.put(static_cast<int>(i), sites[i].x(), sites[i].y(), sites[i].z());

  // 1e-9 of the diagonal: far above the round-off between cells, far below any real edge.
  SharedVertices shared(1e-9 * (hi - lo).norm(), d.vertices);
  std::vector<CellFace> records;
  std::vector<char> done(n, 0);
  voro::c_loop_all loop(con);
  voro::voronoicell_neighbor cell;
  std::vector<int> neighbours, face_vertices;
  std::vector<double> coords;
  if (loop.start()) do {
      const int id = loop.pid();
      const size_t i = static_cast<size_t>(id);
      if (!con.compute_cell(cell, loop))
        throw NumericalError("Voronoi diagram: voro++ could not compute the cell of " + describe(i, sites[i]));
      double x, y, z;
      loop.pos(x, y, z);
      cell.neighbors(neighbours);
      cell.face_vertices(face_vertices);
      cell.vertices(x, y, z, coords);
      d.cell_volume[i] = cell.volume();
      done[i] = 1;
      const std::vector<int> welded = shared.weld(id, neighbours, face_vertices, coords);
      add_cell_faces(id, sites[i], neighbours, face_vertices, welded, d.vertices, records);
    } while (loop.inc());
  for (size_t i = 0; i < n; ++i)
    if (!done[i]) throw NumericalError("Voronoi diagram: voro++ skipped " + describe(i, sites[i]));
  add_faces(records, d);
  return d;
}

}  // namespace shellfrac::brittle
