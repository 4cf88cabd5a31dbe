#include "render_mesh/seam_joins.hpp"

#include <algorithm>
#include <cmath>

namespace shellfrac::render_mesh {

std::vector<SeamVertex> side_vertices(const PolyMesh& mesh, UvSide side, double tolerance) {
  std::vector<SeamVertex> out;
  if (mesh.uvs.size() != mesh.positions.size()) return out;
  std::vector<unsigned char> used(mesh.positions.size(), 0);
  for (int f = 0; f < mesh.num_faces(); ++f) {
    const int b = mesh.face_offsets[static_cast<size_t>(f)], e = mesh.face_offsets[static_cast<size_t>(f) + 1];
    if (e - b < 3) continue;
    for (int k = b; k < e; ++k) used[static_cast<size_t>(mesh.face_vertices[static_cast<size_t>(k)])] = 1;
  }
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    if (!used[static_cast<size_t>(v)]) continue;
    const Vec2& t = mesh.uvs[static_cast<size_t>(v)];
    const bool u_side = side == UvSide::u_min || side == UvSide::u_max;
    const double across = u_side ? t.x() : t.y();
    const double edge = side == UvSide::u_min || side == UvSide::v_min ? 0.0 : 1.0;
    if (std::abs(across - edge) <= tolerance) out.push_back({v, u_side ? t.y() : t.x()});
  }
  return out;
}

std::vector<VertexJoin> seam_joins(int mesh_a, const std::vector<SeamVertex>& a, int mesh_b,
                                   const std::vector<SeamVertex>& b, const std::vector<double>& crack_along,
                                   double max_gap) {
  std::vector<SeamVertex> sorted = b;
  std::sort(sorted.begin(), sorted.end(),
            [](const SeamVertex& x, const SeamVertex& y) { return x.along < y.along || (x.along == y.along && x.vertex < y.vertex); });
  auto separated = [&](double s, double t) {
    const double lo = std::min(s, t), hi = std::max(s, t);
    for (double c : crack_along)
      if (c > lo && c < hi) return true;
    return false;
  };
  std::vector<VertexJoin> joins;
  for (const SeamVertex& p : a) {
    // The nearest b vertex on each side of p's coordinate; of those not cut off by a crack, the nearer.
    const auto hi = std::lower_bound(sorted.begin(), sorted.end(), p.along,
                                     [](const SeamVertex& x, double s) { return x.along < s; });
    const SeamVertex* best = nullptr;
    double best_gap = max_gap;
    for (auto it : {hi, hi == sorted.begin() ? sorted.end() : hi - 1}) {
      if (it == sorted.end()) continue;
      const double gap = std::abs(it->along - p.along);
      if (gap <= best_gap && !separated(p.along, it->along) && (!best || gap < best_gap)) best = &*it, best_gap = gap;
    }
    if (best) joins.push_back({mesh_a, p.vertex, mesh_b, best->vertex});
  }
  return joins;
}

}  // namespace shellfrac::render_mesh
