#pragma once
// Shared by the build of a scene's parts (build.cpp, build_shells.cpp, build_parts.cpp): the scene's
// source for messages, conversions from the plain data, and the defaults of docs/scene-format.md.
#include <Eigen/Core>
#include <string>
#include <vector>

#include "nurbs/nurbs_surface.hpp"
#include "scene/model.hpp"
#include "scene/scene.hpp"
#include "scene/scene_error.hpp"

namespace shellfrac::scene::detail {

inline Eigen::Vector3d vec3(const Vec3& v) { return {v[0], v[1], v[2]}; }
inline Eigen::Vector3d vec3_or(const Opt<Vec3>& v, const Vec3& fallback) { return vec3(v.value_or(fallback)); }
inline Eigen::Vector2d vec2(const Vec2& v) { return {v[0], v[1]}; }
inline std::vector<Eigen::Vector2d> points2(const std::vector<Vec2>& pts) {
  std::vector<Eigen::Vector2d> out;
  out.reserve(pts.size());
  for (const Vec2& p : pts) out.push_back(vec2(p));
  return out;
}
inline core::WeibullStrength weibull_of(const Opt<WeibullSpec>& w) {
  core::WeibullStrength out;
  if (!w) return out;
  out.enabled = true;
  out.modulus = *w->modulus;
  out.scale_is_mean = w->scale_is_mean.value_or(false);
  out.seed = static_cast<unsigned long long>(w->seed.value_or(1));
  return out;
}
inline std::string index_path(const std::string& list, size_t i) { return list + "/" + std::to_string(i); }
// The Greville abscissa of basis function i mapped to [0, 1] over the knot vector's domain: a control
// point's place in the patch, as pin regions and initial velocity fields name it.
inline double normalised_greville(const nurbs::KnotVector& k, int i) {
  return (k.greville(i) - k.domain_begin()) / (k.domain_end() - k.domain_begin());
}

// Errors of the build, all naming the scene's source.
struct Builder {
  const Scene& scene;
  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw SceneError(scene.source, path, message);
  }
};

// The NURBS surface of a shell's patch, as the build makes it (refined control nets included); used by
// the resource estimate too (scene/estimate.cpp) for the grid blocks its particles touch.
nurbs::NurbsSurface patch_surface(const Builder& b, const Patch& p, const std::string& path);
model::Shell build_shell(const Builder& b, const Shell& s, size_t index);
model::SolidBody build_solid(const Builder& b, const Solid& s, size_t index);
model::BrittleBody build_brittle_solid(const Builder& b, const Solid& s, size_t index);  // build_brittle.cpp
model::RigidWorldSettings build_rigid_world(const Builder& b, const Opt<RigidWorldSpec>& spec);  // build_brittle.cpp
model::ColliderSpec build_collider(const Builder& b, const Collider& c, size_t index);
mpm::RigidMotion build_motion(const Motion& m);
// A shell named by name or by index; errors at `path`.
size_t shell_index(const Builder& b, const ShellRef& ref, const std::string& path, const std::vector<model::Shell>& shells);
// Refuses two pins holding one control point when one of them moves it.
void check_pin_conflicts(const Builder& b, const std::vector<model::Pin>& pins, const std::vector<model::Shell>& shells);
// build_loads.cpp: loads, probes (parameter points normalised to [0, 1]) and initial velocity fields.
model::Load build_load(const Builder& b, const Load& l, size_t index, const std::vector<model::Shell>& shells);
model::Probe build_probe(const Builder& b, const Probe& p, size_t index, const std::vector<model::Shell>& shells);
std::vector<Eigen::Vector3d> build_velocity_field(const Builder& b, const VelocityField& f, const nurbs::NurbsSurface& surf,
                                                  const std::string& path);
model::Pin build_pin(const Builder& b, const Pin& p, size_t index, const std::vector<model::Shell>& shells);
model::InterfaceSpec build_interface(const Builder& b, const Interface& i, size_t index,
                                     const std::vector<model::Shell>& shells);
// Exact closure moves the leader's coupled rows, which a pin or another seam's follower rows may also set.
void check_exact_closures(const Builder& b, const model::Model& m);

}  // namespace shellfrac::scene::detail
