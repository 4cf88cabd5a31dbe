#include "output/seam_metrics.hpp"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>

#include "core/constants.hpp"
#include "coupling/edge.hpp"

namespace shellfrac::output {

namespace {

using Eigen::Vector2d;
using Eigen::Vector3d;

constexpr double kSeamCells = 2.0;  // the band next to the seam whose stress is compared
constexpr double kPinCells = 2.0;   // how far a pin's stress spike is excluded

std::string side_key(coupling::Side s) {
  switch (s) {
    case coupling::Side::U0: return "u0";
    case coupling::Side::U1: return "u1";
    case coupling::Side::V0: return "v0";
    case coupling::Side::V1: return "v1";
  }
  return "?";
}

bool along_v(coupling::Side s) { return s == coupling::Side::U0 || s == coupling::Side::U1; }

// Maps a parameter onto "cell units": span j of the non-empty spans covers [j, j + 1]. Distances in
// these units count cells whatever the knot spacing (cylinders join arc pieces at double knots).
class CellCoordinate {
 public:
  explicit CellCoordinate(const nurbs::KnotVector& k) {
    breaks_.push_back(k.domain_begin());
    for (double b : k.interior_breakpoints()) breaks_.push_back(b);
    breaks_.push_back(k.domain_end());
  }
  int cells() const { return static_cast<int>(breaks_.size()) - 1; }
  double operator()(double t) const {
    const auto it = std::upper_bound(breaks_.begin(), breaks_.end(), t);
    const int j = std::clamp(static_cast<int>(it - breaks_.begin()) - 1, 0, cells() - 1);
    const double lo = breaks_[static_cast<size_t>(j)], hi = breaks_[static_cast<size_t>(j) + 1];
    return j + std::clamp((t - lo) / (hi - lo), 0.0, 1.0);
  }

