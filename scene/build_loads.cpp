// Loads, probes and initial velocity fields of a scene: parameter points normalised to [0, 1] mapped onto
// each patch's parameter domain, edges by name, and the per-control-point velocity shapes.
#include <cmath>

#include "core/constants.hpp"
#include "scene/build_context.hpp"

namespace shellfrac::scene::detail {

namespace {

// Normalised (s, t) in [0, 1]^2 to the patch parameter (u, v).
Eigen::Vector2d patch_parameter(const nurbs::NurbsSurface& surf, const Vec2& st) {
  const auto& ku = surf.knots_u();
  const auto& kv = surf.knots_v();
  return {ku.domain_begin() + st[0] * (ku.domain_end() - ku.domain_begin()),
          kv.domain_begin() + st[1] * (kv.domain_end() - kv.domain_begin())};
}

int edge_index(const std::string& side) { return side == "u0" ? 0 : side == "u1" ? 1 : side == "v0" ? 2 : 3; }

}  // namespace

model::Load build_load(const Builder& b, const Load& l, size_t index, const std::vector<model::Shell>& shells) {
  const std::string path = index_path("/loads", index);
  model::Load out;
  out.json_path = path;
  out.shell = shell_index(b, *l.shell, path + "/shell", shells);
  const std::string& type = *l.type;
  if (type == "pressure") {
    out.kind = model::Load::Kind::Pressure;
    out.pressure = *l.pressure;
  } else if (type == "point") {
    out.kind = model::Load::Kind::Point;
    out.at = patch_parameter(shells[out.shell].surface, *l.at);
    out.vector = vec3(*l.force);
  } else if (type == "edge") {
    out.kind = model::Load::Kind::Edge;
    out.edge = edge_index(*l.edge);
    out.vector = vec3(*l.force_per_length);
  } else {
    out.kind = model::Load::Kind::Body;
    out.vector = vec3(*l.acceleration);
  }
  if (l.ramp) out.ramp.keys = points2(*l.ramp);
  return out;
}

model::Probe build_probe(const Builder& b, const Probe& p, size_t index, const std::vector<model::Shell>& shells) {
  const std::string path = index_path("/output/probes", index);
  model::Probe out;
  out.name = *p.name;
  out.shell = shell_index(b, *p.shell, path + "/shell", shells);
  out.at = patch_parameter(shells[out.shell].surface, *p.at);
  out.every_step = p.every == "step";
  return out;
}

std::vector<Eigen::Vector3d> build_velocity_field(const Builder& b, const VelocityField& f, const nurbs::NurbsSurface& surf,
                                                  const std::string& path) {
  const int nu = surf.num_u(), nv = surf.num_v();
  const size_t count = static_cast<size_t>(nu) * static_cast<size_t>(nv);
  std::vector<Eigen::Vector3d> out(count, Eigen::Vector3d::Zero());
  if (f.shape == "list") {
    if (f.values->size() != count)
      b.fail(path + "/values", "expected one velocity per control point (" + std::to_string(nu) + " x " +
                                   std::to_string(nv) + " = " + std::to_string(count) + ", u running fastest), got " +
                                   std::to_string(f.values->size()));
    for (size_t k = 0; k < count; ++k) out[k] = vec3((*f.values)[k]);
    return out;
  }
  const auto& ku = surf.knots_u();
  const auto& kv = surf.knots_v();
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      // Normalised Greville coordinates: the control point's place in the patch (as pin regions use).
      const double s = normalised_greville(ku, i);
      const double t = normalised_greville(kv, j);
      Eigen::Vector3d v;
      if (f.shape == "sine") {
        v = *f.amplitude * vec3(*f.direction).normalized() * std::sin((*f.modes)[0] * core::kPi * s) *
            std::sin((*f.modes)[1] * core::kPi * t);
      } else {
        v = vec3_or(f.at_origin, {0, 0, 0}) + s * vec3_or(f.per_u, {0, 0, 0}) + t * vec3_or(f.per_v, {0, 0, 0});
      }
      out[static_cast<size_t>(i + nu * j)] = v;
    }
  return out;
}

}  // namespace shellfrac::scene::detail
