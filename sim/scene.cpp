#include "sim/scene.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include "crack2d/prescribed_cut.hpp"
#include "nurbs/knot_insertion.hpp"
#include "nurbs/nurbs_error.hpp"
#include "nurbs/patch_builders.hpp"
#include "render_mesh/exporter.hpp"
#include "sim/json_reader.hpp"
#include "sim/quality.hpp"
#include "sim/scene_parts.hpp"

namespace shellfrac::sim {

namespace {

constexpr double kPi = 3.14159265358979323846;
const Range kCells = Range::closed(1, 10000);

nurbs::Vec3 to_vec3(const std::vector<double>& v) { return {v[0], v[1], v[2]}; }

// Origin and in-plane axes of a built-in patch; axes are normalised and must be orthogonal.
nurbs::Frame read_frame(ObjectReader& r) {
  nurbs::Frame f;
  f.origin = to_vec3(r.numbers_or("origin", {0, 0, 0}));
  const nurbs::Vec3 u = to_vec3(r.numbers_or("axis_u", {1, 0, 0}));
  const nurbs::Vec3 v = to_vec3(r.numbers_or("axis_v", {0, 1, 0}));
  if (u.norm() < 1e-12) r.fail("axis_u", "axis must be a non-zero vector");
  if (v.norm() < 1e-12) r.fail("axis_v", "axis must be a non-zero vector");
  f.axis_u = u.normalized();
  f.axis_v = v.normalized();
  const double c = f.axis_u.dot(f.axis_v);
  if (std::abs(c) > 1e-9)
    r.fail("axis_v", "axis_v must be orthogonal to axis_u (their cosine is " + std::to_string(c) +
                         ")");
  return f;
}

double read_sweep(ObjectReader& r) {
  return r.number_or("sweep_degrees", 360.0, Range::left_open(0.0, 360.0)) * kPi / 180.0;
}

nurbs::KnotVector read_knots(ObjectReader& r, const std::string& key, int degree) {
  std::vector<double> k = r.number_list(key, 2);
  try {
    return nurbs::KnotVector(std::move(k), degree);
  } catch (const nurbs::NurbsError& e) {
    r.fail(key, e.what());
  }
}

nurbs::NurbsSurface read_control_net(ObjectReader& r) {
  const std::vector<int> degree = r.integers("degree", 2, Range::closed(1, 10));
  nurbs::KnotVector ku = read_knots(r, "knots_u", degree[0]);
  nurbs::KnotVector kv = read_knots(r, "knots_v", degree[1]);
  const size_t expected = static_cast<size_t>(ku.num_basis()) * static_cast<size_t>(kv.num_basis());

  const Json& pts = r.array("control_points");
  if (pts.size() != expected)
    r.fail("control_points", "control net has " + std::to_string(pts.size()) +
                                 " points but degree and knots require " +
                                 std::to_string(ku.num_basis()) + " x " +
                                 std::to_string(kv.num_basis()) + " = " + std::to_string(expected) +
                                 " (u runs fastest)");
  nurbs::Vec3List points;
  points.reserve(expected);
  for (size_t i = 0; i < pts.size(); ++i) {
    const std::string p = r.child_path("control_points") + "/" + std::to_string(i);
    const Json& c = pts[i];
    if (!c.is_array() || c.size() != 3)
      throw SceneError(r.file(), p, "expected a point [x, y, z]");
    nurbs::Vec3 x;
    for (int d = 0; d < 3; ++d) {
      if (!c[static_cast<size_t>(d)].is_number() ||
          !std::isfinite(c[static_cast<size_t>(d)].get<double>()))
        throw SceneError(r.file(), p + "/" + std::to_string(d), "expected a finite number");
      x[d] = c[static_cast<size_t>(d)].get<double>();
    }
    points.push_back(x);
  }

  std::vector<double> weights(expected, 1.0);
  if (r.has("weights")) {
    weights = r.number_list("weights", 0, Range::positive());
    if (weights.size() != expected)
      r.fail("weights", "expected one weight per control point (" + std::to_string(expected) +
                            "), got " + std::to_string(weights.size()));
  }
  const std::vector<int> refine = r.integers_or("refine", {1, 1}, Range::closed(1, 64));

  nurbs::NurbsSurface surface = [&] {
    try {
      return nurbs::NurbsSurface(std::move(ku), std::move(kv), std::move(points), std::move(weights));
    } catch (const nurbs::NurbsError& e) {
      r.fail_here(e.what());
    }
  }();
  if (refine[0] == 1 && refine[1] == 1) return surface;

  // Split every non-empty span into `refine` equal parts by knot insertion (geometry unchanged).
  auto splits = [](const nurbs::KnotVector& k, int parts) {
    std::vector<double> ins;
    for (int i = k.degree(); i < k.num_basis(); ++i) {
      const double a = k[i], b = k[i + 1];
      if (b <= a) continue;
      for (int s = 1; s < parts; ++s) ins.push_back(a + (b - a) * s / parts);
    }
    return ins;
  };
  return nurbs::insert_knots(surface, splits(surface.knots_u(), refine[0]),
                             splits(surface.knots_v(), refine[1]))
      .surface;
}

nurbs::NurbsSurface read_patch(ObjectReader& r, std::string& shape) {
  shape = r.choice("type", {"flat", "cylinder", "cone", "control_net"});
  try {
    if (shape == "flat") {
      const auto size = r.numbers("size", 2, Range::positive());
      const auto cells = r.integers("cells", 2, kCells);
      const nurbs::Frame frame = read_frame(r);
      return nurbs::flat_patch(size[0], size[1], cells[0], cells[1], frame);
    }
    if (shape == "cylinder") {
      const double radius = r.number("radius", Range::positive());
      const double height = r.number("height", Range::positive());
      const double sweep = read_sweep(r);
      const auto cells = r.integers("cells", 2, kCells);
      const nurbs::Frame frame = read_frame(r);
      return nurbs::cylinder_segment(radius, height, sweep, cells[0], cells[1], frame);
    }
    if (shape == "cone") {
      const double r0 = r.number("radius_bottom", Range::non_negative());
      const double r1 = r.number("radius_top", Range::non_negative());
      if (r0 == 0 && r1 == 0) r.fail("radius_top", "a cone needs at least one radius > 0");
      const double height = r.number("height", Range::positive());
      const double sweep = read_sweep(r);
      const auto cells = r.integers("cells", 2, kCells);
      const nurbs::Frame frame = read_frame(r);
      return nurbs::cone_segment(r0, r1, height, sweep, cells[0], cells[1], frame);
    }
    return read_control_net(r);
  } catch (const nurbs::NurbsError& e) {
    r.fail_here(e.what());
  }
}

std::vector<Eigen::Vector2d> read_points2(ObjectReader& r, const std::string& key, size_t min_count) {
  const Json& pts = r.array(key);
  if (pts.size() < min_count)
    r.fail(key, "expected at least " + std::to_string(min_count) + " points [u, v], got " + std::to_string(pts.size()));
  std::vector<Eigen::Vector2d> out;
  for (size_t i = 0; i < pts.size(); ++i) {
    const Json& c = pts[i];
    const std::string path = r.child_path(key) + "/" + std::to_string(i);
    if (!c.is_array() || c.size() != 2 || !c[0].is_number() || !c[1].is_number() ||
        !std::isfinite(c[0].get<double>()) || !std::isfinite(c[1].get<double>()))
      throw SceneError(r.file(), path, "expected a parameter point [u, v] of two finite numbers");
    out.emplace_back(c[0].get<double>(), c[1].get<double>());
  }
  return out;
}

FractureSpec read_fracture(ObjectReader& r) {
  FractureSpec f;
  f.enabled = true;
  f.failure_stress = r.number("failure_stress", Range::positive());
  f.fracture_energy = r.number("fracture_energy", Range::positive());
  f.rule = r.choice_or("damage_rule", "healing", {"healing", "monotone"}) == "monotone" ? shell::DamageRule::Monotone
                                                                                     : shell::DamageRule::Healing;
  if (r.has("regions")) {
    const Json& regions = r.array("regions");
    for (size_t i = 0; i < regions.size(); ++i) {
      ObjectReader reg(regions[i], r.child_path("regions") + "/" + std::to_string(i), r.file());
      FailureRegion fr;
      fr.polygon = read_points2(reg, "polygon", 3);
      fr.failure_stress = reg.number("failure_stress", Range::positive());
      if (reg.has("fracture_energy")) fr.fracture_energy = reg.number("fracture_energy", Range::positive());
      reg.finish();
      f.regions.push_back(std::move(fr));
    }
  }
  r.finish();
  return f;
}

Material read_material(ObjectReader r) {
  Material m;
  m.model = r.choice_or("model", "neo_hookean", {"neo_hookean"});
  m.youngs_modulus = r.number("E", Range::positive());
  m.poisson_ratio = r.number("nu", Range::open(-1.0, 0.5));
  m.density = r.number("density", Range::positive());
  if (r.has("shear_stiffness")) m.shear_stiffness = r.number("shear_stiffness", Range::non_negative());
  if (r.has("compression_stiffness")) m.compression_stiffness = r.number("compression_stiffness", Range::non_negative());
  m.shear_friction = r.number_or("shear_friction", 0.0, Range::non_negative());
  if (auto plastic = r.optional_object("plasticity")) {
    m.plasticity.enabled = true;
    m.plasticity.yield_stress = plastic->number("yield_stress", Range::positive());
    m.plasticity.hardening = plastic->number_or("hardening", 0.0, Range::non_negative());
    plastic->finish();
  }
  const std::string transverse = r.choice_or("transverse", "condensed", {"condensed", "rigid"});
  m.transverse = transverse == "rigid" ? shell::TransverseModel::Rigid : shell::TransverseModel::Condensed;
  const std::string model =
      r.choice_or("stress_model", "kirchhoff_love", {"kirchhoff_love", "plane_strain", "2d_f", "2d_f_director"});
  m.stress_model = model == "plane_strain"    ? shell::StressModel::PlaneStrain
                   : model == "2d_f"          ? shell::StressModel::MidSurface2D
                   : model == "2d_f_director" ? shell::StressModel::DirectorF2D
                                              : shell::StressModel::KirchhoffLove;
  if (m.stress_model != shell::StressModel::KirchhoffLove && m.plasticity.enabled)
    r.fail("stress_model", "plasticity needs \"stress_model\": \"kirchhoff_love\" (the comparison models are elastic)");
  if (auto frac = r.optional_object("fracture")) m.fracture = read_fracture(*frac);
  r.finish();
  return m;
}

Shell read_shell(ObjectReader r, size_t index) {
  std::string name = r.string_or("name", "shell" + std::to_string(index));
  std::string shape;
  ObjectReader patch = r.object("patch");
  nurbs::NurbsSurface surface = read_patch(patch, shape);
  patch.finish();
  const double thickness = r.number("thickness", Range::positive());
  Material material = read_material(r.object("material"));
  shell::QuadratureRule quadrature;
  if (auto q = r.optional_object("quadrature")) {
    quadrature.points_per_direction = q->integer_or("points", 4, Range::closed(1, 5));
    quadrature.layers = q->integer_or("layers", 3, Range::closed(1, 3));
    if (quadrature.layers == 2) q->fail("layers", "layers must be 1 (membrane only) or 3 (lower, mid, upper)");
    q->finish();
  }
  const auto v0 = r.numbers_or("initial_velocity", {0, 0, 0});
  std::vector<Cut> cuts;
  if (r.has("cuts")) {
    const crack2d::Box domain{{surface.knots_u().domain_begin(), surface.knots_v().domain_begin()},
                              {surface.knots_u().domain_end(), surface.knots_v().domain_end()}};
    const Json& list = r.array("cuts");
    for (size_t i = 0; i < list.size(); ++i) {
      ObjectReader c(list[i], r.child_path("cuts") + "/" + std::to_string(i), r.file());
      Cut cut;
      cut.closed = c.boolean_or("closed", false);
      cut.points = read_points2(c, "points", cut.closed ? 3 : 2);
      try {
        crack2d::validate_cut(cut.points, cut.closed, domain);
      } catch (const crack2d::CutError& e) {
        c.fail("points", std::string(e.what()) + " (parameter domain [" + std::to_string(domain.lo.x()) + ", " +
                             std::to_string(domain.hi.x()) + "] x [" + std::to_string(domain.lo.y()) + ", " +
                             std::to_string(domain.hi.y()) + "])");
      }
      c.finish();
      cuts.push_back(std::move(cut));
    }
  }
  r.finish();
  return Shell{std::move(name), std::move(shape), std::move(surface), thickness, std::move(material),
               quadrature, Eigen::Vector3d(v0[0], v0[1], v0[2]), std::move(cuts)};
}

CrackSettings read_cracks(ObjectReader r) {
  CrackSettings c;
  c.extraction_interval = r.integer_or("extraction_interval", c.extraction_interval, Range::closed(1, 1000000));
  c.phantom_nodes = r.boolean_or("phantom_nodes", c.phantom_nodes);
  c.contact_friction = r.number_or("contact_friction", c.contact_friction, Range::non_negative());
  c.max_support = r.number_or("max_support", c.max_support, Range::closed(1.5, 10.0));
  c.shadow_offset = r.number_or("shadow_offset", c.shadow_offset, Range::open(0.0, 0.01));
  r.finish();
  return c;
}

TimeSettings read_time(ObjectReader r) {
  TimeSettings t;
  t.end = r.number_or("end", t.end, Range::non_negative());
  t.frame_rate = r.number_or("frame_rate", t.frame_rate, Range::positive());
  if (r.has("dt")) t.dt = r.number("dt", Range::positive());
  t.cfl = r.number_or("cfl", t.cfl, Range::left_open(0.0, 1.0));
  t.allow_substepping = r.boolean_or("allow_substepping", t.allow_substepping);
  t.enforce_stability_bound = r.boolean_or("enforce_stability_bound", t.enforce_stability_bound);
  if (!t.enforce_stability_bound && !t.dt)
    r.fail("enforce_stability_bound", "turning the stability bound off needs an explicit \"dt\"");
  r.finish();
  return t;
}

OutputSettings read_output(ObjectReader r) {
  OutputSettings o;
  o.format = r.string_or("format", o.format);
  if (!render_mesh::is_export_format(o.format)) {
    std::string list;
    for (const auto& f : render_mesh::export_formats()) list += (list.empty() ? "" : ", ") + f.id;
    r.fail("format", "unknown mesh format \"" + o.format + "\": allowed are " + list);
  }
  const auto res = r.integers_or("resolution", {o.resolution_u, o.resolution_v}, Range::closed(1, 4096));
  o.resolution_u = res[0];
  o.resolution_v = res[1];
  r.finish();
  return o;
}

std::string stem_of(const std::string& path) {
  const size_t slash = path.find_last_of('/');
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  const size_t dot = base.find_last_of('.');
  return dot == std::string::npos || dot == 0 ? base : base.substr(0, dot);
}

// Line and column (1-based) of a byte offset, for JSON syntax errors.
std::string line_col(const std::string& text, size_t offset) {
  size_t line = 1, col = 1;
  for (size_t i = 0; i < offset && i < text.size(); ++i) {
    if (text[i] == '\n') {
      ++line;
      col = 1;
    } else {
      ++col;
    }
  }
  return "line " + std::to_string(line) + ", column " + std::to_string(col);
}

bool contains(const std::vector<int>& list, int k) { return std::find(list.begin(), list.end(), k) != list.end(); }

// Exact closure moves the leader's coupled rows, which a pin or another seam's follower rows also set.
void check_exact_closures(const Scene& scene, const std::string& file) {
  for (const InterfaceSpec& spec : scene.interfaces) {
    const coupling::Interface& c = spec.coupling;
    if (!c.exact) continue;
    std::vector<int> rows = c.leader_row1;
    rows.insert(rows.end(), c.leader_row2.begin(), c.leader_row2.end());
    for (const Pin& pin : scene.pins)
      for (int k : pin.control_points)
        if (pin.shell == static_cast<size_t>(c.leader_patch) && contains(rows, k))
          throw SceneError(file, spec.json_path + "/closure",
                           "exact closure moves the leader's seam rows, but the pin at " + pin.json_path +
                               " holds one of them (control point " + std::to_string(k) +
                               "); pin the other shell's side or use \"least_squares\"");
    for (const InterfaceSpec& other : scene.interfaces)
      if (&other != &spec && other.coupling.follower_patch == c.leader_patch)
        for (int k : rows)
          if (contains(other.coupling.follower_row1, k) || contains(other.coupling.follower_row2, k))
            throw SceneError(file, spec.json_path + "/closure",
                             "exact closure moves the leader's seam rows, but control point " + std::to_string(k) +
                                 " is also set by the seam at " + other.json_path + "; use \"least_squares\"");
  }
}

}  // namespace

Scene parse_scene(const std::string& json_text, const std::string& source) {
  Json j;
  try {
    j = Json::parse(json_text);
  } catch (const Json::parse_error& e) {
    // e.byte is one past the offending character.
    throw SceneError(source, "", "invalid JSON at " + line_col(json_text, e.byte ? e.byte - 1 : 0) +
                                     ": " + std::string(e.what()));
  }
  apply_quality(j, source);  // "quality" presets rewrite the document before it is read
  ObjectReader root(j, "", source);
  Scene scene;
  scene.source = source;
  scene.name = root.string_or("name", stem_of(source));
  if (auto t = root.optional_object("time")) scene.time = read_time(*t);
  if (auto o = root.optional_object("output")) scene.output = read_output(*o);
  if (root.has("shells")) {
    const Json& shells = root.array("shells");
    for (size_t i = 0; i < shells.size(); ++i)
      scene.shells.push_back(read_shell(ObjectReader(shells[i], "/shells/" + std::to_string(i), source), i));
  }
  const auto g = root.numbers_or("gravity", {0.0, -9.81, 0.0});
  scene.gravity = Eigen::Vector3d(g[0], g[1], g[2]);
  scene.damping = root.number_or("damping", 0.0, Range::non_negative());
  if (auto grid = root.optional_object("grid")) {
    if (grid->has("dx")) scene.grid.dx = grid->number("dx", Range::positive());
    scene.grid.apic = grid->choice_or("transfer", "pic", {"pic", "apic"}) == "apic";
    grid->finish();
  }
  if (auto c = root.optional_object("cracks")) scene.cracks = read_cracks(*c);
  scene.solids = read_solids(root);
  if (scene.shells.empty() && scene.solids.empty()) root.fail("shells", "a scene needs at least one shell or solid");
  scene.colliders = read_colliders(root);
  scene.pins = read_pins(root, scene.shells);
  for (InterfaceSpec& spec : read_interfaces(root, scene.shells))
    (spec.coupled ? scene.interfaces : scene.uncoupled_seams).push_back(std::move(spec));
  check_exact_closures(scene, source);
  root.finish();
  return scene;
}

Scene load_scene_file(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw SceneError(path, "", "cannot open the scene file (does it exist and is it readable?)");
  std::ostringstream ss;
  ss << in.rdbuf();
  return parse_scene(ss.str(), path);
}

Scene default_scene() { return parse_scene(default_scene_json(), "<built-in default>"); }

}  // namespace shellfrac::sim