 private:
  std::vector<double> breaks_;
};

// Largest seam-band stress and median of one patch, in cells away from pins.
struct PatchStress {
  double seam_max = 0;
  double median = 0;
};

PatchStress patch_stress(const shell::ShellPatch& p, const std::vector<double>& stress, coupling::Side side,
                         const std::vector<const scene::model::Pin*>& pins) {
  const CellCoordinate cu(p.reference().knots_u()), cv(p.reference().knots_v());
  const int nu = cu.cells(), nv = cv.cells();
  // Cells whose box comes closer than kPinCells to a pinned control point (its Greville point).
  std::vector<unsigned char> near_pin(static_cast<size_t>(nu * nv), 0);
  for (const scene::model::Pin* pin : pins)
    for (int k : pin->control_points) {
      const Vector2d g = p.control_parameter(static_cast<size_t>(k));
      const double pu = cu(g.x()), pv = cv(g.y());
      for (int j = 0; j < nv; ++j) {
        if (j + 1 <= pv - kPinCells || j >= pv + kPinCells) continue;
        for (int i = 0; i < nu; ++i)
          if (i + 1 > pu - kPinCells && i < pu + kPinCells) near_pin[static_cast<size_t>(i + nu * j)] = 1;
      }
    }
  PatchStress out;
  std::vector<double> kept;
  kept.reserve(stress.size());
  for (size_t q = 0; q < stress.size(); ++q) {
    const Vector2d& uv = p.parameter(q);
    const double a = cu(uv.x()), b = cv(uv.y());
    const int i = std::min(static_cast<int>(a), nu - 1), j = std::min(static_cast<int>(b), nv - 1);
    if (near_pin[static_cast<size_t>(i + nu * j)]) continue;
    kept.push_back(stress[q]);
    double depth = 0;  // cells between the point and the seam
    switch (side) {
      case coupling::Side::U0: depth = a; break;
      case coupling::Side::U1: depth = nu - a; break;
      case coupling::Side::V0: depth = b; break;
      case coupling::Side::V1: depth = nv - b; break;
    }
    if (depth <= kSeamCells) out.seam_max = std::max(out.seam_max, stress[q]);
  }
  if (kept.empty()) return out;
  const auto mid = kept.begin() + static_cast<long>(kept.size() / 2);
  std::nth_element(kept.begin(), mid, kept.end());
  out.median = *mid;
  return out;
}

// Number of samples along an edge: several per cell of the finer side, so that the gap of a
// least-squares (non-nested) seam is seen between the knots, not only at them.
int edge_samples(const nurbs::NurbsSurface& a, coupling::Side sa, const nurbs::NurbsSurface& b, coupling::Side sb) {
  const int ca = (along_v(sa) ? a.knots_v() : a.knots_u()).num_spans();
  const int cb = (along_v(sb) ? b.knots_v() : b.knots_u()).num_spans();
  return std::max(256, 8 * std::max(ca, cb)) + 1;
}

struct EdgeParameters {
  double begin, end;
};

EdgeParameters edge_range(const nurbs::NurbsSurface& s, coupling::Side side) {
  const nurbs::KnotVector& k = along_v(side) ? s.knots_v() : s.knots_u();
  return {k.domain_begin(), k.domain_end()};
}

// Gap and normal angle along one seam. Points are paired by edge parameter: the leader's fraction f
// corresponds to the follower's f (1 - f when reversed), the same affine map the coupling uses.
void measure_edge(const nurbs::NurbsSurface& leader, const nurbs::NurbsSurface& follower,
                  const nurbs::NurbsSurface& leader_ref, const nurbs::NurbsSurface& follower_ref,
                  const coupling::Interface& c, const std::vector<double>& cracks, SeamMeasurement& m) {
  const double margin = 2.0 / (along_v(c.leader_side) ? leader.knots_v() : leader.knots_u()).num_spans();
  const int n = edge_samples(leader, c.leader_side, follower, c.follower_side);
  const EdgeParameters rl = edge_range(leader, c.leader_side), rf = edge_range(follower, c.follower_side);
  std::vector<Vector2d> uv_l(static_cast<size_t>(n)), uv_f(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    const double f = static_cast<double>(k) / (n - 1);
    const double g = c.reversed ? 1.0 - f : f;
    uv_l[static_cast<size_t>(k)] =
        coupling::edge_to_surface_parameter(leader, c.leader_side, rl.begin + f * (rl.end - rl.begin));
    uv_f[static_cast<size_t>(k)] =
        coupling::edge_to_surface_parameter(follower, c.follower_side, rf.begin + g * (rf.end - rf.begin));
  }
  // Orientation of the follower's normal relative to the leader's, from the rest state.
  double agree = 0;
  for (size_t k = 0; k < uv_l.size(); ++k)
    agree += leader_ref.normal(uv_l[k].x(), uv_l[k].y()).dot(follower_ref.normal(uv_f[k].x(), uv_f[k].y()));
  const double sign = agree < 0 ? -1.0 : 1.0;
  for (size_t k = 0; k < uv_l.size(); ++k) {
    const double f = static_cast<double>(k) / (n - 1);
    if (std::any_of(cracks.begin(), cracks.end(), [&](double s) { return std::abs(s - f) < margin; })) continue;
    const nurbs::SurfacePoint a = leader.evaluate(uv_l[k].x(), uv_l[k].y());
    const nurbs::SurfacePoint b = follower.evaluate(uv_f[k].x(), uv_f[k].y());
    m.gap = std::max(m.gap, (a.x - b.x).norm());
    // atan2 keeps small angles accurate (acos loses half the digits near 0).
    const Vector3d nb = sign * b.normal;
    const double angle = std::atan2(a.normal.cross(nb).norm(), a.normal.dot(nb));
    m.angle_degrees = std::max(m.angle_degrees, angle * 180.0 / core::kPi);
  }
}

std::string continuity_name(const scene::model::InterfaceSpec& spec) {
  if (!spec.coupled) return "none";
  return spec.coupling.continuity == coupling::Continuity::C1 ? "C1" : "C0";
}

}  // namespace

std::vector<const scene::model::InterfaceSpec*> scene_seams(const scene::Model& scene) {
  std::vector<const scene::model::InterfaceSpec*> out;
  for (const scene::model::InterfaceSpec& s : scene.interfaces) out.push_back(&s);
  for (const scene::model::InterfaceSpec& s : scene.uncoupled_seams) out.push_back(&s);
  // "/interfaces/<i>": order by i, as written in the scene file.
  auto index = [](const scene::model::InterfaceSpec* s) { return std::stoul(s->json_path.substr(s->json_path.rfind('/') + 1)); };
  std::sort(out.begin(), out.end(), [&](const scene::model::InterfaceSpec* a, const scene::model::InterfaceSpec* b) { return index(a) < index(b); });
  return out;
}

std::vector<SeamMeasurement> measure_seams(const scene::Model& scene, const sim::World& world,
                                           const SeamCrackPositions& cracks) {
  static const std::vector<double> none;
  const std::vector<const scene::model::InterfaceSpec*> seams = scene_seams(scene);
  std::vector<nurbs::NurbsSurface> current;
  current.reserve(world.num_shells());
  for (size_t i = 0; i < world.num_shells(); ++i) current.push_back(world.shell(i).current_surface());
  std::map<size_t, std::vector<double>> stress;  // per patch on a seam, computed once
  std::vector<SeamMeasurement> out;
  for (const scene::model::InterfaceSpec* spec : seams) {
    const coupling::Interface& c = spec->coupling;
    const auto l = static_cast<size_t>(c.leader_patch), f = static_cast<size_t>(c.follower_patch);
    SeamMeasurement m;
    m.json_path = spec->json_path;
    // Coupled interfaces are entries of scene.interfaces; "none" seams never carry crack positions.
    const auto index = static_cast<size_t>(spec - scene.interfaces.data());
    const bool listed = spec->coupled && index < cracks.size();
    measure_edge(current[l], current[f], world.shell(l).reference(), world.shell(f).reference(), c,
                 listed ? cracks[index] : none, m);
    for (const auto& [patch, side] : {std::pair{l, c.leader_side}, std::pair{f, c.follower_side}}) {
      auto it = stress.find(patch);
      if (it == stress.end()) it = stress.emplace(patch, world.shell(patch).mid_surface_stress()).first;
      std::vector<const scene::model::Pin*> pins;
      for (const scene::model::Pin& pin : scene.pins)
        if (pin.shell == patch) pins.push_back(&pin);
      const PatchStress ps = patch_stress(world.shell(patch), it->second, side, pins);
      // Below a strain of about 1e-9 the median is round-off (a shell at rest or in free fall).
      if (ps.median <= 1e-9 * scene.shells[patch].material.youngs_modulus) continue;
      const double ratio = ps.seam_max / ps.median;
      m.stress_ratio = std::max(m.stress_ratio.value_or(ratio), ratio);
    }
    out.push_back(std::move(m));
  }
  return out;
}

double model_size(const scene::Model& scene) {
  Vector3d lo = Vector3d::Constant(1e300), hi = Vector3d::Constant(-1e300);
  for (const scene::model::Shell& s : scene.shells)
    for (const Vector3d& x : s.surface.control_points()) {
      lo = lo.cwiseMin(x);
      hi = hi.cwiseMax(x);
    }
  return scene.shells.empty() ? 0.0 : (hi - lo).norm();
}

SeamThresholds seam_thresholds(const scene::Model& scene, const scene::model::InterfaceSpec& spec) {
  const bool c1 = spec.coupled && spec.coupling.continuity == coupling::Continuity::C1;
  SeamThresholds t;
  if (spec.coupled) t.max_gap = 1e-9 * model_size(scene);
  if (c1) t.max_angle_degrees = 0.5;
  // Stress that is not the seam's doing (a collider under the seam, a ring's bending peak at its sides)
  // puts the ratio well above 2 even without a seam, so the default only catches what no load explains:
  // a seam that drags its neighbours along (docs/coupling.md, "Stress ratio").
  if (spec.coupled) t.max_stress_ratio = kDefaultMaxStressRatio;
  auto apply = [](const scene::model::VerifyLimit& given, std::optional<double>& limit) {
    if (!given.checked) limit.reset();
    else if (given.value) limit = given.value;
  };
  apply(spec.verify.max_gap, t.max_gap);
  apply(spec.verify.max_angle_degrees, t.max_angle_degrees);
  apply(spec.verify.max_stress_ratio, t.max_stress_ratio);
  return t;
}

SeamRecorder::SeamRecorder(const scene::Model& scene) : scene_(scene), series_(scene_seams(scene).size()) {}

void SeamRecorder::record(int frame, double time, const sim::World& world,
                          const SeamCrackPositions& cracks) {
  if (!active()) return;
  std::vector<SeamMeasurement> m = measure_seams(scene_, world, cracks);
  for (size_t i = 0; i < m.size(); ++i) series_[i].push_back({frame, time, std::move(m[i])});
}

std::vector<InterfaceReport> SeamRecorder::reports() const {
  std::vector<InterfaceReport> out;
  const std::vector<const scene::model::InterfaceSpec*> seams = scene_seams(scene_);
  for (size_t i = 0; i < seams.size(); ++i) {
    const scene::model::InterfaceSpec& spec = *seams[i];
    const coupling::Interface& c = spec.coupling;
    const SeamThresholds limits = seam_thresholds(scene_, spec);
    InterfaceReport r;
    // Maxima over the frames, with the frame where each happened.
    struct Peak {
      std::optional<double> value;
      int frame = -1;
      double time = 0;
    } gap, angle, ratio;
    auto update = [](Peak& p, const std::optional<double>& v, const Sample& s) {
      if (!v) return;
      if (!p.value || *v > *p.value || std::isnan(*v)) p = {v, s.frame, s.time};
    };
    for (const Sample& s : series_[i]) {
      r.frames.push_back({s.frame, s.time, s.m.gap, s.m.angle_degrees, s.m.stress_ratio});
      update(gap, s.m.gap, s);
      update(angle, s.m.angle_degrees, s);
      update(ratio, s.m.stress_ratio, s);
    }
    auto check = [&](const Peak& p, const std::optional<double>& limit) {
      SeamCheck out;
      out.max = p.value;
      if (p.frame >= 0) {
        out.frame = p.frame;
        out.time = p.time;
      }
      out.limit = limit;
      // A metric never measured (a stress ratio with no stress anywhere) cannot fail; NaN always does.
      const bool ok = !limit || !p.value || *p.value <= *limit;
      out.result = !limit ? "unchecked" : !p.value ? "not measured" : ok ? "pass" : "fail";
      r.pass = r.pass && ok;
      return out;
    };
    const auto& lead = scene_.shells[static_cast<size_t>(c.leader_patch)];
    const auto& follow = scene_.shells[static_cast<size_t>(c.follower_patch)];
    r.interface = spec.json_path;
    r.leader = lead.name + "." + side_key(c.leader_side);
    r.follower = follow.name + "." + side_key(c.follower_side);
    r.reversed = c.reversed;
    r.continuity = continuity_name(spec);
    r.momentum_correction = spec.coupled && spec.momentum_correction;
    r.gap = check(gap, limits.max_gap);
    r.angle_degrees = check(angle, limits.max_angle_degrees);
    r.stress_ratio = check(ratio, limits.max_stress_ratio);
    out.push_back(std::move(r));
  }
  return out;
}

}  // namespace shellfrac::output
