// Cracks that cross a coupled seam (thesis sec. 4.8 with sec. 4.4): a crack reaching a coupled edge
// continues into the neighbouring patch, the coupling lets go of the follower control points the crack
// separates from their leaders, and the phantom-node partition treats two coupled patches as one body
// that only a crack can split.
#include <algorithm>
#include <cmath>
#include <limits>

#include "coupling/seam_release.hpp"
#include "crack2d/crack_index.hpp"
#include "sim/crack_system.hpp"
#include "sim/seam_system.hpp"

namespace shellfrac::sim {

namespace {

constexpr double kOnEdge = 1e-9;  // seam-chart distance under which a crack vertex lies on the edge

struct SeamSide {
  const nurbs::NurbsSurface* surface;
  coupling::Side side;
  bool flip;
};

SeamSide leader_side(const scene::Model& scene, const coupling::Interface& c) {
  return {&scene.shells[static_cast<size_t>(c.leader_patch)].surface, c.leader_side, false};
}
SeamSide follower_side(const scene::Model& scene, const coupling::Interface& c) {
  return {&scene.shells[static_cast<size_t>(c.follower_patch)].surface, c.follower_side, c.reversed};
}

coupling::SeamCoordinate seam_of(const SeamSide& s, const Eigen::Vector2d& uv) {
  return coupling::seam_coordinate(*s.surface, s.side, s.flip, uv);
}

// A crack vertex on the seam edge, with the direction (seam chart) of the crack leaving it inward.
struct SeamHit {
  double along;
  Eigen::Vector2d inward;
};

std::vector<SeamHit> seam_hits(const crack2d::CrackGraph& g, const SeamSide& s) {
  std::vector<SeamHit> hits;
  const auto& vertices = g.vertices();
  for (const auto& e : g.edges())
    for (int end = 0; end < 2; ++end) {
      const Eigen::Vector2d a = vertices[static_cast<size_t>(e[end])], b = vertices[static_cast<size_t>(e[1 - end])];
      const coupling::SeamCoordinate sa = seam_of(s, a);
      if (std::abs(sa.across) > kOnEdge || sa.along < -kOnEdge || sa.along > 1 + kOnEdge) continue;
      hits.push_back({sa.along, coupling::parameter_direction_to_seam(*s.surface, s.side, s.flip, b - a)});
    }
  return hits;
}

// Cells of the patch across the side and along it.
int cross_cells(const nurbs::NurbsSurface& s, coupling::Side side) {
  const bool u_side = side == coupling::Side::U0 || side == coupling::Side::U1;
  return std::max(1, u_side ? s.knots_u().num_spans() : s.knots_v().num_spans());
}
int along_cells(const nurbs::NurbsSurface& s, coupling::Side side) {
  const bool u_side = side == coupling::Side::U0 || side == coupling::Side::U1;
  return std::max(1, u_side ? s.knots_v().num_spans() : s.knots_u().num_spans());
}

// C1 tangents (row-1 point to its row-2 partner, in the patch's parameter plane) that a crack separates.
coupling::TornTangents torn_tangents(const World& world, const coupling::Interface& c) {
  coupling::TornTangents torn;
  if (c.continuity != coupling::Continuity::C1) return torn;
  auto tears = [&](int patch, const std::vector<int>& row1, const std::vector<int>& row2) {
    const shell::ShellPatch& p = world.shell(static_cast<size_t>(patch));
    std::vector<unsigned char> out(row1.size(), 0);
    if (!p.crack()) return out;
    for (size_t j = 0; j < row1.size(); ++j)
      out[j] = p.crack()->crosses(p.control_parameter(static_cast<size_t>(row1[j])),
                                  p.control_parameter(static_cast<size_t>(row2[j])));
    return out;
  };
  torn.leader = tears(c.leader_patch, c.leader_row1, c.leader_row2);
  torn.follower = tears(c.follower_patch, c.follower_row1, c.follower_row2);
  return torn;
}

// Where cracks cross the seam, once for both patches. Each patch's crack graph meets the edge where its own
// damage took it, so one crack can reach the two sides a little apart (2 mm on the L of three patches
// with a 20-cell top); taken as two crossings, the exact closure would tie the sliver of seam between
// them to neither side. A leader crossing and a follower crossing closer than a cell of either edge are
// one crossing, at the leader's position (the seam's shared space is the leader's); crossings of one
// patch are kept apart, since its own graph says they are distinct.
std::vector<double> shared_crossings(const CrackSystem& cracks, const size_t patch[2], const SeamSide side[2]) {
  std::vector<double> leader, follower;
  for (int k = 0; k < 2; ++k)
    if (cracks.graph(patch[k]))
      for (const SeamHit& h : seam_hits(*cracks.graph(patch[k]), side[k])) (k == 0 ? leader : follower).push_back(h.along);
  const double near = std::max(1.0 / along_cells(*side[0].surface, side[0].side), 1.0 / along_cells(*side[1].surface, side[1].side));
  std::vector<double> out = leader;
  for (double f : follower) {
    const bool shared = std::any_of(leader.begin(), leader.end(), [&](double l) { return std::abs(l - f) < near; });
    if (!shared) out.push_back(f);
  }
  std::sort(out.begin(), out.end());
  return out;
}

}  // namespace

SeamSystem::SeamSystem(const scene::Model& model, const World& world) : model_(model), start_positions_(world.num_shells()) {
  seams_.assign(model_.interfaces.size(), SeamState{});
  for (size_t i = 0; i < model_.interfaces.size(); ++i) {
    const coupling::Interface& c = model_.interfaces[i].coupling;
    SeamState& st = seams_[i];
    const SeamSide lead = leader_side(model_, c), follow = follower_side(model_, c);
    const shell::ShellPatch& lp = world.shell(static_cast<size_t>(c.leader_patch));
    const shell::ShellPatch& fp = world.shell(static_cast<size_t>(c.follower_patch));
    for (int k : c.leader_row1) st.leader_along.push_back(seam_of(lead, lp.control_parameter(static_cast<size_t>(k))).along);
    for (int k : c.follower_row1) st.follower_along.push_back(seam_of(follow, fp.control_parameter(static_cast<size_t>(k))).along);
    st.released.assign(c.follower_row1.size() * (c.continuity == coupling::Continuity::C1 ? 2 : 1), 0);
    build_projection(world, i);
  }
  // Shear particles of cells that hold a control point the coupling stage sets or corrects.
  shear_near_seam_.assign(world.num_shells(), {});
  for (size_t patch = 0; patch < world.num_shells(); ++patch) {
    std::vector<unsigned char> set_by_seam(world.shell(patch).num_control_points(), 0);
    for (const scene::model::InterfaceSpec& spec : model_.interfaces) {
      const coupling::Interface& c = spec.coupling;
      auto mark = [&](int owner, const std::vector<int>& points) {
        if (static_cast<size_t>(owner) == patch)
          for (int k : points) set_by_seam[static_cast<size_t>(k)] = 1;
      };
      for (const auto* rows : {&c.leader_row1, &c.leader_row2, &spec.leader_neighbours}) mark(c.leader_patch, *rows);
      for (const auto* rows : {&c.follower_row1, &c.follower_row2, &spec.follower_neighbours}) mark(c.follower_patch, *rows);
    }
    const shell::ShellPatch& p = world.shell(patch);
    for (size_t cell = 0; cell < p.num_cells(); ++cell) {
      const int* ids = p.support(cell);
      if (std::any_of(ids, ids + p.support_size(), [&](int k) { return set_by_seam[static_cast<size_t>(k)] != 0; }))
        shear_near_seam_[patch].push_back(cell);
    }
  }
  // Seams that set another seam's leader rows go first (Kahn's order; a cycle keeps the scene order).
  auto sets_leader_of = [&](size_t j, size_t i) {
    const coupling::Interface& a = model_.interfaces[j].coupling;
    const coupling::Interface& b = model_.interfaces[i].coupling;
    if (i == j || a.follower_patch != b.leader_patch) return false;
    auto in = [](const std::vector<int>& rows, int k) { return std::find(rows.begin(), rows.end(), k) != rows.end(); };
    for (const std::vector<int>* rows : {&b.leader_row1, &b.leader_row2})
      for (int k : *rows)
        if (in(a.follower_row1, k) || in(a.follower_row2, k)) return true;
    return false;
  };
  const size_t n = model_.interfaces.size();
  std::vector<unsigned char> placed(n, 0);
  while (order_.size() < n) {
    bool progress = false;
    for (size_t i = 0; i < n; ++i) {
      if (placed[i]) continue;
      bool ready = true;
      for (size_t j = 0; j < n; ++j) ready = ready && (placed[j] || !sets_leader_of(j, i));
      if (!ready) continue;
      order_.push_back(i);
      placed[i] = 1;
      progress = true;
    }
    if (progress) continue;
    for (size_t i = 0; i < n; ++i)
      if (!placed[i]) {
        order_.push_back(i);
        placed[i] = 1;
        break;
      }
  }
  // Seams whose row 1 shares a control point with another seam's coupled rows (patch corners): their
  // row 1 is placed once more after all seams (SeamSystem::couple).
  for (size_t i = 0; i < model_.interfaces.size(); ++i)
    for (size_t j = 0; j < model_.interfaces.size() && !seams_[i].shares_points; ++j) {
      const coupling::Interface& a = model_.interfaces[i].coupling;
      const coupling::Interface& b = model_.interfaces[j].coupling;
      if (i == j || a.follower_patch != b.follower_patch) continue;
      for (int k : a.follower_row1) {
        const bool in_b = std::find(b.follower_row1.begin(), b.follower_row1.end(), k) != b.follower_row1.end() ||
                          std::find(b.follower_row2.begin(), b.follower_row2.end(), k) != b.follower_row2.end();
        seams_[i].shares_points = seams_[i].shares_points || in_b;
      }
    }
}

void SeamSystem::update_cracks(World& world, CrackSystem& cracks) {
  for (size_t i = 0; i < model_.interfaces.size(); ++i) {
    const scene::model::InterfaceSpec& spec = model_.interfaces[i];
    const coupling::Interface& c = spec.coupling;
    const size_t patch[2] = {static_cast<size_t>(c.leader_patch), static_cast<size_t>(c.follower_patch)};
    const SeamSide side[2] = {leader_side(model_, c), follower_side(model_, c)};
    if (!cracks.graph(patch[0]) && !cracks.graph(patch[1])) continue;
    // A crack that reaches the seam from one side continues into the other as a short cut straight
    // across (the mirror image in the seam chart); the neighbour's own damage grows it from there.
    for (int from = 0; from < 2; ++from) {
      const int to = 1 - from;
      if (!cracks.graph(patch[from]) || !cracks.graph(patch[to])) continue;
      const double cell_along = 1.0 / along_cells(*side[to].surface, side[to].side);
      const double cell_across = 1.0 / cross_cells(*side[to].surface, side[to].side);
      for (const SeamHit& h : seam_hits(*cracks.graph(patch[from]), side[from])) {
        if (h.inward.y() <= 1e-3 * h.inward.norm()) continue;  // running along the seam: does not cross it
        bool continued = false;
        for (const SeamHit& other : seam_hits(*cracks.graph(patch[to]), side[to]))
          continued = continued || std::abs(other.along - h.along) <= cell_along;
        if (continued) continue;
        // Mirror across the seam: the along component flips, the inward component stays inward.
        Eigen::Vector2d dir(-h.inward.x(), h.inward.y());
        dir *= 1.5 * cell_across / dir.y();  // one and a half cells deep into the neighbour
        Eigen::Vector2d end_seam(h.along + dir.x(), dir.y());
        end_seam.x() = std::clamp(end_seam.x(), 0.0, 1.0);
        const Eigen::Vector2d start = coupling::seam_edge_parameter(*side[to].surface, side[to].side, side[to].flip,
                                                                    std::clamp(h.along, 0.0, 1.0));
        const Eigen::Vector2d end =
            start + coupling::seam_direction_to_parameter(*side[to].surface, side[to].side, side[to].flip,
                                                          end_seam - Eigen::Vector2d(h.along, 0.0));
        // A degenerate continuation (at a corner) is skipped: the neighbour's damage decides alone.
        if (!cracks.add_cut(world, patch[to], start, end)) continue;
        cracks.count_seam_continuation();
      }
    }
    SeamState& st = seams_[i];
    st.cracks = shared_crossings(cracks, patch, side);
    const coupling::TornTangents torn = torn_tangents(world, c);
    if (st.cracks.empty() && !torn.any()) continue;
    // An exactly closed seam stays exact on each side of the crack (segmented shared space); the
    // thesis's least-squares seam drops the crack's connections from its rows.
    coupling::SeamCut cut = c.exact ? coupling::cut_exact_interface(c, st.follower_along, st.leader_along, st.cracks, torn)
                                    : coupling::cut_interface(c, st.follower_along, st.leader_along, st.cracks, torn);
    st.released = std::move(cut.released);
    st.cut = std::move(cut.coupling);
    build_projection(world, i);
  }
}

size_t SeamSystem::released_points(size_t i) const {
  return static_cast<size_t>(std::count(seams_[i].released.begin(), seams_[i].released.end(), 1));
}

bool SeamSystem::connected(const World& world, size_t patch_a, const Eigen::Vector2d& uv_a, size_t patch_b,
                           const Eigen::Vector2d& uv_b) const {
  // The path between points of two coupled patches runs from each point straight to the seam, then
  // along it; only a crack on one of the three pieces separates them. With several seams between the
  // two patches (a closed cylinder) the nearest one decides.
  double nearest = std::numeric_limits<double>::infinity();
  bool connected = false;
  for (size_t i = 0; i < model_.interfaces.size(); ++i) {
    const scene::model::InterfaceSpec& spec = model_.interfaces[i];
    const coupling::Interface& c = spec.coupling;
    const auto l = static_cast<size_t>(c.leader_patch), f = static_cast<size_t>(c.follower_patch);
    if (!((l == patch_a && f == patch_b) || (l == patch_b && f == patch_a))) continue;
    const SeamSide sa = l == patch_a ? leader_side(model_, c) : follower_side(model_, c);
    const SeamSide sb = l == patch_a ? follower_side(model_, c) : leader_side(model_, c);
    const coupling::SeamCoordinate ca = seam_of(sa, uv_a), cb = seam_of(sb, uv_b);
    const double distance = ca.across + cb.across;
    if (distance >= nearest) continue;
    nearest = distance;
    auto clear = [](const shell::ShellPatch& p, const Eigen::Vector2d& from, const Eigen::Vector2d& to) {
      return !p.crack() || !p.crack()->crosses(from, to);
    };
    const double lo = std::min(ca.along, cb.along), hi = std::max(ca.along, cb.along);
    bool open = true;
    for (double s : seams_[i].cracks) open = open && !(s > lo && s < hi);
    connected = open &&
                clear(world.shell(patch_a), uv_a, coupling::seam_edge_parameter(*sa.surface, sa.side, sa.flip, ca.along)) &&
                clear(world.shell(patch_b), uv_b, coupling::seam_edge_parameter(*sb.surface, sb.side, sb.flip, cb.along));
  }
  return connected;
}

}  // namespace shellfrac::sim
