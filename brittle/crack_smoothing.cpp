#include "brittle/crack_smoothing.hpp"

#include "brittle/regions.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <set>
#include <unordered_map>

namespace shellfrac::brittle {

namespace {

uint64_t edge_key(int a, int b) {
  const auto [lo, hi] = std::minmax(a, b);
  return (static_cast<uint64_t>(static_cast<uint32_t>(lo)) << 32) | static_cast<uint32_t>(hi);
}

// Six times the smallest signed volume of the tetrahedra (reference point of a cell, triangle) the face
// forms with its cells, each triangle oriented outward from the cell: positive while neither cell folds
// over the face. `star`: the triangles of the face bent (as the smoothing will mark it), else its own.
double min_tetrahedron(const VoronoiDiagram& d, const std::vector<Vec3>& centre_of, const VoronoiFace& face, bool star) {
  double lowest = std::numeric_limits<double>::infinity();
  const Vec3 centre = face_centre(d.vertices, face);
  VoronoiFace shape;
  shape.vertices = face.vertices;
  shape.bent = star || face.bent;
  for_face_triangles(shape, [&](int a, int b, int c) {
    const Vec3& pa = a < 0 ? centre : d.vertices[static_cast<size_t>(a)];
    const Vec3 n = (d.vertices[static_cast<size_t>(b)] - pa).cross(d.vertices[static_cast<size_t>(c)] - pa);
    lowest = std::min(lowest, n.dot(pa - centre_of[static_cast<size_t>(face.cell_a)]));
    if (!face.wall()) lowest = std::min(lowest, -n.dot(pa - centre_of[static_cast<size_t>(face.cell_b)]));
  });
  return lowest;
}

// A corner or a node of the lattice h Z^3 (corners are offset by h/2) as one key.
uint64_t lattice_key(const Eigen::Vector3i& k) {
  return (static_cast<uint64_t>(k.x() + (1 << 20)) << 42) | (static_cast<uint64_t>(k.y() + (1 << 20)) << 21) |
         static_cast<uint64_t>(k.z() + (1 << 20));
}

// How a point moves with the staircase: the eight corners of its cube with their trilinear weights
// (corner -1: one that does not move).
struct Stencil {
  int vertex;  // or cell, for a site
  std::array<int, 8> corner;
  std::array<double, 8> weight;
};

// The staircase: each crack face (smooth[f], not a wall) as the polygon of the lattice corners
// (k + 1/2) h nearest its vertices, numbered as they are met; squares met twice are counted once, and
// faces that shrink to an edge or a point there (the jitter's slivers) are left out.
struct Staircase {
  struct CornerEdge {
    int squares = 0;
    std::vector<int> labels;  // the regions on either side of its squares
  };
  struct Square {
    std::vector<int> corners;  // oriented from the lower region label to the higher
  };
  Staircase(const VoronoiDiagram& d, const std::vector<char>& smooth, double h);
  // The stencil of the cube holding x; false if none of its corners moves (along[c] empty).
  bool stencil(const std::vector<std::vector<int>>& along, int id, const Vec3& x, Stencil& s) const;
  Eigen::Vector3i nearest_corner(const Vec3& x) const {
    const Vec3 q = x / h - Vec3::Constant(0.5);
    return Eigen::Vector3i(static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())), static_cast<int>(std::lround(q.z())));
  }

  double h;
  std::unordered_map<uint64_t, int> corner_id;
  std::vector<Eigen::Vector3i> corner_at;
  std::unordered_map<uint64_t, CornerEdge> edges;
  std::vector<Square> squares;

 private:
  int corner_of(const Eigen::Vector3i& k) {
    const auto [it, added] = corner_id.try_emplace(lattice_key(k), static_cast<int>(corner_at.size()));
    if (added) corner_at.push_back(k);
    return it->second;
  }
};

