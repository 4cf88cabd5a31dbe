#include "render_mesh/mesh_quality.hpp"

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include "render_mesh/triangulation.hpp"

namespace shellfrac::render_mesh {

namespace {

class UnionFind {
 public:
  explicit UnionFind(size_t n) : parent_(n) { std::iota(parent_.begin(), parent_.end(), size_t{0}); }
  size_t find(size_t a) {
    while (parent_[a] != a) a = parent_[a] = parent_[parent_[a]];
    return a;
  }
  void unite(size_t a, size_t b) {
    a = find(a), b = find(b);
    if (a != b) parent_[std::max(a, b)] = std::min(a, b);
  }

 private:
  std::vector<size_t> parent_;
};

bool same_faces(const PolyMesh& a, const PolyMesh& b) {
  return a.num_vertices() == b.num_vertices() && a.face_offsets == b.face_offsets && a.face_vertices == b.face_vertices;
}

void check_rest(const PolyMesh& current, const std::vector<Vec3>& rest, const char* what) {
  if (rest.size() != current.positions.size())
    throw std::invalid_argument(std::string(what) + ": " + std::to_string(rest.size()) + " rest positions for " +
                                std::to_string(current.positions.size()) + " vertices of mesh \"" + current.name + "\"");
}

// Calls visit(face, corner, rest length, current length) for every polygon side (a line: its one edge).
template <class Visit>
void for_each_side(const PolyMesh& current, const std::vector<Vec3>& rest, Visit&& visit) {
  for (int f = 0; f < current.num_faces(); ++f) {
    const int b = current.face_offsets[static_cast<size_t>(f)], e = current.face_offsets[static_cast<size_t>(f) + 1];
    if (e - b < 2) continue;
    const int edges = e - b == 2 ? 1 : e - b;
    for (int k = 0; k < edges; ++k) {
      const auto u = static_cast<size_t>(current.face_vertices[static_cast<size_t>(b + k)]);
      const auto v = static_cast<size_t>(current.face_vertices[static_cast<size_t>(b + (k + 1) % (e - b))]);
      visit(f, k, (rest[v] - rest[u]).norm(), (current.positions[v] - current.positions[u]).norm());
    }
  }
}

// The median rest length of the sides of positive rest length (0 when there are none): the mesh's
// typical edge, the scale below which a side or a face is too small to measure a stretch on.
double median_rest_side(const PolyMesh& current, const std::vector<Vec3>& rest) {
  std::vector<double> lengths;
  for_each_side(current, rest, [&](int, int, double rest_length, double) {
    if (rest_length > 0.0) lengths.push_back(rest_length);
  });
  if (lengths.empty()) return 0.0;
  const auto middle = lengths.begin() + static_cast<std::ptrdiff_t>(lengths.size() / 2);
  std::nth_element(lengths.begin(), middle, lengths.end());
  return *middle;
}

double diameter(const std::vector<Vec3>& corners) {
  double d = 0.0;
  for (size_t i = 0; i < corners.size(); ++i)
    for (size_t j = i + 1; j < corners.size(); ++j) d = std::max(d, (corners[i] - corners[j]).norm());
  return d;
}

}  // namespace

double face_area(const PolyMesh& mesh, int face) {
  double area = 0.0;
  for (const auto& t : face_triangles(mesh, face)) {
    const Vec3& a = mesh.positions[static_cast<size_t>(t[0])];
    area += 0.5 * (mesh.positions[static_cast<size_t>(t[1])] - a).cross(mesh.positions[static_cast<size_t>(t[2])] - a).norm();
  }
  return area;
}

PieceStats piece_stats(const std::vector<PolyMesh>& meshes, const std::vector<VertexJoin>& joins,
                       double min_piece_area) {
  if (!(min_piece_area >= 0.0)) throw std::invalid_argument("piece_stats: min_piece_area must be >= 0");
  std::vector<size_t> offset(meshes.size() + 1, 0);
  for (size_t m = 0; m < meshes.size(); ++m) offset[m + 1] = offset[m] + meshes[m].positions.size();
  UnionFind sets(offset.back());
  for (size_t m = 0; m < meshes.size(); ++m) {
    const PolyMesh& mesh = meshes[m];
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const int b = mesh.face_offsets[static_cast<size_t>(f)], e = mesh.face_offsets[static_cast<size_t>(f) + 1];
      if (e - b < 3) continue;
      for (int k = b + 1; k < e; ++k)
        sets.unite(offset[m] + static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(b)]),
                   offset[m] + static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(k)]));
    }
  }
  for (size_t j = 0; j < joins.size(); ++j) {
    const VertexJoin& join = joins[j];
    auto global = [&](int mesh, int vertex) {
      if (mesh < 0 || static_cast<size_t>(mesh) >= meshes.size() || vertex < 0 ||
          vertex >= meshes[static_cast<size_t>(mesh)].num_vertices())
        throw std::invalid_argument("piece_stats: join " + std::to_string(j) + " names vertex " + std::to_string(vertex) +
                                    " of mesh " + std::to_string(mesh) + ", which does not exist");
      return offset[static_cast<size_t>(mesh)] + static_cast<size_t>(vertex);
    };
    sets.unite(global(join.mesh_a, join.vertex_a), global(join.mesh_b, join.vertex_b));
  }

  PieceStats stats;
  std::vector<int> label_of_root(offset.back(), -1);
  stats.face_label.resize(meshes.size());
  for (size_t m = 0; m < meshes.size(); ++m) {
    const PolyMesh& mesh = meshes[m];
    stats.face_label[m].assign(static_cast<size_t>(mesh.num_faces()), -1);
    for (int f = 0; f < mesh.num_faces(); ++f) {
      const int b = mesh.face_offsets[static_cast<size_t>(f)], e = mesh.face_offsets[static_cast<size_t>(f) + 1];
      if (e - b < 3) continue;
      const size_t root = sets.find(offset[m] + static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(b)]));
      int& label = label_of_root[root];
      if (label < 0) {
        label = static_cast<int>(stats.component_area.size());
        stats.component_area.push_back(0.0);
      }
      stats.face_label[m][static_cast<size_t>(f)] = label;
      stats.component_area[static_cast<size_t>(label)] += face_area(mesh, f);
    }
  }
  for (const double area : stats.component_area) {
    const bool sliver = area < min_piece_area;
    stats.component_is_sliver.push_back(sliver ? 1 : 0);
    (sliver ? stats.slivers : stats.pieces) += 1;
    (sliver ? stats.sliver_area : stats.piece_area) += area;
  }
  return stats;
}

