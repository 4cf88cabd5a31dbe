#include <filesystem>
#include <memory>

#include "mpm/level_set_shape.hpp"
#include "sim/mesh_import.hpp"

#include "sim/scene_parts.hpp"

namespace shellfrac::sim {

namespace {

Eigen::Vector3d vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

Eigen::Vector3d unit_vector(ObjectReader& r, const std::string& key, std::vector<double> fallback) {
  const Eigen::Vector3d v = vec3(fallback.empty() ? r.numbers(key, 3) : r.numbers_or(key, fallback));
  if (v.norm() < 1e-12) r.fail(key, "direction must be a non-zero vector");
  return v.normalized();
}

// A mesh file (relative paths from the scene's folder) as a level set; errors name the "file" key.
std::shared_ptr<const mpm::LevelSetShape> read_mesh_shape(ObjectReader& r, double voxel) {
  const std::string file = r.string("file");
  std::filesystem::path path(file);
  if (path.is_relative()) path = std::filesystem::path(r.file()).parent_path() / path;
  const double scale = r.number_or("scale", 1.0, Range::positive());
  const Eigen::Vector3d translate = vec3(r.numbers_or("translate", {0, 0, 0}));
  const double band = r.number_or("band_voxels", 3.0, Range::closed(1.0, 100.0));
  try {
    const TriangleMesh mesh = import_mesh(path.string(), scale, translate);
    return std::make_shared<mpm::LevelSetShape>(mesh.vertices, mesh.triangles, voxel, band);
  } catch (const std::exception& e) {
    r.fail("file", path.string() + ": " + e.what());
  }
}

mpm::Boundary read_boundary(ObjectReader& r) {
  const std::string b = r.choice_or("boundary", "friction", {"sticky", "slip", "friction"});
  return b == "sticky" ? mpm::Boundary::Sticky : b == "slip" ? mpm::Boundary::Slip : mpm::Boundary::Friction;
}

}  // namespace

mpm::RigidMotion read_motion(ObjectReader r) {
  mpm::RigidMotion m;
  m.pivot = vec3(r.numbers_or("pivot", {0, 0, 0}));
  if (r.has("keyframes")) {
    const Json& frames = r.array("keyframes", 1);
    if (r.has("linear_velocity") || r.has("angular_velocity"))
      r.fail("keyframes", "give either keyframes or constant velocities, not both");
    for (size_t i = 0; i < frames.size(); ++i) {
      ObjectReader k(frames[i], r.child_path("keyframes") + "/" + std::to_string(i), r.file());
      mpm::Keyframe f;
      f.time = k.number("time", Range::non_negative());
      f.translation = vec3(k.numbers_or("translation", {0, 0, 0}));
      f.rotation = vec3(k.numbers_or("rotation", {0, 0, 0}));
      k.finish();
      if (!m.keyframes.empty() && !(f.time > m.keyframes.back().time))
        k.fail("time", "keyframe times must increase strictly");
      m.keyframes.push_back(f);
    }
  } else {
    m.linear_velocity = vec3(r.numbers_or("linear_velocity", {0, 0, 0}));
    m.angular_velocity = vec3(r.numbers_or("angular_velocity", {0, 0, 0}));
  }
  r.finish();
  return m;
}

std::vector<ColliderSpec> read_colliders(ObjectReader& root) {
  std::vector<ColliderSpec> out;
  if (!root.has("colliders")) return out;
  const Json& list = root.array("colliders");
  for (size_t i = 0; i < list.size(); ++i) {
    ObjectReader r(list[i], "/colliders/" + std::to_string(i), root.file());
    ColliderSpec c;
    c.name = r.string_or("name", "collider" + std::to_string(i));
    c.shape = r.choice("shape", {"half_space", "sphere", "box", "mesh"});
    if (c.shape == "mesh") {
      c.collider.shape = read_mesh_shape(r, r.number("voxel_size", Range::positive()));
    } else if (c.shape == "half_space") {
      c.collider.shape = std::make_shared<mpm::HalfSpace>(vec3(r.numbers("point", 3)), unit_vector(r, "normal", {}));
    } else if (c.shape == "sphere") {
      c.collider.shape = std::make_shared<mpm::Sphere>(vec3(r.numbers("center", 3)), r.number("radius", Range::positive()));
    } else {
      c.collider.shape = std::make_shared<mpm::Box>(vec3(r.numbers("center", 3)),
                                                    vec3(r.numbers("half_extents", 3, Range::positive())));
    }
    c.collider.boundary = read_boundary(r);
    c.collider.friction = r.number_or("friction", 0.3, Range::non_negative());
    if (auto m = r.optional_object("motion")) c.collider.motion = read_motion(*m);
    r.finish();
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<SolidBody> read_solids(ObjectReader& root) {
  std::vector<SolidBody> out;
  if (!root.has("solids")) return out;
  const Json& list = root.array("solids");
  for (size_t i = 0; i < list.size(); ++i) {
    ObjectReader r(list[i], "/solids/" + std::to_string(i), root.file());
    SolidBody b;
    b.name = r.string_or("name", "solid" + std::to_string(i));
    b.shape = r.choice("shape", {"sphere", "box", "mesh"});
    b.spacing = r.number("spacing", Range::positive());
    if (b.shape == "mesh") {
      const auto level_set = read_mesh_shape(r, r.number_or("voxel_size", 0.5 * b.spacing, Range::positive()));
      b.geometry = level_set;
      b.lo = level_set->lower();
      b.hi = level_set->upper();
    } else if (b.shape == "sphere") {
      const Eigen::Vector3d c = vec3(r.numbers("center", 3));
      const double radius = r.number("radius", Range::positive());
      b.geometry = std::make_shared<mpm::Sphere>(c, radius);
      b.lo = c - Eigen::Vector3d::Constant(radius);
      b.hi = c + Eigen::Vector3d::Constant(radius);
    } else {
      const Eigen::Vector3d c = vec3(r.numbers("center", 3));
      const Eigen::Vector3d h = vec3(r.numbers("half_extents", 3, Range::positive()));
      b.geometry = std::make_shared<mpm::Box>(c, h);
      b.lo = c - h;
      b.hi = c + h;
    }
    if ((b.hi - b.lo).minCoeff() < b.spacing)
      r.fail("spacing", "spacing is larger than the solid: no particle would fit");
    if (((b.hi - b.lo) / b.spacing).prod() > 5e7)
      r.fail("spacing", "spacing would create more than 50 million particles");
    b.poisson_disk = r.choice_or("sampling", "jittered", {"jittered", "poisson_disk"}) == "poisson_disk";
    b.seed = static_cast<unsigned>(r.integer_or("seed", 1, Range::closed(0, 2147483647)));
    ObjectReader m = r.object("material");
    b.material.model = m.choice_or("model", "neo_hookean", {"neo_hookean"});
    b.material.youngs_modulus = m.number("E", Range::positive());
    b.material.poisson_ratio = m.number("nu", Range::open(-1.0, 0.5));
    b.material.density = m.number("density", Range::positive());
    m.finish();
    b.initial_velocity = vec3(r.numbers_or("initial_velocity", {0, 0, 0}));
    r.finish();
    out.push_back(std::move(b));
  }
  return out;
}

size_t read_shell_reference(ObjectReader& r, const std::string& key, const std::vector<Shell>& shells) {
  const Json& which = r.raw(key);
  if (which.is_string()) {
    const std::string name = which.get<std::string>();
    size_t k = 0;
    while (k < shells.size() && shells[k].name != name) ++k;
    if (k == shells.size()) r.fail(key, "no shell is named \"" + name + "\"");
    return k;
  }
  if (shells.empty()) r.fail(key, "the scene has no shells");
  return static_cast<size_t>(r.integer(key, Range::closed(0, static_cast<double>(shells.size()) - 1)));
}

std::vector<Pin> read_pins(ObjectReader& root, const std::vector<Shell>& shells) {
  std::vector<Pin> out;
  if (!root.has("pins")) return out;
  const Json& list = root.array("pins");
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = "/pins/" + std::to_string(i);
    ObjectReader r(list[i], path, root.file());
    Pin pin;
    pin.json_path = path;
    pin.shell = read_shell_reference(r, "shell", shells);  // by name or by index
    const auto& surf = shells[pin.shell].surface;
    const int nu = surf.num_u(), nv = surf.num_v();
    const bool has_region = r.has("region"), has_points = r.has("control_points");
    if (has_region == has_points) r.fail_here("a pin needs exactly one of \"region\" or \"control_points\"");
    if (has_region) {
      // Control points whose Greville abscissae, normalised to [0, 1] over the patch, lie in the box.
      ObjectReader reg = r.object("region");
      const auto u = reg.numbers_or("u", {0, 1}, Range::closed(0, 1));
      const auto v = reg.numbers_or("v", {0, 1}, Range::closed(0, 1));
      reg.finish();
      if (u[0] > u[1]) r.fail("region", "u range is reversed");
      if (v[0] > v[1]) r.fail("region", "v range is reversed");
      const auto& ku = surf.knots_u();
      const auto& kv = surf.knots_v();
      for (int j = 0; j < nv; ++j)
        for (int i = 0; i < nu; ++i) {
          const double s = (ku.greville(i) - ku.domain_begin()) / (ku.domain_end() - ku.domain_begin());
          const double t = (kv.greville(j) - kv.domain_begin()) / (kv.domain_end() - kv.domain_begin());
          if (s >= u[0] - 1e-12 && s <= u[1] + 1e-12 && t >= v[0] - 1e-12 && t <= v[1] + 1e-12)
            pin.control_points.push_back(i + nu * j);
        }
      if (pin.control_points.empty())
        r.fail("region", "the region selects no control point of shell \"" + shells[pin.shell].name + "\"");
    } else {
      const Json& pts = r.array("control_points", 1);
      for (size_t k = 0; k < pts.size(); ++k) {
        const std::string p = r.child_path("control_points") + "/" + std::to_string(k);
        if (!pts[k].is_array() || pts[k].size() != 2 || !pts[k][0].is_number_integer() || !pts[k][1].is_number_integer())
          throw SceneError(r.file(), p, "expected a control point index pair [i, j]");
        const int ci = pts[k][0].get<int>(), cj = pts[k][1].get<int>();
        if (ci < 0 || ci >= nu || cj < 0 || cj >= nv)
          throw SceneError(r.file(), p, "control point [" + std::to_string(ci) + ", " + std::to_string(cj) +
                                            "] is outside the patch: allowed are [0.." + std::to_string(nu - 1) +
                                            ", 0.." + std::to_string(nv - 1) + "]");
        pin.control_points.push_back(ci + nu * cj);
      }
    }
    if (auto m = r.optional_object("motion")) pin.motion = read_motion(*m);
    r.finish();
    out.push_back(std::move(pin));
  }
  return out;
}

}  // namespace shellfrac::sim

namespace shellfrac::sim {

namespace {

// A limit of the interface's "verify" object: a number in `range`, or null to switch the check off.
VerifyLimit read_verify_limit(ObjectReader& r, const std::string& key, const Range& range) {
  VerifyLimit limit;
  if (!r.has(key)) return limit;
  if (r.raw(key).is_null()) {
    limit.checked = false;
    return limit;
  }
  limit.value = r.number(key, range);
  return limit;
}

InterfaceVerify read_interface_verify(ObjectReader& r) {
  InterfaceVerify v;
  v.max_gap = read_verify_limit(r, "max_gap", Range::non_negative());
  v.max_angle_degrees = read_verify_limit(r, "max_angle_degrees", Range::closed(0.0, 180.0));
  v.max_stress_ratio = read_verify_limit(r, "max_stress_ratio", Range::positive());
  r.finish();
  return v;
}

}  // namespace

namespace {

// Flat indices of the control points within six rows of `side` (the coupled rows and their neighbours).
std::vector<int> rows_near_side(const nurbs::NurbsSurface& s, coupling::Side side) {
  constexpr int kRows = 6;
  const int nu = s.num_u(), nv = s.num_v();
  std::vector<int> out;
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      int depth = 0;
      switch (side) {
        case coupling::Side::U0: depth = i; break;
        case coupling::Side::U1: depth = nu - 1 - i; break;
        case coupling::Side::V0: depth = j; break;
        case coupling::Side::V1: depth = nv - 1 - j; break;
      }
      if (depth < kRows) out.push_back(i + nu * j);
    }
  return out;
}

}  // namespace

std::vector<InterfaceSpec> read_interfaces(ObjectReader& root, const std::vector<Shell>& shells) {
  std::vector<InterfaceSpec> out;
  if (!root.has("interfaces")) return out;
  const Json& list = root.array("interfaces");
  const std::vector<std::string> sides{"u0", "u1", "v0", "v1"};
  for (size_t i = 0; i < list.size(); ++i) {
    const std::string path = "/interfaces/" + std::to_string(i);
    ObjectReader r(list[i], path, root.file());
    auto read_edge = [&](const std::string& key, size_t& shell, coupling::Side& side) {
      ObjectReader e = r.object(key);
      shell = read_shell_reference(e, "shell", shells);
      const std::string s = e.choice("side", sides);
      side = s == "u0" ? coupling::Side::U0 : s == "u1" ? coupling::Side::U1 : s == "v0" ? coupling::Side::V0 : coupling::Side::V1;
      e.finish();
    };
    size_t a = 0, b = 0;
    coupling::Side sa{}, sb{};
    read_edge("a", a, sa);
    read_edge("b", b, sb);
    if (a == b) r.fail("b", "an interface couples two different shells");
    coupling::InterfaceOptions options;
    // "none" declares a seam that is measured but never coupled; its operators (C0) are built only to
    // check the edges and to know which side leads.
    const std::string continuity = r.choice_or("continuity", "C1", {"C0", "C1", "none"});
    options.continuity = continuity == "C1" ? coupling::Continuity::C1 : coupling::Continuity::C0;
    options.tolerance = r.number_or("tolerance", 1e-8, Range::positive());
    const bool reversed = r.boolean_or("reversed", false);
    const bool correction = r.boolean_or("momentum_correction", true);
    const std::string closure = r.choice_or("closure", "least_squares", {"least_squares", "exact"});
    if (closure == "exact" && continuity == "none") r.fail("closure", "a seam with \"continuity\": \"none\" is never closed");
    options.closure = closure == "exact" ? coupling::Closure::Exact : coupling::Closure::LeastSquares;
    const bool both_sides = r.choice_or("seam_velocity", "leader", {"leader", "projected"}) == "projected";
    InterfaceSpec spec;
    if (auto v = r.optional_object("verify")) spec.verify = read_interface_verify(*v);
    spec.coupled = continuity != "none";
    r.finish();
    try {
      spec.coupling = coupling::make_interface(shells[a].surface, static_cast<int>(a), sa, shells[b].surface,
                                               static_cast<int>(b), sb, reversed, options);
    } catch (const std::invalid_argument& e) {
      r.fail_here(std::string("cannot couple these edges: ") + e.what());
    }
    spec.json_path = path;
    spec.momentum_correction = correction;
    spec.project_both_sides = both_sides;
    // Rows 0..5 counted from the coupled side: the coupled rows plus those whose quadratic stencils
    // share grid nodes with them.
    const coupling::Interface& c = spec.coupling;
    spec.follower_neighbours = rows_near_side(shells[static_cast<size_t>(c.follower_patch)].surface, c.follower_side);
    spec.leader_neighbours = rows_near_side(shells[static_cast<size_t>(c.leader_patch)].surface, c.leader_side);
    out.push_back(std::move(spec));
  }
  return out;
}

}  // namespace shellfrac::sim