Staircase::Staircase(const VoronoiDiagram& d, const std::vector<char>& smooth, double h_) : h(h_) {
  const std::vector<int> label = find_regions(d, smooth).cell_region;
  std::set<std::vector<int>> seen_square;
  for (size_t f = 0; f < d.faces.size() && f < smooth.size(); ++f) {
    const VoronoiFace& face = d.faces[f];
    if (!smooth[f] || face.wall()) continue;
    std::vector<int> poly;
    for (int v : face.vertices) {
      const int c = corner_of(nearest_corner(d.vertices[static_cast<size_t>(v)]));
      if (poly.empty() || poly.back() != c) poly.push_back(c);
    }
    while (poly.size() > 1 && poly.front() == poly.back()) poly.pop_back();
    std::vector<int> sorted = poly;
    std::sort(sorted.begin(), sorted.end());
    if (poly.size() < 3 || std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end()) continue;  // a sliver
    if (!seen_square.insert(sorted).second) continue;
    const int la = label[static_cast<size_t>(face.cell_a)], lb = label[static_cast<size_t>(face.cell_b)];
    squares.push_back({la < lb ? poly : std::vector<int>(poly.rbegin(), poly.rend())});
    for (size_t i = 0; i < poly.size(); ++i) {
      CornerEdge& e = edges[edge_key(poly[i], poly[(i + 1) % poly.size()])];
      ++e.squares;
      for (int l : {la, lb})
        if (std::find(e.labels.begin(), e.labels.end(), l) == e.labels.end()) e.labels.push_back(l);
    }
  }
}

bool Staircase::stencil(const std::vector<std::vector<int>>& along, int id, const Vec3& x, Stencil& s) const {
  const Vec3 q = x / h - Vec3::Constant(0.5);
  const Eigen::Vector3i base(static_cast<int>(std::floor(q.x())), static_cast<int>(std::floor(q.y())), static_cast<int>(std::floor(q.z())));
  const Vec3 t = q - base.cast<double>();
  s.vertex = id;
  bool any = false;
  for (int k = 0; k < 8; ++k) {
    const Eigen::Vector3i off(k & 1, (k >> 1) & 1, (k >> 2) & 1);
    const auto it = corner_id.find(lattice_key(base + off));
    s.corner[static_cast<size_t>(k)] = it == corner_id.end() || along[static_cast<size_t>(it->second)].empty() ? -1 : it->second;
    s.weight[static_cast<size_t>(k)] = (off.x() ? t.x() : 1 - t.x()) * (off.y() ? t.y() : 1 - t.y()) * (off.z() ? t.z() : 1 - t.z());
    any = any || s.corner[static_cast<size_t>(k)] >= 0;
  }
  return any;
}

// Areas and centroids of the faces around the vertices that moved (fan areas: the faces need not be
// planar any more), marked bent, and the volumes of their cells; the largest vertex move goes to the report.
void refresh_moved_geometry(VoronoiDiagram& d, const std::vector<int>& movable, const std::vector<Vec3>& original,
                            const std::vector<std::vector<int>>& faces_of, CrackSmoothingReport& report) {
  std::vector<char> cell_touched(d.num_cells(), 0);
  for (const int vertex : movable) {
    const size_t v = static_cast<size_t>(vertex);
    report.max_displacement = std::max(report.max_displacement, (d.vertices[v] - original[v]).norm());
    if (d.vertices[v] == original[v]) continue;
    for (int f : faces_of[v]) {
      VoronoiFace& face = d.faces[static_cast<size_t>(f)];
      cell_touched[static_cast<size_t>(face.cell_a)] = 1;
      if (!face.wall()) cell_touched[static_cast<size_t>(face.cell_b)] = 1;
      face.bent = true;
      const Vec3 centre = face_centre(d.vertices, face);
      double area2 = 0;
      Vec3 c = Vec3::Zero();
      for_face_triangles(face, [&](int a, int b, int cc) {
        const Vec3 &pa = a < 0 ? centre : d.vertices[static_cast<size_t>(a)], &pb = d.vertices[static_cast<size_t>(b)],
                   &pc = d.vertices[static_cast<size_t>(cc)];
        const double t = (pb - pa).cross(pc - pa).norm();
        area2 += t;
        c += t * (pa + pb + pc) / 3.0;
      });
      face.area = 0.5 * area2;
      if (area2 > 0) face.centroid = c / area2;
    }
  }
  for (size_t cell = 0; cell < d.num_cells(); ++cell) {
    if (!cell_touched[cell]) continue;
    double six_v = 0;
    for (int f : d.cell_faces[cell]) {
      const VoronoiFace& face = d.faces[static_cast<size_t>(f)];
      const double sign = face.cell_a == static_cast<int>(cell) ? 1.0 : -1.0;
      const Vec3 centre = face_centre(d.vertices, face);
      for_face_triangles(face, [&](int a, int b, int c) {
        const Vec3& pa = a < 0 ? centre : d.vertices[static_cast<size_t>(a)];
        six_v += sign * (d.vertices[static_cast<size_t>(b)] - pa).cross(d.vertices[static_cast<size_t>(c)] - pa).dot(pa - d.sites[cell]);
      });
    }
    d.cell_volume[cell] = six_v / 6.0;
  }
}