double principal_stretch(const Vec3& r0, const Vec3& r1, const Vec3& r2, const Vec3& c0, const Vec3& c1,
                         const Vec3& c2) {
  // Rest edges in an orthonormal frame (t1, t2) of the rest plane: R = [[|E1|, E2.t1], [0, E2.t2]].
  const Vec3 E1 = r1 - r0, E2 = r2 - r0;
  const Vec3 n = E1.cross(E2);
  const double l1 = E1.norm();
  if (!(n.norm() > 1e-14 * l1 * E2.norm())) return 0.0;  // zero rest area
  const Vec3 t1 = E1 / l1;
  const Vec3 t2 = n.cross(E1).normalized();
  Eigen::Matrix2d R;
  R << l1, E2.dot(t1), 0.0, E2.dot(t2);
  Eigen::Matrix<double, 3, 2> D;
  D.col(0) = c1 - c0;
  D.col(1) = c2 - c0;
  // F maps rest tangent vectors to current ones: F R = D (the affine map of the triangle).
  const Eigen::Matrix<double, 3, 2> F = D * R.inverse();
  const Eigen::Matrix2d C = F.transpose() * F;  // right Cauchy-Green tensor of the triangle
  const double half_trace = 0.5 * (C(0, 0) + C(1, 1));
  const double radius = std::sqrt(0.25 * (C(0, 0) - C(1, 1)) * (C(0, 0) - C(1, 1)) + C(0, 1) * C(0, 1));
  return std::sqrt(half_trace + radius);
}

EdgeStretch max_edge_stretch(const PolyMesh& current, const std::vector<Vec3>& rest) {
  check_rest(current, rest, "max_edge_stretch");
  const double floor = kShortSideFraction * median_rest_side(current, rest);
  EdgeStretch worst;
  for_each_side(current, rest, [&](int f, int k, double rest_length, double length) {
    if (!(rest_length > 0.0)) return;
    const double ratio = length / std::max(rest_length, floor);
    if (ratio > worst.ratio) worst = {ratio, f, k, length, rest_length};
  });
  return worst;
}

