// Brittle solids of a scene (solids with a "fracture" object, docs/brittle.md): the closed mesh of the
// object, its particles with their strength, the impacts as ghost particles and the settings of the
// fracture run. Everything the run could refuse later (an open mesh, an impact off the object, a crack
// grid or voxel too fine for memory) is refused here, before any output, with the JSON path.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "brittle/crack_grid.hpp"
#include "brittle/mesh_repair.hpp"
#include "brittle/primitives.hpp"
#include "brittle/solid_grid.hpp"
#include "core/format.hpp"
#include "scene/build_context.hpp"
#include "scene/mesh_import.hpp"

namespace shellfrac::scene::detail {

namespace {

using brittle::TriMesh;
using BVec3 = Eigen::Vector3d;

// Memory the run may take for one grid or level-set set (the brittle library's own limits).
constexpr double kCrackGridLimit = double(size_t{2} << 30);
constexpr double kSolverGridLimit = double(size_t{4} << 30);

// OBJ with its texture coordinates: a vertex per (position, uv) corner, polygons fanned.
TriMesh read_obj(const std::filesystem::path& file, double scale, const BVec3& translate) {
  std::ifstream in(file);
  if (!in) throw std::runtime_error("cannot open the mesh file");
  std::vector<BVec3> v;
  std::vector<Eigen::Vector2d> vt;
  TriMesh m;
  std::map<std::pair<long, long>, int> corner;
  std::string line;
  while (std::getline(in, line)) {
    std::istringstream s(line);
    std::string tag;
    s >> tag;
    if (tag == "v" || tag == "vt") {  // strtod, so that "nan" reaches the closed-solid check as NaN
      std::string word;
      std::vector<double> c;
      while (c.size() < 3 && s >> word) c.push_back(std::strtod(word.c_str(), nullptr));
      if (c.size() < (tag == "v" ? 3u : 2u)) throw std::runtime_error("a vertex needs its coordinates: " + line);
      if (tag == "v") v.push_back(scale * BVec3(c[0], c[1], c[2]) + translate);
      else vt.emplace_back(c[0], c[1]);
    } else if (tag == "f") {
      std::vector<int> ids;
      std::string c;
      while (s >> c) {
        long pi = std::stol(c.substr(0, c.find('/')));
        pi = pi < 0 ? static_cast<long>(v.size()) + pi : pi - 1;
        long ti = -1;
        const size_t slash = c.find('/');
        if (slash != std::string::npos && slash + 1 < c.size() && c[slash + 1] != '/') {
          ti = std::stol(c.substr(slash + 1));
          ti = ti < 0 ? static_cast<long>(vt.size()) + ti : ti - 1;
        }
        if (pi < 0 || pi >= static_cast<long>(v.size()) || ti >= static_cast<long>(vt.size()))
          throw std::runtime_error("face refers to a vertex that does not exist: " + line);
        auto it = corner.find({pi, ti});
        if (it == corner.end()) {
          it = corner.emplace(std::make_pair(pi, ti), static_cast<int>(m.positions.size())).first;
          m.positions.push_back(v[static_cast<size_t>(pi)]);
          m.uvs.push_back(ti >= 0 ? vt[static_cast<size_t>(ti)] : Eigen::Vector2d::Zero());
        }
        ids.push_back(it->second);
      }
      for (size_t k = 1; k + 1 < ids.size(); ++k) m.triangles.emplace_back(ids[0], ids[k], ids[k + 1]);
    }
  }
  if (m.triangles.empty()) throw std::runtime_error("the file holds no faces");
  return m;
}

std::filesystem::path mesh_path(const Builder& b, const MeshFile& mf) {
  std::filesystem::path file(*mf.file);
  if (file.is_relative()) file = std::filesystem::path(b.scene.source).parent_path() / file;
  return file;
}

// The triangles of a mesh file, scaled and translated (OBJ keeps its UVs; other formats through assimp);
// a file that cannot be read fails at path + "/file".
TriMesh read_mesh_file(const Builder& b, const MeshFile& mf, const std::string& path) {
  const std::filesystem::path file = mesh_path(b, mf);
  const double scale = mf.scale.value_or(1.0);
  const BVec3 translate = vec3_or(mf.translate, {0, 0, 0});
  TriMesh m;
  try {
    if (file.extension() == ".obj" || file.extension() == ".OBJ") {
      m = read_obj(file, scale, translate);
    } else {
      const TriangleMesh t = import_mesh(file.string(), scale, translate);
      m.positions = t.vertices;
      for (const Eigen::Vector3i& f : t.triangles) m.triangles.emplace_back(f[0], f[1], f[2]);
    }
  } catch (const std::exception& e) {
    b.fail(path + "/file", file.string() + ": " + e.what());
  }
  return m;
}

// The object's surface: a primitive or a mesh file (OBJ keeps its UVs; other formats through assimp).
// `repaired` says what "repair" changed, when it did.
TriMesh solid_mesh(const Builder& b, const Solid& s, const std::string& path, std::string& repaired) {
  const BVec3 c = vec3_or(s.center, {0, 0, 0});
  TriMesh m;
  if (*s.shape == "box") {
    m = brittle::box_mesh(c, vec3(*s.half_extents), 2);
  } else if (*s.shape == "sphere") {
    m = brittle::sphere_mesh(c, *s.radius, 48, 24);
  } else if (*s.shape == "cylinder") {
    m = brittle::cylinder_mesh(c, *s.radius, *s.height, 48);
  } else if (*s.shape == "torus") {
    m = brittle::torus_mesh(c, *s.major_radius, *s.minor_radius, 48, 24);
  } else {
    const std::filesystem::path file = mesh_path(b, s.mesh);
    m = read_mesh_file(b, s.mesh, path);
    // Refused here, with the file and its counts (holes, non-manifold edges and vertices, flipped
    // triangles), rather than by the exact cutter after the whole simulation. A mesh that passes is
    // used as it is (with its UVs), even with "repair".
    m.name = s.name.value_or(*s.shape);
    try {
      brittle::require_closed_solid(m, file.string());
    } catch (const core::InputError& e) {
      if (!s.mesh.repair.value_or(false)) {
        // The hint only where orientation is all that is wrong: repair fills no holes and cannot pull
        // touching parts apart.
        const brittle::MeshReport r = brittle::inspect_mesh(m);
        const bool turnable = r.closed() && r.non_manifold_vertices == 0 && (r.inconsistent_edges > 0 || r.volume < 0);
        b.fail(path + "/file", std::string(e.what()) + (turnable ? "; \"repair\": true can orient it" : ""));
      }
      try {
        brittle::MeshRepair changes;
        m = brittle::repair_closed_solid(m, file.string(), changes);
        repaired = file.string() + ": mesh repaired (" + path + "/repair): " + changes.describe();
      } catch (const core::InputError& after) {
        b.fail(path + "/file", after.what());
      }
    }
    brittle::compute_vertex_normals(m);
  }
  m.name = s.name.value_or(*s.shape);
  return m;
}

brittle::StrengthRegion region_of(const SolidRegion& r) {
  brittle::StrengthRegion out;
  out.shape = r.shape == "sphere" ? brittle::StrengthRegion::Shape::Sphere : brittle::StrengthRegion::Shape::Box;
  out.centre = vec3(*r.center);
  if (r.half_extents) out.half_extents = vec3(*r.half_extents);
  out.radius = r.radius.value_or(0.0);
  out.failure_stress = r.failure_stress.value_or(0.0);
  return out;
}

std::string gigabytes(double bytes) { return core::format_number(bytes / 1e9, 3) + " GB"; }

// Refuses a grid spacing whose grid over the object's box would not fit in `limit` bytes.
void check_grid_memory(const Builder& b, const std::string& key, const std::string& what, double bytes, double limit,
                       double spacing) {
  if (bytes <= limit) return;
  b.fail(key, what + " spacing " + core::format_number(spacing, 4) + " m is too small for memory: it would need about " +
                  gigabytes(bytes) + " (limit " + gigabytes(limit) + "); use at least " +
                  core::format_number(spacing * std::cbrt(bytes / limit), 4) + " m");
}

}  // namespace

namespace {

// Refuses grids and level sets that would not fit in memory, before anything is allocated.
void check_event_memory(const Builder& b, const std::string& path, const SolidFracture& fr, const brittle::TriMesh& mesh,
                        const BVec3& lo, const BVec3& hi, double dx, double h_v) {
  double solver_nodes = 1;
  for (int a = 0; a < 3; ++a) solver_nodes *= std::floor((hi[a] - lo[a]) / dx) + 4;
  const double node_bytes =
      fr.two_fields.value_or(true) ? 2.0 * sizeof(brittle::GridNode) + sizeof(brittle::GVec3) : sizeof(brittle::GridNode);
  check_grid_memory(b, path + "/fracture/grid_spacing", "MPM grid", solver_nodes * node_bytes, kSolverGridLimit, dx);
  check_grid_memory(b, path + "/fracture/crack_grid_spacing", "crack grid (h_v)",
                    brittle::CrackGrid::memory_estimate(lo, hi, h_v), kCrackGridLimit, h_v);
  if (fr.cutter == "level_set" || fr.gap_width.value_or(0.0) > 0) {
    const double voxel = fr.voxel.value_or(0.0);
    const double v = voxel > 0 ? voxel : (hi - lo).norm() / 200.0;
    const double bytes = brittle::level_set_cut_bytes(v, 3.0 * brittle::surface_area(mesh));
    if (bytes > kCrackGridLimit)
      b.fail(path + "/fracture/voxel", "voxel " + core::format_number(v, 4) + " m is too small for memory: the level sets would need about " +
                                           gigabytes(bytes) + " (limit " + gigabytes(kCrackGridLimit) + "); use at least " +
                                           core::format_number(v * std::sqrt(bytes / kCrackGridLimit), 4) + " m");
  }
}

brittle::BrittleMaterial brittle_material(const SolidMaterial& sm) {
  brittle::BrittleMaterial mat;
  mat.youngs_modulus = *sm.youngs_modulus;
  mat.poisson_ratio = *sm.poisson_ratio;
  mat.density = *sm.density;
  mat.model = sm.damage_model == "phase_field" ? brittle::DamageModel::PhaseField
              : sm.damage_model == "nacc"      ? brittle::DamageModel::Nacc
                                               : brittle::DamageModel::Rankine;
  mat.failure_stress = sm.failure_stress.value_or(0.0);    // the phase field and NACC have none
  mat.fracture_energy = sm.fracture_energy.value_or(0.0);  // NACC has none
  if (sm.nacc) {
    const NaccMaterial& nm = *sm.nacc;
    brittle::NaccParams& np = mat.nacc;
    np.alpha0 = nm.alpha0.value_or(np.alpha0);
    np.beta = nm.beta.value_or(np.beta);
    np.xi = nm.xi.value_or(np.xi);
    np.friction = nm.friction.value_or(np.friction);
    np.hardening = nm.hardening.value_or(np.hardening);
  }
  mat.rule = sm.damage_rule == "monotone" ? brittle::DamageRule::Monotone : brittle::DamageRule::Healing;
  mat.characteristic_length = sm.characteristic_length.value_or(0.0);
  mat.residual_stiffness = sm.residual_stiffness.value_or(0.0);
  const std::string fully_damaged = sm.fully_damaged.value_or("tensionless");
  if (fully_damaged == "bounded") mat.broken_stretch_limit = 3.0;
  mat.retire_rubble = fully_damaged == "rubble";
  return mat;
}

brittle::Sampling sampling_of(const Solid& s) {
  return s.sampling == "regular"        ? brittle::Sampling::Regular
         : s.sampling == "poisson_disk" ? brittle::Sampling::PoissonDisk
                                        : brittle::Sampling::Jittered;
}

// Particles sampled in the mesh, minus the removed regions; their volumes share the mesh volume.
void add_sampled_particles(const Builder& b, const Solid& s, const std::string& path, const brittle::TriMesh& mesh,
                           brittle::BrittleSolid& solid) {
  try {
    const std::vector<BVec3> points = brittle::sample_mesh(mesh, solid.spacing, sampling_of(s),
                                                           static_cast<unsigned>(s.seed.value_or(1)), b.scene.source + ": " + path);
    const double particle_volume = brittle::mass_properties(mesh, 1.0).volume / static_cast<double>(points.size());
    std::vector<brittle::StrengthRegion> removed;
    for (const SolidRegion& r : s.remove) removed.push_back(region_of(r));
    std::vector<BVec3> kept;
    for (const BVec3& p : points) {
      bool gone = false;
      for (const brittle::StrengthRegion& r : removed) gone = gone || r.contains(p);
      if (!gone) kept.push_back(p);
    }
    if (kept.empty()) b.fail(path + "/remove", "the removed regions take every particle");
    solid.add_particles(kept, particle_volume, vec3_or(s.initial_velocity, {0, 0, 0}));
  } catch (const SceneError&) {
    throw;
  } catch (const core::InputError& e) {
    b.fail(path + "/spacing", e.what());
  }
}

// The ghost particles of the solid's impacts; the Hertz duration needs the sampled solid (its mass and
// centre of mass).
std::vector<brittle::GhostParticle> impact_ghosts(const Builder& b, const Solid& s, const std::string& path,
                                                  const model::BrittleBody& body, const brittle::BrittleSolid& solid) {
  std::vector<brittle::GhostParticle> out;
  for (size_t k = 0; k < s.impacts.size(); ++k) {
    const ImpactSpec& im = s.impacts[k];
    brittle::Impact impact;
    impact.point = vec3(*im.point);
    impact.direction = vec3(*im.direction);
    impact.impulse = *im.impulse;
    impact.start_time = im.start_time.value_or(0.0);
    impact.radius = im.radius.value_or(0.0);
    try {
      if (im.hertz) {
        const HertzSpec& h = *im.hertz;
        impact.duration = brittle::impact_duration(brittle::HertzBody{*h.youngs_modulus, *h.poisson_ratio, *h.radius, *h.mass},
                                                   solid, impact.point, *h.speed);
      } else {
        impact.duration = *im.duration;
      }
      const std::vector<brittle::GhostParticle> ghosts = brittle::impact_ghosts(impact, body.mesh, solid, body.name);
      out.insert(out.end(), ghosts.begin(), ghosts.end());
    } catch (const core::InputError& e) {
      b.fail(index_path(path + "/impacts", k), e.what());
    }
  }
  return out;
}

brittle::SolverOptions solver_options(const Builder& b, const Solid& s, const brittle::BrittleMaterial& mat, double dx) {
  const SolidFracture& fr = *s.fracture;
  brittle::SolverOptions o;
  o.dx = dx;
  o.cfl = fr.cfl.value_or(0.3);
  o.gravity = vec3_or(b.scene.gravity, {0.0, -9.81, 0.0});
  o.two_fields = fr.two_fields.value_or(true);
  o.field_contact = fr.field_contact.value_or(true);
  if (fr.stop) {
    o.stop.damaged_fraction = fr.stop->damaged_fraction.value_or(0.0);
    o.stop.max_steps = static_cast<size_t>(fr.stop->max_steps.value_or(0));
    o.stop.max_time = fr.stop->max_time.value_or(0.0);
  }
  if (mat.model == brittle::DamageModel::PhaseField) {
    brittle::PhaseFieldOptions& pf = o.phase_field;
    const PhaseFieldMaterial& pm = *s.material->phase_field;
    pf.length_scale = pm.length_scale.value_or(0.0);
    pf.mobility = *pm.mobility;
    pf.residual = pm.residual.value_or(pf.residual);
    pf.broken_below = pm.broken_below.value_or(pf.broken_below);
    if (fr.phase_field) {
      const PhaseFieldSolve& ps = *fr.phase_field;
      pf.solver = ps.solver == "cholmod" ? brittle::PhaseFieldSolver::Cholmod : brittle::PhaseFieldSolver::ConjugateGradient;
      pf.gradient = ps.gradient == "mls" ? brittle::PhaseFieldGradient::Mls : brittle::PhaseFieldGradient::Spline;
      pf.interval = static_cast<size_t>(ps.interval.value_or(1));
      pf.tolerance = ps.tolerance.value_or(pf.tolerance);
      pf.max_iterations = static_cast<size_t>(ps.max_iterations.value_or(static_cast<int>(pf.max_iterations)));
    }
  }
  return o;
}

// Crack extraction, cutting, breakage order and fracture detail (thesis Table 3.2).
brittle::FractureEventOptions event_options(const SolidFracture& fr, double h_v) {
  brittle::FractureEventOptions e;
  e.crack.grid.spacing = h_v;
  e.fragments.cutter = fr.cutter == "level_set" ? brittle::Cutter::LevelSet : brittle::Cutter::Exact;
  e.fragments.voxel = fr.voxel.value_or(0.0);
  e.gap_width = fr.gap_width.value_or(0.0);
  if (fr.breakage_order) {
    e.breakage.enabled = true;
    e.breakage.dynamics = fr.breakage_order->dynamics.value_or(0.1);
    e.breakage.min_share = fr.breakage_order->min_share.value_or(0.01);
    e.breakage.smoothing.passes = fr.breakage_order->smoothing_steps.value_or(e.breakage.smoothing.passes);
  }
  if (fr.detail) {
    // Table 3.2's lengths default to fractions of the crack grid: faces refined to h_v / 4, lines stepping
    // one refined edge and marking h_v across (Table 3.3's s = 5 d), the heights smoothed over h_v / 2.
    brittle::FractureDetailOptions& d = e.detail;
    d.height = *fr.detail->height;
    d.edge = fr.detail->edge.value_or(0.25 * h_v);
    d.step = fr.detail->step.value_or(d.edge);
    d.radius = fr.detail->radius.value_or(4.0 * d.edge);
    d.grid = fr.detail->grid.value_or(0.5 * h_v);
    d.max_steps = fr.detail->max_steps.value_or(d.max_steps);
    d.enhanced = fr.detail->enhanced.value_or(d.enhanced);
  }
  return e;
}

model::BrittleBody::Rigid rigid_settings(const Solid& s, const std::vector<brittle::StrengthRegion>& regions,
                                         const brittle::WeibullStrength& weibull) {
  const RigidBodySpec& r = *s.rigid_body;
  model::BrittleBody::Rigid rb;
  rb.impulse_threshold = *r.impulse_threshold;
  rb.angular_velocity = vec3_or(r.angular_velocity, {0, 0, 0});
  rb.velocity = vec3_or(s.initial_velocity, {0, 0, 0});
  rb.collision_faces = static_cast<size_t>(r.collision_faces.value_or(10000));
  rb.surface = rigid::Surface{r.friction.value_or(0.5), r.restitution.value_or(0.2)};
  rb.impact_radius = r.impact_radius.value_or(0.0);
  rb.contact_times = r.contact_times.value_or(3.0);
  rb.strength_regions = regions;
  rb.weibull = weibull;
  rb.sampling = sampling_of(s);
  rb.seed = static_cast<unsigned>(s.seed.value_or(1));
  return rb;
}

}  // namespace

model::BrittleBody build_brittle_solid(const Builder& b, const Solid& s, size_t index) {
  const std::string path = index_path("/solids", index);
  const SolidFracture& fr = *s.fracture;
  model::BrittleBody out;
  out.name = s.name.value_or(*s.shape + std::to_string(index));
  out.json_path = path;
  out.mesh = solid_mesh(b, s, path, out.mesh_repair);
  out.mesh.name = out.name;
  BVec3 lo, hi;
  brittle::bounding_box(out.mesh, lo, hi);
  if ((hi - lo).minCoeff() < *s.spacing) b.fail(path + "/spacing", "spacing is larger than the solid: no particle would fit");
  const double dx = fr.grid_spacing.value_or(2.0 * *s.spacing);
  const double h_v = fr.crack_grid_spacing.value_or(dx);
  check_event_memory(b, path, fr, out.mesh, lo, hi, dx, h_v);

  auto solid = std::make_shared<brittle::BrittleSolid>();
  solid->material = brittle_material(*s.material);
  solid->spacing = *s.spacing;
  add_sampled_particles(b, s, path, out.mesh, *solid);

  // Strength: regions, then the Weibull draw; H per particle (refused where sigma_f^2 l / (2 E G_f) >= 1).
  std::vector<brittle::StrengthRegion> regions;
  brittle::WeibullStrength weibull;
  if (s.strength) {
    for (const SolidRegion& r : s.strength->regions) regions.push_back(region_of(r));
    weibull = weibull_of(s.strength->weibull);
  }
  try {
    solid->set_strength(regions, weibull, dx);
  } catch (const core::InputError& e) {
    b.fail(path + "/material/fracture_energy", e.what());
  }
  out.ghosts = impact_ghosts(b, s, path, out, *solid);
  out.solver = solver_options(b, s, solid->material, dx);
  out.solid = std::move(solid);
  out.crack_interval = fr.crack_interval.value_or(20);
  out.event = event_options(fr, h_v);
  // Counting rule (docs/brittle.md): a piece smaller than one MPM cell, dx^3, cannot have been resolved
  // by the simulation; it is a sliver, kept in the mesh but not counted as a fragment.
  out.sliver_volume = fr.sliver_volume.value_or(dx * dx * dx);
  if (s.rigid_body) out.rigid = rigid_settings(s, regions, weibull);
  return out;
}

model::RigidWorldSettings build_rigid_world(const Builder& b, const Opt<RigidWorldSpec>& spec) {
  model::RigidWorldSettings w;
  const BVec3 gravity = vec3_or(b.scene.gravity, {0.0, -9.81, 0.0});
  w.options.gravity = gravity;
  const RigidWorldSpec r = spec.value_or(RigidWorldSpec{});
  w.options.dt = r.dt.value_or(1e-3);
  w.options.solver_iterations = r.solver_iterations.value_or(20);
  if (r.volume_ratios) w.ratios = shatter::VolumeRatios{(*r.volume_ratios)[0], (*r.volume_ratios)[1], (*r.volume_ratios)[2]};
  // The ground: the scene's, or a plane through the origin facing up against gravity.
  const RigidGround g = r.ground.value_or(RigidGround{});
  shatter::GroundSpec ground;
  ground.point = vec3_or(g.point, {0, 0, 0});
  const BVec3 up = gravity.norm() > 0 ? BVec3(-gravity.normalized()) : BVec3(0, 1, 0);
  ground.normal = g.normal ? vec3(*g.normal).normalized() : up;
  ground.surface = rigid::Surface{g.friction.value_or(0.5), g.restitution.value_or(0.2)};
  ground.material = brittle::HertzBody{g.youngs_modulus.value_or(3e10), g.poisson_ratio.value_or(0.2)};
  w.options.ground = ground;
  for (size_t i = 0; i < r.projectiles.size(); ++i) {
    const Projectile& p = r.projectiles[i];
    shatter::ProjectileSpec ps;
    ps.name = p.name.value_or("projectile" + std::to_string(i));
    ps.radius = *p.radius;
    ps.density = *p.density;
    ps.material = brittle::HertzBody{*p.youngs_modulus, *p.poisson_ratio};
    ps.centre = vec3(*p.center);
    ps.velocity = vec3_or(p.velocity, {0, 0, 0});
    ps.angular_velocity = vec3_or(p.angular_velocity, {0, 0, 0});
    ps.kinematic = p.kinematic.value_or(false);
    ps.surface = rigid::Surface{p.friction.value_or(0.5), p.restitution.value_or(0.5)};
    w.projectiles.push_back(ps);
  }
  for (size_t i = 0; i < r.props.size(); ++i) {
    const RigidProp& p = r.props[i];
    shatter::PropSpec prop;
    prop.name = p.name.value_or("prop" + std::to_string(i));
    if (p.shape == "mesh") {
      // Any surface will do for a static Bullet mesh, open or closed; only its numbers must be finite.
      const std::string path = "/rigid/props/" + std::to_string(i);
      prop.mesh = read_mesh_file(b, p.mesh, path);
      if (brittle::inspect_mesh(prop.mesh).non_finite > 0)
        b.fail(path + "/file", mesh_path(b, p.mesh).string() + ": the mesh has NaN or infinite coordinates");
      prop.mesh.name = prop.name;
    } else {
      prop.centre = vec3(*p.center);
      prop.half_extents = vec3(*p.half_extents);
    }
    prop.surface = rigid::Surface{p.friction.value_or(0.5), p.restitution.value_or(0.2)};
    prop.material = brittle::HertzBody{p.youngs_modulus.value_or(3e10), p.poisson_ratio.value_or(0.2)};
    w.props.push_back(prop);
  }
  return w;
}

}  // namespace shellfrac::scene::detail
