#include "brittle/tri_mesh.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <sstream>
#include <tuple>

#include "brittle/errors.hpp"

namespace shellfrac::brittle {

void TriMesh::append(const TriMesh& other) {
  const bool keep_normals = (positions.empty() || has_normals()) && other.has_normals();
  const bool keep_uvs = (positions.empty() || has_uvs()) && other.has_uvs();
  const int offset = static_cast<int>(positions.size());
  positions.insert(positions.end(), other.positions.begin(), other.positions.end());
  for (const Tri& t : other.triangles) triangles.push_back(t + Tri::Constant(offset));
  if (keep_normals)
    normals.insert(normals.end(), other.normals.begin(), other.normals.end());
  else
    normals.clear();
  if (keep_uvs)
    uvs.insert(uvs.end(), other.uvs.begin(), other.uvs.end());
  else
    uvs.clear();
}

namespace {

// Vertex ids after welding equal positions (split attribute seams share one id).
std::vector<int> weld_by_position(const std::vector<Vec3>& p) {
  std::vector<int> order(p.size());
  for (size_t i = 0; i < p.size(); ++i) order[i] = static_cast<int>(i);
  auto less = [&](int a, int b) {
    return std::tie(p[a].x(), p[a].y(), p[a].z()) < std::tie(p[b].x(), p[b].y(), p[b].z());
  };
  std::sort(order.begin(), order.end(), less);
  std::vector<int> id(p.size(), -1);
  for (size_t k = 0; k < order.size(); ++k) {
    const int i = order[k];
    id[i] = (k > 0 && p[order[k - 1]] == p[i]) ? id[order[k - 1]] : i;
  }
  return id;
}

// Vertices (welded ids) where the triangles around them form more than one fan. Around a vertex, the
// link graph has the other two corners of each triangle as nodes and each triangle as an edge between
// them; its connected components are the fans (triangles joined across an edge at the vertex, whatever
// the number of triangles on that edge, so a non-manifold edge is counted once, as an edge).
size_t count_non_manifold_vertices(std::vector<std::array<int, 3>> corners) {
  std::sort(corners.begin(), corners.end());  // (vertex, other, other), grouped by vertex
  size_t count = 0;
  std::vector<int> nodes, parent;
  for (size_t begin = 0; begin < corners.size();) {
    size_t end = begin;
    while (end < corners.size() && corners[end][0] == corners[begin][0]) ++end;
    nodes.clear();
    for (size_t k = begin; k < end; ++k) nodes.insert(nodes.end(), {corners[k][1], corners[k][2]});
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    parent.resize(nodes.size());
    for (size_t k = 0; k < parent.size(); ++k) parent[k] = static_cast<int>(k);
    auto local = [&](int w) { return static_cast<int>(std::lower_bound(nodes.begin(), nodes.end(), w) - nodes.begin()); };
    auto root = [&](int x) {
      while (parent[x] != x) x = parent[x] = parent[parent[x]];
      return x;
    };
    size_t fans = nodes.size();
    for (size_t k = begin; k < end; ++k) {
      const int x = root(local(corners[k][1])), y = root(local(corners[k][2]));
      if (x != y) {
        parent[x] = y;
        --fans;
      }
    }
    if (fans > 1) ++count;
    begin = end;
  }
  return count;
}

}  // namespace

MeshReport inspect_mesh(const TriMesh& mesh) {
  MeshReport r;
  const size_t nv = mesh.positions.size();
  for (const Vec3& v : mesh.positions) r.non_finite += v.allFinite() ? 0 : 1;
  for (const Vec3& v : mesh.normals) r.non_finite += v.allFinite() ? 0 : 1;
  for (const Vec2& v : mesh.uvs) r.non_finite += v.allFinite() ? 0 : 1;
  const std::vector<int> id = weld_by_position(mesh.positions);
  // Directed edge counts on welded ids.
  std::map<std::pair<int, int>, std::array<int, 2>> edges;  // (min, max) -> {forward uses, backward uses}
  std::vector<std::array<int, 3>> corners;                  // (vertex, next, previous) per triangle corner
  corners.reserve(3 * mesh.triangles.size());
  const Vec3 ref = nv > 0 ? mesh.positions.front() : Vec3::Zero();
  double six_volume = 0;
  for (const Tri& t : mesh.triangles) {
    bool ok = true;
    for (int k = 0; k < 3; ++k)
      if (t[k] < 0 || static_cast<size_t>(t[k]) >= nv) {
        ++r.bad_indices;
        ok = false;
      }
    if (!ok) continue;
    const Vec3 &a = mesh.positions[t[0]], &b = mesh.positions[t[1]], &c = mesh.positions[t[2]];
    const Vec3 n = (b - a).cross(c - a);
    if (!(n.norm() > 0)) ++r.degenerate_triangles;
    six_volume += (a - ref).dot((b - ref).cross(c - ref));
    const int w[3] = {id[t[0]], id[t[1]], id[t[2]]};
    // The exact cutter drops a triangle with two corners welded together; so does the topology here.
    if (w[0] == w[1] || w[1] == w[2] || w[0] == w[2]) continue;
    for (int k = 0; k < 3; ++k) {
      const int u = w[k], x = w[(k + 1) % 3];
      auto& e = edges[{std::min(u, x), std::max(u, x)}];
      ++e[u < x ? 0 : 1];
      corners.push_back({u, x, w[(k + 2) % 3]});
    }
  }
  for (const auto& [key, uses] : edges) {
    const int total = uses[0] + uses[1];
    if (total == 1) ++r.boundary_edges;
    if (total > 2) ++r.non_manifold_edges;
    if (total == 2 && uses[0] != 1) ++r.inconsistent_edges;
  }
  r.non_manifold_vertices = count_non_manifold_vertices(std::move(corners));
  r.volume = six_volume / 6.0;
  return r;
}

namespace {

// "1 boundary edge", "3 boundary edges".
std::string counted(size_t n, const std::string& one, const std::string& many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

}  // namespace

void require_closed_solid(const TriMesh& mesh, const std::string& source) {
  const MeshReport r = inspect_mesh(mesh);
  std::ostringstream why;
  if (mesh.triangles.empty()) {
    why << "it has no triangles";
  } else if (r.bad_indices > 0) {
    why << r.bad_indices << " triangle corners name vertices that do not exist";
  } else if (r.non_finite > 0) {
    why << r.non_finite << " vertex positions, normals or UVs are NaN or infinite";
  } else if (!r.closed_manifold()) {
    // Every count at once: a user fixing the file in an editor wants the whole list, not one per run.
    std::vector<std::string> parts;
    if (r.boundary_edges > 0) parts.push_back(counted(r.boundary_edges, "boundary edge", "boundary edges") + " (holes)");
    if (r.non_manifold_edges > 0)
      parts.push_back(counted(r.non_manifold_edges, "non-manifold edge", "non-manifold edges") + " (shared by more than two triangles)");
    if (r.non_manifold_vertices > 0)
      parts.push_back(counted(r.non_manifold_vertices, "non-manifold vertex", "non-manifold vertices") +
                      " (where parts touch at a point)");
    if (r.inconsistent_edges > 0)
      parts.push_back(counted(r.inconsistent_edges, "edge", "edges") + " with inconsistent orientation (flipped triangles)");
    why << "it is not a closed manifold surface: ";
    for (size_t k = 0; k < parts.size(); ++k) why << (k == 0 ? "" : ", ") << parts[k];
    why << " (a solid to break needs a watertight, consistently oriented surface)";
  } else if (!(std::abs(r.volume) > 0)) {
    why << "it encloses zero volume";
  } else if (r.volume < 0) {
    why << "it is inside out (negative volume " << r.volume << "; flip the triangle order)";
  }
  if (why.tellp() > 0) throw InputError(source + ": mesh '" + mesh.name + "' cannot be broken: " + why.str());
}

MassProperties mass_properties(const TriMesh& mesh, double density) {
  MassProperties mp;
  if (mesh.triangles.empty()) return mp;
  // Signed tetrahedra (ref, a, b, c): volume det/6, first moment V (ref + a + b + c)/4 and second moment
  // V/20 (sum v v^T + (sum v)(sum v)^T) with v relative to ref (exact for polynomials of degree 2).
  Vec3 lo, hi;
  bounding_box(mesh, lo, hi);
  const Vec3 ref = 0.5 * (lo + hi);
  double volume = 0;
  Vec3 first = Vec3::Zero();
  Mat3 second = Mat3::Zero();
  for (const Tri& t : mesh.triangles) {
    const Vec3 a = mesh.positions[t[0]] - ref, b = mesh.positions[t[1]] - ref, c = mesh.positions[t[2]] - ref;
    const double v = a.dot(b.cross(c)) / 6.0;
    const Vec3 s = a + b + c;
    volume += v;
    first += v * s / 4.0;
    second += (v / 20.0) * (a * a.transpose() + b * b.transpose() + c * c.transpose() + s * s.transpose());
  }
  mp.volume = volume;
  if (!(std::abs(volume) > 0)) return mp;
  const Vec3 centre = first / volume;
  mp.centroid = ref + centre;
  const Mat3 about_centre = second - volume * centre * centre.transpose();
  mp.mass = density * volume;
  mp.inertia = density * (about_centre.trace() * Mat3::Identity() - about_centre);
  return mp;
}

double surface_area(const TriMesh& mesh) {
  double a = 0;
  for (const Tri& t : mesh.triangles)
    a += 0.5 * (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]).norm();
  return a;
}

void bounding_box(const TriMesh& mesh, Vec3& lo, Vec3& hi) {
  lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  hi = -lo;
  for (const Vec3& p : mesh.positions) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
}

void compute_vertex_normals(TriMesh& mesh) {
  mesh.normals.assign(mesh.positions.size(), Vec3::Zero());
  for (const Tri& t : mesh.triangles) {
    const Vec3 n = (mesh.positions[t[1]] - mesh.positions[t[0]]).cross(mesh.positions[t[2]] - mesh.positions[t[0]]);
    for (int k = 0; k < 3; ++k) mesh.normals[t[k]] += n;
  }
  for (Vec3& n : mesh.normals) {
    const double l = n.norm();
    n = l > 0 ? Vec3(n / l) : Vec3::UnitZ();
  }
}

}  // namespace shellfrac::brittle
