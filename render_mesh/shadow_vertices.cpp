// Step 2 of the cracked render mesh (thesis sec. 4.9.3): shadow vertices, so that fragments share no
// vertex. See docs/render-mesh.md for the sector rule.
#include "render_mesh/cracked_tessellation.hpp"
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

ParameterMesh separate_crack_vertices(const ParameterMesh& split, double shadow_offset) {
  if (!(shadow_offset >= 0.0)) throw std::invalid_argument("shadow offset must be non-negative");
  ParameterMesh out;
  out.face_offsets = split.face_offsets;
  out.crack_edge = split.crack_edge;
  std::vector<int> kept(split.uv.size(), -1);
  for (int v = 0; v < split.num_vertices(); ++v)
    if (!split.on_crack[static_cast<size_t>(v)]) {
      kept[static_cast<size_t>(v)] = out.num_vertices();
      out.uv.push_back(split.uv[static_cast<size_t>(v)]);
      out.on_crack.push_back(0);
      out.source_vertex.push_back(v);
    }

  // Corner c is face_vertices[c]; its neighbours along its face.
  const int corners = static_cast<int>(split.face_vertices.size());
  std::vector<int> next(static_cast<size_t>(corners)), prev(static_cast<size_t>(corners));
  for (int f = 0; f < split.num_faces(); ++f) {
    const int begin = split.face_offsets[static_cast<size_t>(f)], end = split.face_offsets[static_cast<size_t>(f) + 1];
    for (int c = begin; c < end; ++c) {
      next[static_cast<size_t>(c)] = c + 1 < end ? c + 1 : begin;
      prev[static_cast<size_t>(c)] = c > begin ? c - 1 : end - 1;
    }
  }
  auto vertex = [&](int c) { return split.face_vertices[static_cast<size_t>(c)]; };
  auto key = [&](int from, int to) { return static_cast<long long>(from) * split.num_vertices() + to; };
  std::unordered_map<long long, int> corner_of_edge;  // directed edge -> the corner it leaves
  for (int c = 0; c < corners; ++c) {
    const int from = vertex(c), to = vertex(next[static_cast<size_t>(c)]);
    if (split.on_crack[static_cast<size_t>(to)]) corner_of_edge[key(from, to)] = c;  // only twins looked up
  }

  // Corners around a crack vertex that meet across an edge not on the crack form one sector: one side
  // of the crack locally. Each sector gets one shadow, so a fragment stays watertight. cw[c] is the
  // corner beyond c's outgoing edge, clockwise about the vertex; ccw is the inverse.
  std::vector<int> cw(static_cast<size_t>(corners), -1), ccw(static_cast<size_t>(corners), -1), face_of(static_cast<size_t>(corners));
  for (int f = 0; f < split.num_faces(); ++f)
    for (int c = split.face_offsets[static_cast<size_t>(f)]; c < split.face_offsets[static_cast<size_t>(f) + 1]; ++c)
      face_of[static_cast<size_t>(c)] = f;
  for (int c = 0; c < corners; ++c) {
    const int v = vertex(c), w = vertex(next[static_cast<size_t>(c)]);
    if (!split.on_crack[static_cast<size_t>(v)] || split.crack_edge[static_cast<size_t>(c)]) continue;
    const auto twin = corner_of_edge.find(key(w, v));
    if (twin == corner_of_edge.end()) continue;  // patch boundary
    cw[static_cast<size_t>(c)] = next[static_cast<size_t>(twin->second)];
    ccw[static_cast<size_t>(cw[static_cast<size_t>(c)])] = c;
  }

  // A sector spans counter-clockwise from the outgoing edge of its first (clockwise-most) corner
  // through the sum of its corners' interior angles (2 pi around a crack tip).
  struct Sector {
    int first = -1;  // -1: the corners close around the vertex, nothing to separate
    double angle = 0.0, shortest = 1e300;
    int shadow = -1;
  };
  std::vector<Sector> sectors;
  std::vector<int> sector_of(static_cast<size_t>(corners), -1);
  auto direction = [&](int from, int to) { return Vec2(split.uv[static_cast<size_t>(to)] - split.uv[static_cast<size_t>(from)]); };
  auto add_corner = [&](Sector& sector, int c) {
    const int v = vertex(c);
    const Vec2 to_next = direction(v, vertex(next[static_cast<size_t>(c)]));
    const Vec2 to_prev = direction(v, vertex(prev[static_cast<size_t>(c)]));
    double interior = std::atan2(cross2(to_next, to_prev), to_next.dot(to_prev));
    if (interior <= 0.0) interior += kTwoPi;
    sector.angle += interior;
    sector.shortest = std::min({sector.shortest, to_next.norm(), to_prev.norm()});
    // Twice the clearance to the face's edges that do not end at v (e.g. a quad edge just beyond a
    // crack tip), so that the shadow cannot leave the sector.
    const int f = face_of[static_cast<size_t>(c)];
    const Vec2& p = split.uv[static_cast<size_t>(v)];
    for (int k = split.face_offsets[static_cast<size_t>(f)]; k < split.face_offsets[static_cast<size_t>(f) + 1]; ++k) {
      const int a = vertex(k), b = vertex(next[static_cast<size_t>(k)]);
      if (a == v || b == v) continue;
      const Vec2 &pa = split.uv[static_cast<size_t>(a)], ab = split.uv[static_cast<size_t>(b)] - pa;
      const double t = std::clamp((p - pa).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      sector.shortest = std::min(sector.shortest, 2.0 * (pa + t * ab - p).norm());
    }
    sector_of[static_cast<size_t>(c)] = static_cast<int>(sectors.size()) - 1;
  };
  for (int c = 0; c < corners; ++c) {
    if (!split.on_crack[static_cast<size_t>(vertex(c))] || cw[static_cast<size_t>(c)] >= 0) continue;
    // A face never takes the same shadow twice (a crack tip on a quad edge would pinch its face):
    // where the walk meets a face again, a new sector starts.
    std::vector<int> faces;
    for (int corner = c; corner >= 0; corner = ccw[static_cast<size_t>(corner)]) {
      if (faces.empty() || std::find(faces.begin(), faces.end(), face_of[static_cast<size_t>(corner)]) != faces.end()) {
        sectors.emplace_back();
        sectors.back().first = corner;
        faces.clear();
      }
      faces.push_back(face_of[static_cast<size_t>(corner)]);
      add_corner(sectors.back(), corner);
    }
  }
  for (int c = 0; c < corners; ++c)
    if (split.on_crack[static_cast<size_t>(vertex(c))] && sector_of[static_cast<size_t>(c)] < 0) {
      sectors.emplace_back();
      for (int corner = c; corner >= 0 && sector_of[static_cast<size_t>(corner)] < 0; corner = ccw[static_cast<size_t>(corner)])
        add_corner(sectors.back(), corner);
    }

  out.face_vertices.reserve(split.face_vertices.size());
  for (int c = 0; c < corners; ++c) {
    const int v = vertex(c);
    if (!split.on_crack[static_cast<size_t>(v)]) {
      out.face_vertices.push_back(kept[static_cast<size_t>(v)]);
      continue;
    }
    Sector& sector = sectors[static_cast<size_t>(sector_of[static_cast<size_t>(c)])];
    if (sector.shadow < 0) {
      // Thesis 4.9.3 / Fig. 4.17: move by Dv along the bisector of the sector, into it.
      Vec2 shadow = split.uv[static_cast<size_t>(v)];
      if (sector.first >= 0) {
        const Vec2 start = direction(v, vertex(next[static_cast<size_t>(sector.first)])).normalized();
        const double cs = std::cos(0.5 * sector.angle), sn = std::sin(0.5 * sector.angle);
        const Vec2 bisector(cs * start.x() - sn * start.y(), sn * start.x() + cs * start.y());
        shadow += std::min(shadow_offset, 0.25 * sector.shortest) * bisector;
      }
      sector.shadow = out.num_vertices();
      out.uv.push_back(shadow);
      out.on_crack.push_back(1);
      out.source_vertex.push_back(v);
    }
    out.face_vertices.push_back(sector.shadow);
  }
  return out;
}

}  // namespace shellfrac::render_mesh
