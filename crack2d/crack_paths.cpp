#include "crack2d/crack_paths.hpp"

#include <algorithm>
#include <cmath>
#include <map>
#include <utility>

namespace shellfrac::crack2d {

namespace {
constexpr double kPi = 3.14159265358979323846;
}  // namespace

void CrackPortals::build(const CrackIndex& index, double offset) {
  points_.clear();
  ahead_.clear();
  tips_.clear();
  tip_portals_.clear();
  corners_.clear();
  segments_ = index.num_segments();
  // Directions of the segments leaving each vertex; ends with identical coordinates are one vertex.
  std::map<std::pair<double, double>, std::vector<double>> leaving;
  for (size_t i = 0; i < index.num_segments(); ++i) {
    const Segment& s = index.segment(i);
    if (s.a == s.b) continue;
    const Point d = s.b - s.a;
    leaving[{s.a.x(), s.a.y()}].push_back(std::atan2(d.y(), d.x()));
    leaving[{s.b.x(), s.b.y()}].push_back(std::atan2(-d.y(), -d.x()));
  }
  const Box& domain = index.domain();
  for (auto& [key, angles] : leaving) {
    const Point v(key.first, key.second);
    std::sort(angles.begin(), angles.end());
    angles.erase(std::unique(angles.begin(), angles.end()), angles.end());
    // A sector wider than pi is a reflex corner: a shortest path can bend there. A free tip is one sector of
    // 2 pi (its portal lies straight beyond the tip). Convexity is kept by any linear map, so the test holds
    // in scaled coordinates too.
    const size_t n = angles.size();
    for (size_t k = 0; k < n; ++k) {
      const double from = angles[k];
      const double to = k + 1 < n ? angles[k + 1] : angles[0] + 2.0 * kPi;
      const double gap = to - from;
      if (!(gap > kPi)) continue;
      const double mid = from + 0.5 * gap;
      const Point dir(std::cos(mid), std::sin(mid));
      const Point p = v + offset * dir;
      if (!box_contains(domain, p)) continue;
      if (n == 1) {  // a free tip
        tips_.push_back(v);
        tip_portals_.push_back(points_.size());
      }
      points_.push_back(p);
      corners_.push_back(v);
      ahead_.push_back(dir);
    }
  }
}

double CrackPaths::scaled_length(const Point& a, const Point& b) const {
  return std::hypot((b.x() - a.x()) / s_.scale_u, (b.y() - a.y()) / s_.scale_v);
}

double CrackPaths::turn_at(const Node& n, const Point& next) const {
  if (n.in_dir.x() == 0.0 && n.in_dir.y() == 0.0) return 0.0;  // the source: no incoming direction
  Point d((next.x() - n.p.x()) / s_.scale_u, (next.y() - n.p.y()) / s_.scale_v);
  const double len = d.norm();
  if (!(len > 0.0)) return 0.0;
  return std::acos(std::clamp(n.in_dir.dot(d / len), -1.0, 1.0));
}

void CrackPaths::start(const CrackIndex& index, const CrackPortals& portals, const Point& source,
                       const PathSettings& s) {
  index_ = &index;
  s_ = s;
  nodes_.clear();
  settled_.clear();
  exhausted_ = false;
  Node src;
  src.p = source;
  src.length = 0.0;
  nodes_.push_back(src);
  // A portal farther than the limit in a straight line is farther along any path too.
  for (size_t i = 0; i < portals.size(); ++i)
    if (scaled_length(source, portals.points()[i]) <= s_.limit) {
      Node n;
      n.p = portals.points()[i];
      n.ahead = portals.ahead()[i];
      nodes_.push_back(n);
    }
  settle_next();  // the source
}

bool CrackPaths::settle_next() {
  size_t best = nodes_.size();
  for (size_t i = 0; i < nodes_.size(); ++i)
    if (!nodes_[i].settled && std::isfinite(nodes_[i].length) &&
        (best == nodes_.size() || nodes_[i].length < nodes_[best].length))
      best = i;
  if (best == nodes_.size()) {
    exhausted_ = true;
    return false;
  }
  Node& u = nodes_[best];
  u.settled = true;
  settled_.push_back(best);
  // Relax: a straight crack-free hop u -> v. The crossing test runs only when it would shorten v's path.
  for (size_t i = 0; i < nodes_.size(); ++i) {
    Node& v = nodes_[i];
    if (v.settled) continue;
    const double hop = scaled_length(u.p, v.p);
    const double length = u.length + hop;
    if (!(length < v.length) || length > s_.limit || !(hop > 0.0)) continue;
    const double turn = u.turn + turn_at(u, v.p);
    if (turn > s_.max_turn || !goes_ahead(u, v.p)) continue;
    if (index_->crosses(u.p, v.p)) continue;
    v.length = length;
    v.turn = turn;
    v.in_dir = Point((v.p.x() - u.p.x()) / s_.scale_u, (v.p.y() - u.p.y()) / s_.scale_v) / hop;
    const bool from_source = best == 0;
    v.first_hop = from_source ? v.p : u.first_hop;
    v.bends = from_source ? 0 : u.bends + 1;
  }
  return true;
}

bool CrackPaths::path_to(const Point& target, double& length, Point& first_hop) const {
  // Candidates by total length; the first whose last hop is crack-free is the shortest admissible path.
  std::vector<std::pair<double, size_t>> cand;
  cand.reserve(settled_.size());
  for (size_t id : settled_) {
    const Node& n = nodes_[id];
    const double total = n.length + scaled_length(n.p, target);
    if (total > s_.limit) continue;
    if (n.turn + turn_at(n, target) > s_.max_turn || !goes_ahead(n, target)) continue;
    cand.emplace_back(total, id);
  }
  std::sort(cand.begin(), cand.end());
  for (const auto& [total, id] : cand) {
    const Node& n = nodes_[id];
    if (index_->crosses(n.p, target)) continue;
    length = total;
    first_hop = id == 0 ? target : n.first_hop;
    last_bends_ = id == 0 ? 0 : n.bends + 1;
    return true;
  }
  return false;
}

}  // namespace shellfrac::crack2d