// How each staircase corner may move: its neighbours along staircase edges by kind (junction: three or
// more regions around the edge; rim: one square; sheet: the rest), and what a movable corner is averaged
// over (`along`; empty: fixed).
struct CornerRoles {
  std::vector<std::vector<int>> sheet, rim, junction, along;
  bool on_sheet(size_t c) const { return !along[c].empty() && junction[c].empty() && rim[c].empty(); }
};

CornerRoles corner_roles(const VoronoiDiagram& d, const Staircase& stairs, double h, CrackSmoothingReport& report) {
  const size_t nc = stairs.corner_at.size();
  CornerRoles r;
  r.sheet.resize(nc);
  r.rim.resize(nc);
  r.junction.resize(nc);
  r.along.resize(nc);
  for (const auto& [key, e] : stairs.edges) {
    const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    auto& list = e.labels.size() >= 3 ? r.junction : e.squares == 1 ? r.rim : r.sheet;
    list[static_cast<size_t>(a)].push_back(b);
    list[static_cast<size_t>(b)].push_back(a);
  }
  // Corners whose cube of nodes is not all sites lie outside the rasterised object (its nodes reach 1.5
  // cells past the particles): they stay, so that the large cells beyond the object, which a moved corner
  // would tilt against their far sites, keep their shape.
  std::unordered_map<uint64_t, char> site_node;
  for (const Vec3& x : d.sites) {
    const Vec3 q = x / h;
    site_node.emplace(lattice_key(Eigen::Vector3i(static_cast<int>(std::lround(q.x())), static_cast<int>(std::lround(q.y())),
                                                 static_cast<int>(std::lround(q.z())))), 1);
  }
  auto inside = [&](const Eigen::Vector3i& k) {  // the nodes k .. k + 1 around corner (k + 1/2) h
    for (int i = 0; i < 8; ++i)
      if (!site_node.count(lattice_key(k + Eigen::Vector3i(i & 1, (i >> 1) & 1, (i >> 2) & 1)))) return false;
    return true;
  };
  for (size_t c = 0; c < nc; ++c) {
    if (r.sheet[c].empty() && r.rim[c].empty() && r.junction[c].empty()) continue;  // a sliver's corner only
    if (!inside(stairs.corner_at[c])) {
      ++report.fixed_corners;
      continue;
    }
    if (!r.junction[c].empty()) {
      if (r.junction[c].size() == 2) r.along[c] = r.junction[c];
    } else if (!r.rim[c].empty()) {
      if (r.rim[c].size() == 2) r.along[c] = r.rim[c];
    } else {
      r.along[c] = r.sheet[c];
    }
    std::sort(r.along[c].begin(), r.along[c].end());  // a sum in the same order on every platform
    if (r.along[c].empty()) ++report.fixed_corners;
    else (r.junction[c].empty() && r.rim[c].empty() ? report.sheet_corners : report.curve_corners) += 1;
  }
  return r;
}