EdgeStretch max_edge_stretch(const PolyMesh& current, const PolyMesh& rest) {
  if (!same_faces(current, rest))
    throw std::invalid_argument("max_edge_stretch: the rest mesh of \"" + current.name + "\" has other faces");
  return max_edge_stretch(current, rest.positions);
}

double face_stretch(const std::vector<Vec3>& rest, const std::vector<Vec3>& current) {
  // Rest polygon in its own plane: the two principal axes of the centred rest corners.
  const size_t n = rest.size();
  Vec3 rc = Vec3::Zero(), cc = Vec3::Zero();
  for (size_t k = 0; k < n; ++k) {
    rc += rest[k] / static_cast<double>(n);
    cc += current[k] / static_cast<double>(n);
  }
  Eigen::MatrixXd R(static_cast<Eigen::Index>(n), 3), C(static_cast<Eigen::Index>(n), 3);
  for (size_t k = 0; k < n; ++k) {
    R.row(static_cast<Eigen::Index>(k)) = (rest[k] - rc).transpose();
    C.row(static_cast<Eigen::Index>(k)) = (current[k] - cc).transpose();
  }
  const Eigen::JacobiSVD<Eigen::MatrixXd> axes(R, Eigen::ComputeThinV);
  // Degenerate rest polygons carry no material: the tessellation leaves faces one crack-line nudge
  // (1e-9 of a cell) wide between a crack's vertices and their neighbours; their map is ill-determined
  // and read 10-8000x on tear-mode-one's cleanly separated last frame. A width below 1e-6 of the length
  // is such a face (a real sliver next to a crack is at least a shadow offset, 1e-5 of a cell, wide).
  if (axes.singularValues()(1) <= kDegenerateWidth * axes.singularValues()(0) || axes.singularValues()(0) == 0.0) return 0.0;
  const Eigen::MatrixXd P = R * axes.matrixV().leftCols(2);  // n x 2 rest coordinates
  // F (3 x 2) minimises sum_k |c_k - F p_k|^2: exact for triangles and for affinely deformed polygons.
  const Eigen::MatrixXd F = (C.transpose() * P) * (P.transpose() * P).inverse();
  return Eigen::JacobiSVD<Eigen::MatrixXd>(F).singularValues()(0);
}

StrandStats strand_area(const PolyMesh& current, const std::vector<Vec3>& rest_positions, double threshold) {
  check_rest(current, rest_positions, "strand_area");
  const double floor = kShortSideFraction * median_rest_side(current, rest_positions);
  StrandStats stats;
  std::vector<Vec3> rest, now;
  for (int f = 0; f < current.num_faces(); ++f) {
    const int b = current.face_offsets[static_cast<size_t>(f)], e = current.face_offsets[static_cast<size_t>(f) + 1];
    if (e - b < 3) continue;
    rest.clear();
    now.clear();
    for (int k = b; k < e; ++k) {
      rest.push_back(rest_positions[static_cast<size_t>(current.face_vertices[static_cast<size_t>(k)])]);
      now.push_back(current.positions[static_cast<size_t>(current.face_vertices[static_cast<size_t>(k)])]);
    }
    // A face smaller at rest than the short-side floor is measured as the sides are: by its current
    // size against the floor (a 1e-7 m triangle at a crack junction has an ill-determined map).
    double stretch = face_stretch(rest, now);
    if (diameter(rest) < floor) stretch = std::min(stretch, diameter(now) / floor);
    if (stretch > stats.max_principal_stretch) stats.max_principal_stretch = stretch, stats.worst_face = f;
    if (stretch > threshold) {
      ++stats.faces;
      stats.area += face_area(current, f);
    }
  }
  return stats;
}

StrandStats strand_area(const PolyMesh& current, const PolyMesh& rest, double threshold) {
  if (!same_faces(current, rest))
    throw std::invalid_argument("strand_area: the rest mesh of \"" + current.name + "\" has other faces");
  return strand_area(current, rest.positions, threshold);
}

}  // namespace shellfrac::render_mesh
