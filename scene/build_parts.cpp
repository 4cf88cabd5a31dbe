// Solids, colliders, motions, pins and interfaces of a scene: shapes and mesh level sets, pinned control
// points selected on the built patches, and coupling operators between patch edges (thesis sec. 4.8).
#include <algorithm>
#include <filesystem>
#include <memory>

#include "mpm/level_set_shape.hpp"
#include "scene/build_context.hpp"
#include "scene/mesh_import.hpp"
#include "scene/range.hpp"

namespace shellfrac::scene::detail {

namespace {

// A mesh file (relative paths from the scene's folder) as a level set; errors name the "file" key.
std::shared_ptr<const mpm::LevelSetShape> mesh_shape(const Builder& b, const MeshFile& m, double voxel,
                                                     const std::string& path) {
  std::filesystem::path file(*m.file);
  if (file.is_relative()) file = std::filesystem::path(b.scene.source).parent_path() / file;
  try {
    const TriangleMesh mesh = import_mesh(file.string(), m.scale.value_or(1.0), vec3_or(m.translate, {0, 0, 0}));
    return std::make_shared<mpm::LevelSetShape>(mesh.vertices, mesh.triangles, voxel, m.band_voxels.value_or(3.0));
  } catch (const std::exception& e) {
    b.fail(path + "/file", file.string() + ": " + e.what());
  }
}

mpm::Boundary boundary_of(const Opt<std::string>& b) {
  return b == "sticky" ? mpm::Boundary::Sticky : b == "slip" ? mpm::Boundary::Slip : mpm::Boundary::Friction;
}


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

coupling::Side side_of(const std::string& s) {
  return s == "u0" ? coupling::Side::U0 : s == "u1" ? coupling::Side::U1 : s == "v0" ? coupling::Side::V0 : coupling::Side::V1;
}

model::VerifyLimit limit_of(const Opt<VerifyLimit>& l) {
  model::VerifyLimit out;
  if (!l) return out;
  out.checked = l->value.has_value();
  out.value = l->value;
  return out;
}

bool contains(const std::vector<int>& list, int k) { return std::find(list.begin(), list.end(), k) != list.end(); }

}  // namespace

// A shell named by name or by index; errors at `path`.
size_t shell_index(const Builder& b, const ShellRef& ref, const std::string& path, const std::vector<model::Shell>& shells) {
  if (const auto* name = std::get_if<std::string>(&ref)) {
    for (size_t k = 0; k < shells.size(); ++k)
      if (shells[k].name == *name) return k;
    b.fail(path, "no shell is named \"" + *name + "\"");
  }
  if (shells.empty()) b.fail(path, "the scene has no shells");
  const int k = std::get<int>(ref);
  const Range allowed = Range::closed(0, static_cast<double>(shells.size()) - 1);
  if (!allowed.contains(k)) b.fail(path, allowed.violation(k));
  return static_cast<size_t>(k);
}

model::SolidBody build_solid(const Builder& b, const Solid& s, size_t index) {
  const std::string path = index_path("/solids", index);
  model::SolidBody out;
  out.name = s.name.value_or("solid" + std::to_string(index));
  out.shape = *s.shape;
  out.spacing = *s.spacing;
  if (out.shape == "mesh") {
    const auto level_set = mesh_shape(b, s.mesh, s.mesh.voxel_size.value_or(0.5 * out.spacing), path);
    out.geometry = level_set;
    out.lo = level_set->lower();
    out.hi = level_set->upper();
  } else if (out.shape == "sphere") {
    const Eigen::Vector3d c = vec3(*s.center);
    out.geometry = std::make_shared<mpm::Sphere>(c, *s.radius);
    out.lo = c - Eigen::Vector3d::Constant(*s.radius);
    out.hi = c + Eigen::Vector3d::Constant(*s.radius);
  } else {
    const Eigen::Vector3d c = vec3(*s.center), h = vec3(*s.half_extents);
    out.geometry = std::make_shared<mpm::Box>(c, h);
    out.lo = c - h;
    out.hi = c + h;
  }
  if ((out.hi - out.lo).minCoeff() < out.spacing) b.fail(path + "/spacing", "spacing is larger than the solid: no particle would fit");
  if (((out.hi - out.lo) / out.spacing).prod() > 5e7)
    b.fail(path + "/spacing", "spacing would create more than 50 million particles");
  out.poisson_disk = s.sampling == "poisson_disk";
  out.seed = static_cast<unsigned>(s.seed.value_or(1));
  out.material.model = s.material->model.value_or("neo_hookean");
  out.material.youngs_modulus = *s.material->youngs_modulus;
  out.material.poisson_ratio = *s.material->poisson_ratio;
  out.material.density = *s.material->density;
  out.initial_velocity = vec3_or(s.initial_velocity, {0, 0, 0});
  return out;
}

mpm::RigidMotion build_motion(const Motion& m) {
  mpm::RigidMotion out;
  out.pivot = vec3_or(m.pivot, {0, 0, 0});
  if (m.keyframes) {
    for (const Keyframe& k : *m.keyframes) {
      mpm::Keyframe f;
      f.time = *k.time;
      f.translation = vec3_or(k.translation, {0, 0, 0});
      f.rotation = vec3_or(k.rotation, {0, 0, 0});
      out.keyframes.push_back(f);
    }
  } else {
    out.linear_velocity = vec3_or(m.linear_velocity, {0, 0, 0});
    out.angular_velocity = vec3_or(m.angular_velocity, {0, 0, 0});
  }
  return out;
}

model::ColliderSpec build_collider(const Builder& b, const Collider& c, size_t index) {
  const std::string path = index_path("/colliders", index);
  model::ColliderSpec out;
  out.name = c.name.value_or("collider" + std::to_string(index));
  out.shape = *c.shape;
  if (out.shape == "mesh") {
    out.collider.shape = mesh_shape(b, c.mesh, *c.mesh.voxel_size, path);
  } else if (out.shape == "half_space") {
    out.collider.shape = std::make_shared<mpm::HalfSpace>(vec3(*c.point), vec3(*c.normal).normalized());
  } else if (out.shape == "sphere") {
    out.collider.shape = std::make_shared<mpm::Sphere>(vec3(*c.center), *c.radius);
  } else {
    out.collider.shape = std::make_shared<mpm::Box>(vec3(*c.center), vec3(*c.half_extents));
  }
  out.collider.boundary = boundary_of(c.boundary);
  out.collider.friction = c.friction.value_or(0.3);
  if (c.motion) out.collider.motion = build_motion(*c.motion);
  return out;
}

namespace {

// The control points of the first `rows` rows from a patch edge, with the edge's parameter point beside
// each (where the edge frame is taken).
struct EdgeRow {
  int index;
  double u, v;
};
std::vector<EdgeRow> edge_rows(const nurbs::NurbsSurface& surf, const std::string& side, int rows) {
  const int nu = surf.num_u(), nv = surf.num_v();
  const auto& ku = surf.knots_u();
  const auto& kv = surf.knots_v();
  std::vector<EdgeRow> out;
  if (side == "u0" || side == "u1") {
    const double u = side == "u0" ? ku.domain_begin() : ku.domain_end();
    for (int r = 0; r < std::min(rows, nu); ++r)
      for (int j = 0; j < nv; ++j) out.push_back({(side == "u0" ? r : nu - 1 - r) + nu * j, u, kv.greville(j)});
  } else {
    const double v = side == "v0" ? kv.domain_begin() : kv.domain_end();
    for (int r = 0; r < std::min(rows, nv); ++r)
      for (int i = 0; i < nu; ++i) out.push_back({i + nu * (side == "v0" ? r : nv - 1 - r), ku.greville(i), v});
  }
  return out;
}

// The unit directions a component list names in the pin's frame; `edge` is the edge frame at the point
// (columns: surface normal, edge tangent, in-surface direction across the edge).
std::vector<Eigen::Vector3d> held_directions(const Pin& p, const Eigen::Matrix3d& edge) {
  const std::string frame = p.frame.value_or("global");
  std::vector<Eigen::Vector3d> out;
  if (frame == "global") {
    for (const std::string& c : *p.components) out.push_back(Eigen::Vector3d::Unit(c == "x" ? 0 : c == "y" ? 1 : 2));
    return out;
  }
  Eigen::Matrix3d basis = edge;  // normal, then two tangential directions
  if (frame == "plane") {
    const Eigen::Vector3d n = vec3(*p.plane_normal).normalized();
    const Eigen::Vector3d t1 = n.unitOrthogonal();
    basis << n, t1, n.cross(t1);
  }
  for (const std::string& c : *p.components) {
    if (c == "normal") out.push_back(basis.col(0));
    if (c == "along" || c == "tangential") out.push_back(basis.col(1));
    if (c == "across" || c == "tangential") out.push_back(basis.col(2));
  }
  return out;
}

}  // namespace

model::Pin build_pin(const Builder& b, const Pin& p, size_t index, const std::vector<model::Shell>& shells) {
  const std::string path = index_path("/pins", index);
  model::Pin pin;
  pin.json_path = path;
  pin.name = p.name.value_or("pin" + std::to_string(index));
  pin.shell = shell_index(b, *p.shell, path + "/shell", shells);
  const auto& surf = shells[pin.shell].surface;
  const int nu = surf.num_u(), nv = surf.num_v();
  std::vector<Eigen::Matrix3d> frames;  // edge frame per selected point (edges only)
  if (p.region) {
    // Control points whose Greville abscissae, normalised to [0, 1] over the patch, lie in the box.
    const Vec2 u = p.region->u.value_or(Vec2{0, 1}), v = p.region->v.value_or(Vec2{0, 1});
    const auto& ku = surf.knots_u();
    const auto& kv = surf.knots_v();
    for (int j = 0; j < nv; ++j)
      for (int i = 0; i < nu; ++i) {
        const double s = normalised_greville(ku, i);
        const double t = normalised_greville(kv, j);
        if (s >= u[0] - 1e-12 && s <= u[1] + 1e-12 && t >= v[0] - 1e-12 && t <= v[1] + 1e-12)
          pin.control_points.push_back(i + nu * j);
      }
    if (pin.control_points.empty())
      b.fail(path + "/region", "the region selects no control point of shell \"" + shells[pin.shell].name + "\"");
  } else if (p.control_points) {
    const std::vector<Int2>& pts = *p.control_points;
    for (size_t k = 0; k < pts.size(); ++k) {
      const int ci = pts[k][0], cj = pts[k][1];
      if (ci < 0 || ci >= nu || cj < 0 || cj >= nv)
        b.fail(index_path(path + "/control_points", k),
               "control point [" + std::to_string(ci) + ", " + std::to_string(cj) + "] is outside the patch: allowed are [0.." +
                   std::to_string(nu - 1) + ", 0.." + std::to_string(nv - 1) + "]");
      pin.control_points.push_back(ci + nu * cj);
    }
  } else {
    const int rows = p.rows.value_or(1);
    for (size_t e = 0; e < p.edges->size(); ++e) {
      const std::string& side = (*p.edges)[e];
      const int across = side[0] == 'u' ? nu : nv;
      if (rows > across)
        b.fail(path + "/rows", std::to_string(rows) + " rows from edge " + side + " but the patch has " + std::to_string(across));
      for (const EdgeRow& r : edge_rows(surf, side, rows)) {
        if (std::find(pin.control_points.begin(), pin.control_points.end(), r.index) != pin.control_points.end())
          continue;  // a corner of two listed edges: held once (by the first edge's frame)
        pin.control_points.push_back(r.index);
        const nurbs::SurfacePoint sp = surf.evaluate(r.u, r.v);
        Eigen::Vector3d along = (side[0] == 'u' ? sp.dv : sp.du).normalized();
        Eigen::Matrix3d f;
        f << sp.normal, along, sp.normal.cross(along);
        frames.push_back(f);
      }
      if (p.symmetry_normal && across < 2)
        b.fail(path + "/edges/" + std::to_string(e), "a symmetry edge needs a second row of control points");
    }
  }
  if (p.symmetry_normal) {
    // Each held point's partner: the neighbour one row inwards from its edge.
    pin.symmetry_normal = vec3(*p.symmetry_normal).normalized();
    pin.tied.clear();
    for (int k : pin.control_points) {
      const int i = k % nu, j = k / nu;
      int partner = -1;
      for (const std::string& side : *p.edges) {
        if (side == "u0" && i == 0) partner = 1 + nu * j;
        if (side == "u1" && i == nu - 1) partner = nu - 2 + nu * j;
        if (side == "v0" && j == 0) partner = i + nu;
        if (side == "v1" && j == nv - 1) partner = i + nu * (nv - 2);
        if (partner >= 0) break;
      }
      pin.tied.push_back(partner);
    }
    for (size_t k = 0; k < pin.control_points.size(); ++k) pin.held.push_back({pin.symmetry_normal});
  } else if (p.components) {
    for (size_t k = 0; k < pin.control_points.size(); ++k)
      pin.held.push_back(held_directions(p, frames.empty() ? Eigen::Matrix3d::Identity() : frames[k]));
  }
  if (p.motion) pin.motion = build_motion(*p.motion);
  return pin;
}

// Two pins on one control point agree only when neither moves it: a moving pin owns its points.
void check_pin_conflicts(const Builder& b, const std::vector<model::Pin>& pins, const std::vector<model::Shell>& shells) {
  for (size_t a = 0; a < pins.size(); ++a)
    for (size_t c = 0; c < a; ++c) {
      if (pins[a].shell != pins[c].shell) continue;
      const bool a_moves = b.scene.pins[a].motion.has_value(), c_moves = b.scene.pins[c].motion.has_value();
      if (!a_moves && !c_moves) continue;
      for (int k : pins[a].control_points)
        if (std::find(pins[c].control_points.begin(), pins[c].control_points.end(), k) != pins[c].control_points.end()) {
          const int nu = shells[pins[a].shell].surface.num_u();
          b.fail(pins[a].json_path, "control point [" + std::to_string(k % nu) + ", " + std::to_string(k / nu) +
                                        "] is also held by " + pins[c].json_path +
                                        " and one of them moves it: the pins' components conflict");
        }
    }
}

namespace {

// Whether a pin of the scene holds a control point of the interface's leader rows (exact closure would
// have to move it).
bool pins_hold_leader_rows(const Builder& b, const coupling::Interface& c, const std::vector<model::Shell>& shells) {
  std::vector<int> rows = c.leader_row1;
  rows.insert(rows.end(), c.leader_row2.begin(), c.leader_row2.end());
  for (size_t p = 0; p < b.scene.pins.size(); ++p) {
    const model::Pin pin = build_pin(b, b.scene.pins[p], p, shells);
    if (pin.shell != static_cast<size_t>(c.leader_patch)) continue;
    for (int k : pin.control_points)
      if (contains(rows, k)) return true;
  }
  return false;
}

}  // namespace

model::InterfaceSpec build_interface(const Builder& b, const Interface& i, size_t index,
                                     const std::vector<model::Shell>& shells) {
  const std::string path = index_path("/interfaces", index);
  const size_t a = shell_index(b, *i.a->shell, path + "/a/shell", shells);
  const size_t c = shell_index(b, *i.b->shell, path + "/b/shell", shells);
  if (a == c) b.fail(path + "/b", "an interface couples two different shells");
  coupling::InterfaceOptions options;
  // "none" declares a seam that is measured but never coupled; its operators (C0) are built only to
  // check the edges and to know which side leads.
  const std::string continuity = i.continuity.value_or("C1");
  options.continuity = continuity == "C1" ? coupling::Continuity::C1 : coupling::Continuity::C0;
  options.tolerance = i.tolerance.value_or(1e-8);
  // Exact closure is the default wherever it applies (docs/coupling.md, "Exact closure"); the thesis's
  // least-squares Eq. 4.29 when asked for, or when the edges' shared space cannot hold the leader's rows
  // (rational weights off the shared knots, a rest state off the space) or a pin holds one of them.
  const bool exact_by_default = !i.closure && continuity != "none";
  options.closure = i.closure == "exact" || exact_by_default ? coupling::Closure::Exact : coupling::Closure::LeastSquares;
  model::InterfaceSpec spec;
  if (i.verify) {
    spec.verify.max_gap = limit_of(i.verify->max_gap);
    spec.verify.max_angle_degrees = limit_of(i.verify->max_angle_degrees);
    spec.verify.max_stress_ratio = limit_of(i.verify->max_stress_ratio);
  }
  spec.coupled = continuity != "none";
  auto make = [&] {
    return coupling::make_interface(shells[a].surface, static_cast<int>(a), side_of(*i.a->side), shells[c].surface,
                                    static_cast<int>(c), side_of(*i.b->side), i.reversed.value_or(false), options);
  };
  try {
    try {
      spec.coupling = make();
    } catch (const std::invalid_argument&) {
      if (!exact_by_default) throw;
      options.closure = coupling::Closure::LeastSquares;  // the shared space does not apply: thesis Eq. 4.29
      spec.coupling = make();
    }
    if (exact_by_default && spec.coupling.exact && pins_hold_leader_rows(b, spec.coupling, shells)) {
      options.closure = coupling::Closure::LeastSquares;
      spec.coupling = make();
    }
  } catch (const std::invalid_argument& e) {
    b.fail(path, std::string("cannot couple these edges: ") + e.what());
  }
  spec.json_path = path;
  spec.momentum_correction = i.momentum_correction.value_or(true);
  spec.project_both_sides = i.seam_velocity == "projected";
  // Rows 0..5 counted from the coupled side: the coupled rows plus those whose quadratic stencils
  // share grid nodes with them.
  const coupling::Interface& ci = spec.coupling;
  spec.follower_neighbours = rows_near_side(shells[static_cast<size_t>(ci.follower_patch)].surface, ci.follower_side);
  spec.leader_neighbours = rows_near_side(shells[static_cast<size_t>(ci.leader_patch)].surface, ci.leader_side);
  return spec;
}

void check_exact_closures(const Builder& b, const model::Model& m) {
  for (const model::InterfaceSpec& spec : m.interfaces) {
    const coupling::Interface& c = spec.coupling;
    if (!c.exact) continue;
    std::vector<int> rows = c.leader_row1;
    rows.insert(rows.end(), c.leader_row2.begin(), c.leader_row2.end());
    for (const model::Pin& pin : m.pins)
      for (int k : pin.control_points)
        if (pin.shell == static_cast<size_t>(c.leader_patch) && contains(rows, k))
          b.fail(spec.json_path + "/closure", "exact closure moves the leader's seam rows, but the pin at " + pin.json_path +
                                                  " holds one of them (control point " + std::to_string(k) +
                                                  "); pin the other shell's side or use \"least_squares\"");
    // Leader rows that another seam sets (a patch that follows on one seam and leads on another) are held
    // in the projection and that seam is coupled first (sim::SeamSystem), so they need no refusal.
  }
}

}  // namespace shellfrac::scene::detail