// The relaxation of the staircase: corner shifts, the diagram vertices and the cells' reference points
// that follow them through their stencils, and the faces whose cells must not fold.
class StaircaseRelaxation {
 public:
  StaircaseRelaxation(VoronoiDiagram& d, const Staircase& stairs, const CornerRoles& roles, double h,
                      CrackSmoothingReport& report)
      : d_(d), stairs_(stairs), roles_(roles), h_(h), report_(report), original_(d.vertices), reference_(d.sites) {
    const size_t nv = d.vertices.size(), nc = stairs.corner_at.size();
    walls_.assign(nv, 0);
    faces_of_.resize(nv);
    for (size_t f = 0; f < d.faces.size(); ++f)
      for (int v : d.faces[f].vertices) {
        faces_of_[static_cast<size_t>(v)].push_back(static_cast<int>(f));
        if (d.faces[f].wall()) walls_[static_cast<size_t>(v)] |= static_cast<uint8_t>(1u << (-d.faces[f].cell_b - 1));
      }
    // Each vertex near the staircase: its cube's eight corners with their trilinear weights.
    for (size_t v = 0; v < nv; ++v) {
      Stencil s;
      const uint8_t w = walls_[v];
      const int wall_count = (w & 1) + (w >> 1 & 1) + (w >> 2 & 1) + (w >> 3 & 1) + (w >> 4 & 1) + (w >> 5 & 1);
      if (stairs.stencil(roles.along, static_cast<int>(v), d.vertices[v], s) && wall_count < 3) stencils_.push_back(s);
    }
    // The sites move with the same deformation as reference points of the fold test (the diagram's sites
    // stay): a tetrahedron (site, face triangle) then folds only where the deformation itself does.
    for (size_t c = 0; c < d.num_cells(); ++c) {
      Stencil s;
      if (stairs.stencil(roles.along, static_cast<int>(c), d.sites[c], s)) site_stencils_.push_back(s);
    }
    site_stencil_of_.assign(d.num_cells(), -1);
    for (size_t i = 0; i < site_stencils_.size(); ++i) site_stencil_of_[static_cast<size_t>(site_stencils_[i].vertex)] = static_cast<int>(i);
    stencil_of_.assign(nv, -1);
    for (size_t i = 0; i < stencils_.size(); ++i) stencil_of_[static_cast<size_t>(stencils_[i].vertex)] = static_cast<int>(i);
    // The faces around the vertices that can move.
    std::vector<char> in(d.faces.size(), 0);
    auto add = [&](int f) {
      if (!in[static_cast<size_t>(f)]) {
        in[static_cast<size_t>(f)] = 1;
        check_.push_back(f);
      }
    };
    for (const Stencil& s : stencils_)
      for (int f : faces_of_[static_cast<size_t>(s.vertex)]) add(f);
    for (const Stencil& s : site_stencils_)
      for (int f : d.cell_faces[static_cast<size_t>(s.vertex)]) add(f);
    std::sort(check_.begin(), check_.end());
    // A face fails when a tetrahedron falls below this (six times its volume): far above the round-off of
    // the determinant and far below the cells (h^3 / 8 and more) and most jitter faces (about 1e-3 h^3);
    // a face of the diagram already below it (a speck left by the welding) must keep a quarter of its own.
    floor_of_.resize(check_.size());
    for (size_t i = 0; i < check_.size(); ++i)
      floor_of_[i] = std::min(1e-9 * h * h * h, 0.25 * min_tetrahedron(d, d.sites, d.faces[static_cast<size_t>(check_[i])], true));
    shift_.assign(nc, Vec3::Zero());
    previous_.resize(nc);
    target_.resize(nc);
    halved_.assign(nc, 0);
  }

  // One Jacobi step of the umbrella operator (uniform weights), then the corners around every face that
  // would fold a cell are put back, until none does; the state before the step was valid, so this ends.
  void pass(const CrackSmoothingOptions& o) {
    const size_t nc = shift_.size();
    for (size_t c = 0; c < nc; ++c) {
      target_[c] = shift_[c];
      const std::vector<int>& along = roles_.along[c];
      if (along.empty()) continue;
      Vec3 mean = Vec3::Zero();
      for (int u : along) mean += corner_position(static_cast<size_t>(u));
      mean /= static_cast<double>(along.size());
      target_[c] += o.lambda * (mean - corner_position(c));
      // A corner stays inside its cube of lattice nodes (as in constrained surface nets): the sheet keeps
      // to within half a cell of the staircase and neighbouring cubes cannot collapse.
      target_[c] = target_[c].cwiseMax(Vec3::Constant(-o.reach * h_)).cwiseMin(Vec3::Constant(o.reach * h_));
    }
    previous_ = shift_;
    shift_ = target_;
    std::fill(halved_.begin(), halved_.end(), 0);
    for (bool changed = true; changed;) {
      place();
      changed = false;
      for (size_t i = 0; i < check_.size(); ++i)
        if (min_tetrahedron(d_, reference_, d_.faces[static_cast<size_t>(check_[i])], true) <= floor_of_[i])
          changed = back_off(d_.faces[static_cast<size_t>(check_[i])]) || changed;
    }
  }

