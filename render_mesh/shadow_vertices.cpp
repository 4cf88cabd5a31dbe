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

namespace {

// The corners of a face mesh (corner c is face_vertices[c]) with their neighbours along their face, and
// around the crack vertices: cw[c] is the corner beyond c's outgoing edge, clockwise about the vertex,
// where that edge is not on the crack; ccw is the inverse (-1: none).
struct Corners {
  std::vector<int> next, prev, face_of, cw, ccw;

  explicit Corners(const ParameterMesh& m) {
    const size_t n = m.face_vertices.size();
    next.resize(n);
    prev.resize(n);
    face_of.resize(n);
    cw.assign(n, -1);
    ccw.assign(n, -1);
    for (int f = 0; f < m.num_faces(); ++f) {
      const int begin = m.face_offsets[static_cast<size_t>(f)], end = m.face_offsets[static_cast<size_t>(f) + 1];
      for (int c = begin; c < end; ++c) {
        next[static_cast<size_t>(c)] = c + 1 < end ? c + 1 : begin;
        prev[static_cast<size_t>(c)] = c > begin ? c - 1 : end - 1;
        face_of[static_cast<size_t>(c)] = f;
      }
    }
    const auto vertex = [&](int c) { return m.face_vertices[static_cast<size_t>(c)]; };
    const auto key = [&](int from, int to) { return static_cast<long long>(from) * m.num_vertices() + to; };
    std::unordered_map<long long, int> corner_of_edge;  // directed edge -> the corner it leaves
    for (int c = 0; c < static_cast<int>(n); ++c) {
      const int from = vertex(c), to = vertex(next[static_cast<size_t>(c)]);
      if (m.on_crack[static_cast<size_t>(to)]) corner_of_edge[key(from, to)] = c;  // only twins looked up
    }
    for (int c = 0; c < static_cast<int>(n); ++c) {
      const int v = vertex(c), w = vertex(next[static_cast<size_t>(c)]);
      if (!m.on_crack[static_cast<size_t>(v)] || m.crack_edge[static_cast<size_t>(c)]) continue;
      const auto twin = corner_of_edge.find(key(w, v));
      if (twin == corner_of_edge.end()) continue;  // patch boundary
      cw[static_cast<size_t>(c)] = next[static_cast<size_t>(twin->second)];
      ccw[static_cast<size_t>(cw[static_cast<size_t>(c)])] = c;
    }
  }
};

// A sector spans counter-clockwise from the outgoing edge of its first (clockwise-most) corner
// through the sum of its corners' interior angles (2 pi around a crack tip).
struct Sector {
  int first = -1;  // -1: the corners close around the vertex, nothing to separate
  double angle = 0.0, shortest = 1e300;
  int shadow = -1;
};

// Corners around a crack vertex that meet across an edge not on the crack form one sector: one side
// of the crack locally. Each sector gets one shadow, so a fragment stays watertight.
class Sectors {
 public:
  Sectors(const ParameterMesh& m, const Corners& corners)
      : m_(m), k_(corners), sector_of_(m.face_vertices.size(), -1) {
    const int n = static_cast<int>(m.face_vertices.size());
    for (int c = 0; c < n; ++c) {
      if (!m.on_crack[static_cast<size_t>(vertex(c))] || k_.cw[static_cast<size_t>(c)] >= 0) continue;
      // A face never takes the same shadow twice (a crack tip on a quad edge would pinch its face):
      // where the walk meets a face again, a new sector starts.
      std::vector<int> faces;
      for (int corner = c; corner >= 0; corner = k_.ccw[static_cast<size_t>(corner)]) {
        const int f = k_.face_of[static_cast<size_t>(corner)];
        if (faces.empty() || std::find(faces.begin(), faces.end(), f) != faces.end()) {
          sectors_.emplace_back();
          sectors_.back().first = corner;
          faces.clear();
        }
        faces.push_back(f);
        add_corner(corner);
      }
    }
    for (int c = 0; c < n; ++c)  // closed fans (no crack edge around an interior crack vertex)
      if (m.on_crack[static_cast<size_t>(vertex(c))] && sector_of_[static_cast<size_t>(c)] < 0) {
        sectors_.emplace_back();
        for (int corner = c; corner >= 0 && sector_of_[static_cast<size_t>(corner)] < 0; corner = k_.ccw[static_cast<size_t>(corner)])
          add_corner(corner);
      }
  }

  Sector& of(int corner) { return sectors_[static_cast<size_t>(sector_of_[static_cast<size_t>(corner)])]; }
  int vertex(int c) const { return m_.face_vertices[static_cast<size_t>(c)]; }
  Vec2 direction(int from, int to) const { return Vec2(m_.uv[static_cast<size_t>(to)] - m_.uv[static_cast<size_t>(from)]); }

 private:
  void add_corner(int c) {
    Sector& sector = sectors_.back();
    const int v = vertex(c);
    const Vec2 to_next = direction(v, vertex(k_.next[static_cast<size_t>(c)]));
    const Vec2 to_prev = direction(v, vertex(k_.prev[static_cast<size_t>(c)]));
    double interior = std::atan2(cross2(to_next, to_prev), to_next.dot(to_prev));
    if (interior <= 0.0) interior += kTwoPi;
    sector.angle += interior;
    sector.shortest = std::min({sector.shortest, to_next.norm(), to_prev.norm()});
    // Twice the clearance to the face's edges that do not end at v (e.g. a quad edge just beyond a
    // crack tip), so that the shadow cannot leave the sector.
    const int f = k_.face_of[static_cast<size_t>(c)];
    const Vec2& p = m_.uv[static_cast<size_t>(v)];
    for (int k = m_.face_offsets[static_cast<size_t>(f)]; k < m_.face_offsets[static_cast<size_t>(f) + 1]; ++k) {
      const int a = vertex(k), b = vertex(k_.next[static_cast<size_t>(k)]);
      if (a == v || b == v) continue;
      const Vec2 &pa = m_.uv[static_cast<size_t>(a)], ab = m_.uv[static_cast<size_t>(b)] - pa;
      const double t = std::clamp((p - pa).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
      sector.shortest = std::min(sector.shortest, 2.0 * (pa + t * ab - p).norm());
    }
    sector_of_[static_cast<size_t>(c)] = static_cast<int>(sectors_.size()) - 1;
  }

  const ParameterMesh& m_;
  const Corners& k_;
  std::vector<Sector> sectors_;
  std::vector<int> sector_of_;
};

}  // namespace

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
  const Corners corners(split);
  Sectors sectors(split, corners);
  out.face_vertices.reserve(split.face_vertices.size());
  for (int c = 0; c < static_cast<int>(split.face_vertices.size()); ++c) {
    const int v = sectors.vertex(c);
    if (!split.on_crack[static_cast<size_t>(v)]) {
      out.face_vertices.push_back(kept[static_cast<size_t>(v)]);
      continue;
    }
    Sector& sector = sectors.of(c);
    if (sector.shadow < 0) {
      // Thesis 4.9.3 / Fig. 4.17: move by Dv along the bisector of the sector, into it.
      Vec2 shadow = split.uv[static_cast<size_t>(v)];
      if (sector.first >= 0) {
        const Vec2 start = sectors.direction(v, sectors.vertex(corners.next[static_cast<size_t>(sector.first)])).normalized();
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