  // The vertices of a sheet face near a corner came from one cube corner of the staircase and still lie in
  // that cube face's (axis-aligned) plane: moved together, they leave a step a tenth of a cell high at
  // every corner. Each is projected onto the sheet's tangent plane at its corner (the normal from the
  // moved squares around it); a projection that would fold a cell is undone.
  void project_on_tangent_planes(const std::vector<char>& smooth) {
    const size_t nc = shift_.size(), nv = d_.vertices.size();
    std::vector<Vec3> normal(nc, Vec3::Zero());
    for (const Staircase::Square& q : stairs_.squares) {
      Vec3 n = Vec3::Zero();
      for (size_t i = 0; i < q.corners.size(); ++i)
        n += corner_position(static_cast<size_t>(q.corners[i])).cross(corner_position(static_cast<size_t>(q.corners[(i + 1) % q.corners.size()])));
      for (int c : q.corners) normal[static_cast<size_t>(c)] += n;
    }
    std::vector<char> on_sheet(nv, 0);
    for (size_t f = 0; f < d_.faces.size() && f < smooth.size(); ++f)
      if (smooth[f] && !d_.faces[f].wall())
        for (int v : d_.faces[f].vertices) on_sheet[static_cast<size_t>(v)] = 1;
    const std::vector<Vec3> before = d_.vertices;
    std::vector<int> projected;
    for (const Stencil& st : stencils_) {
      const size_t v = static_cast<size_t>(st.vertex);
      if (!on_sheet[v] || walls_[v]) continue;
      const auto it = stairs_.corner_id.find(lattice_key(stairs_.nearest_corner(original_[v])));
      if (it == stairs_.corner_id.end()) continue;
      const size_t c = static_cast<size_t>(it->second);
      if (!roles_.on_sheet(c) || !(normal[c].norm() > 0)) continue;  // sheet corners only
      const Vec3 n = normal[c].normalized();
      d_.vertices[v] -= (d_.vertices[v] - corner_position(c)).dot(n) * n;
      projected.push_back(static_cast<int>(v));
    }
    std::vector<char> is_projected(nv, 0);
    for (int v : projected) is_projected[static_cast<size_t>(v)] = 1;
    for (bool changed = true; changed;) {
      changed = false;
      for (int vi : projected) {
        if (!is_projected[static_cast<size_t>(vi)]) continue;
        for (int f : faces_of_[static_cast<size_t>(vi)]) {
          const VoronoiFace& face = d_.faces[static_cast<size_t>(f)];
          const size_t i = static_cast<size_t>(std::lower_bound(check_.begin(), check_.end(), f) - check_.begin());
          const double floor = i < check_.size() && check_[i] == f ? floor_of_[i] : 1e-9 * h_ * h_ * h_;
          if (min_tetrahedron(d_, reference_, face, true) > floor) continue;
          for (int u : face.vertices)
            if (is_projected[static_cast<size_t>(u)]) {
              d_.vertices[static_cast<size_t>(u)] = before[static_cast<size_t>(u)];
              is_projected[static_cast<size_t>(u)] = 0;
              ++report_.rejected_moves;
              changed = true;
            }
        }
      }
    }
  }

  void finish() {
    std::vector<int> movable;
    for (const Stencil& st : stencils_) movable.push_back(st.vertex);
    refresh_moved_geometry(d_, movable, original_, faces_of_, report_);
    report_.reference = std::move(reference_);
  }

 private:
  Vec3 corner_position(size_t c) const {
    return Vec3((stairs_.corner_at[c].cast<double>() + Vec3::Constant(0.5)) * h_ + shift_[c]);
  }

  static Vec3 displacement(const Stencil& s, const std::vector<Vec3>& shift) {
    Vec3 u = Vec3::Zero();
    for (size_t k = 0; k < 8; ++k)
      if (s.corner[k] >= 0) u += s.weight[k] * shift[static_cast<size_t>(s.corner[k])];
    return u;
  }

  // Moves the vertices and the reference points with the corners' shifts.
  void place() {
    for (const Stencil& s : stencils_) {
      Vec3 u = displacement(s, shift_);
      const uint8_t w = walls_[static_cast<size_t>(s.vertex)];
      for (int a = 0; a < 3; ++a)
        if (w >> (2 * a) & 3u) u[a] = 0;  // stays in the wall's plane
      d_.vertices[static_cast<size_t>(s.vertex)] = original_[static_cast<size_t>(s.vertex)] + u;
    }
    for (const Stencil& s : site_stencils_)
      reference_[static_cast<size_t>(s.vertex)] = d_.sites[static_cast<size_t>(s.vertex)] + displacement(s, shift_);
  }

  // Takes back the step of every corner that moves the folding face's vertices or its cells' reference
  // points: half the step, twice; then none. True if any corner changed.
  bool back_off(const VoronoiFace& face) {
    std::vector<const Stencil*> movers;
    for (int v : face.vertices)
      if (stencil_of_[static_cast<size_t>(v)] >= 0) movers.push_back(&stencils_[static_cast<size_t>(stencil_of_[static_cast<size_t>(v)])]);
    for (int cell : {face.cell_a, face.cell_b})
      if (cell >= 0 && site_stencil_of_[static_cast<size_t>(cell)] >= 0)
        movers.push_back(&site_stencils_[static_cast<size_t>(site_stencil_of_[static_cast<size_t>(cell)])]);
    bool changed = false;
    for (const Stencil* mover : movers)
      for (int ci : mover->corner) {
        if (ci < 0) continue;
        const size_t c = static_cast<size_t>(ci);
        if (shift_[c] != previous_[c]) {
          shift_[c] = ++halved_[c] > 2 ? previous_[c] : Vec3(0.5 * (shift_[c] + previous_[c]));
          ++report_.rejected_moves;
          changed = true;
        }
      }
    return changed;
  }

  VoronoiDiagram& d_;
  const Staircase& stairs_;
  const CornerRoles& roles_;
  double h_;
  CrackSmoothingReport& report_;
  const std::vector<Vec3> original_;  // the diagram's vertices before any move
  std::vector<Vec3> reference_;       // per cell, its site moved with the deformation
  std::vector<uint8_t> walls_;        // per vertex, the container walls it lies on (bit 2a + side)
  std::vector<std::vector<int>> faces_of_;
  std::vector<Stencil> stencils_, site_stencils_;
  std::vector<int> stencil_of_, site_stencil_of_;
  std::vector<int> check_;        // faces whose cells must not fold, sorted
  std::vector<double> floor_of_;  // their lowest allowed tetrahedron
  std::vector<Vec3> shift_, previous_, target_;  // per corner
  std::vector<int> halved_;
};

}  // namespace

size_t folded_tetrahedra(const VoronoiDiagram& d, const std::vector<Vec3>& reference) {
  size_t folded = 0;
  for (const VoronoiFace& face : d.faces) folded += min_tetrahedron(d, reference.empty() ? d.sites : reference, face, false) > 0 ? 0 : 1;
  return folded;
}

CrackSmoothingReport smooth_crack_faces(VoronoiDiagram& d, const std::vector<char>& smooth, double h,
                                        const CrackSmoothingOptions& o) {
  CrackSmoothingReport report;
  if (!(h > 0) || d.vertices.empty()) return report;
  const Staircase stairs(d, smooth, h);
  if (stairs.edges.empty()) return report;
  const CornerRoles roles = corner_roles(d, stairs, h, report);
  StaircaseRelaxation relax(d, stairs, roles, h, report);
  for (int pass = 0; pass < o.passes; ++pass) relax.pass(o);
  relax.project_on_tangent_planes(smooth);
  relax.finish();
  return report;
}

}  // namespace shellfrac::brittle
