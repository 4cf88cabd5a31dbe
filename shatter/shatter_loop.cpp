#include "shatter/shatter_loop.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

#include "brittle/primitives.hpp"
#include "brittle/triangle_index.hpp"
#include "core/constants.hpp"
#include "core/error.hpp"
#include "mpm/level_set_shape.hpp"

namespace shellfrac::shatter {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
constexpr double kInf = std::numeric_limits<double>::infinity();

// The particles of `solid` whose rest positions lie inside `mesh`, with their volumes and strengths:
// a nearly whole fragment reuses its parent's sampling (thesis sec. 3.6.1).
std::shared_ptr<brittle::BrittleSolid> particles_inside(const brittle::BrittleSolid& solid, const brittle::TriMesh& mesh) {
  std::vector<brittle::Vec3> verts(mesh.positions.begin(), mesh.positions.end());
  std::vector<Eigen::Vector3i> tris(mesh.triangles.begin(), mesh.triangles.end());
  const mpm::LevelSetShape inside(verts, tris, 0.5 * solid.spacing);
  auto out = std::make_shared<brittle::BrittleSolid>();
  out->material = solid.material;
  out->spacing = solid.spacing;
  for (size_t p = 0; p < solid.size(); ++p) {
    if (!(inside.signed_distance(solid.rest[p]) < 0)) continue;
    out->add_particles({solid.rest[p]}, solid.particles.volume[p], brittle::Vec3::Zero());
    out->failure_stress.back() = solid.failure_stress[p];
    out->brittleness.back() = solid.brittleness[p];
  }
  return out;
}

double relative(const rigid::Vec3& a, const rigid::Vec3& b, double scale) {
  return scale > 0 ? (a - b).norm() / scale : (a - b).norm();
}

}  // namespace

ShatterLoop::ShatterLoop(const ShatterOptions& options)
    : options_(options), world_(rigid::RigidWorld::Options{options.gravity, options.solver_iterations}) {
  if (!(options.dt > 0)) throw core::InputError("shatter loop: the rigid step must be > 0");
  if (options.ground) {
    ground_ = options.ground;
    ground_id_ = world_.add_ground(ground_->point, ground_->normal, ground_->surface);
    piece_of_body_.push_back(-1);
  }
}

ShatterLoop::~ShatterLoop() = default;

int ShatterLoop::add_piece(Piece piece, const rigid::BodyDesc& body) {
  const int id = world_.add_body(body);
  if (piece_of_body_.size() <= static_cast<size_t>(id)) piece_of_body_.resize(static_cast<size_t>(id) + 1, -1);
  piece.body = id;
  piece.born = time_;
  piece_of_body_[static_cast<size_t>(id)] = static_cast<int>(pieces_.size());
  pieces_.push_back(std::move(piece));
  return id;
}

void ShatterLoop::add_breakable(const BreakableSpec& spec) {
  const std::string who = "breakable body \"" + spec.name + "\"";
  if (!(spec.impulse_threshold > 0)) throw core::InputError(who + ": impulse_threshold must be > 0");
  if (const std::string bad = spec.spawn.ratios.check(); !bad.empty()) throw core::InputError(who + ": " + bad);
  if (!spec.particles || spec.particles->size() == 0) throw core::InputError(who + ": no particles");
  brittle::require_closed_solid(spec.mesh, who);
  const brittle::MassProperties props = brittle::mass_properties(spec.mesh, spec.particles->material.density);
  roots_.push_back(spec);
  root_volume_.push_back(props.volume);
  const SpawnedFragment s = rigid_piece(spec.mesh, props, rigid::Pose{}, props.centroid, spec.velocity,
                                        spec.angular_velocity, props.volume, spec.spawn, spec.name);
  Piece p;
  p.name = spec.name;
  p.root = static_cast<int>(roots_.size()) - 1;
  p.fragment_class = FragmentClass::NearlyWhole;
  p.breakable = true;
  p.mesh = spec.mesh;
  p.properties = props;
  p.material_to_body = s.material_to_body;
  p.particles = spec.particles;
  add_piece(std::move(p), s.body);
}

void ShatterLoop::add_projectile(const ProjectileSpec& spec) {
  const std::string who = "projectile \"" + spec.name + "\"";
  if (!(spec.radius > 0)) throw core::InputError(who + ": radius must be > 0");
  if (!spec.kinematic && !(spec.density > 0)) throw core::InputError(who + ": density must be > 0");
  projectiles_.push_back(spec);
  rigid::BodyDesc b;
  b.name = spec.name;
  b.shape = rigid::Shape::Sphere;
  b.radius = spec.radius;
  b.mass = spec.density * 4.0 / 3.0 * core::kPi * std::pow(spec.radius, 3);
  b.inertia = rigid::Vec3::Constant(0.4 * b.mass * spec.radius * spec.radius);
  b.pose.translation = spec.centre;
  b.velocity = spec.velocity;
  b.angular_velocity = spec.angular_velocity;
  b.kinematic = spec.kinematic;
  b.surface = spec.surface;
  b.margin = std::min(1e-3, 0.1 * spec.radius);
  Piece p;
  p.name = spec.name;
  p.root = -1 - static_cast<int>(projectiles_.size() - 1);  // -1 - projectile index
  p.mesh = brittle::sphere_mesh(brittle::Vec3::Zero(), spec.radius, 32, 16);
  p.mesh.name = spec.name;
  p.properties = brittle::mass_properties(p.mesh, spec.density > 0 ? spec.density : 1.0);
  p.properties.centroid = rigid::Vec3::Zero();
  add_piece(std::move(p), b);
}

void ShatterLoop::add_static_mesh(const std::string& name, const brittle::TriMesh& mesh, const rigid::Surface& surface) {
  const int id = world_.add_static_mesh(name, mesh, surface);
  if (piece_of_body_.size() <= static_cast<size_t>(id)) piece_of_body_.resize(static_cast<size_t>(id) + 1, -1);
}

void ShatterLoop::add_prop(const PropSpec& prop) {
  int id = -1;
  if (!prop.mesh.triangles.empty()) {
    id = world_.add_static_mesh(prop.name, prop.mesh, prop.surface);
    prop_meshes_.push_back(prop.mesh);
  } else {
    if (!(prop.half_extents.minCoeff() > 0)) throw core::InputError("prop \"" + prop.name + "\": half_extents must be > 0");
    rigid::Pose pose;
    pose.translation = prop.centre;
    id = world_.add_static_box(prop.name, pose, prop.half_extents, prop.surface);
    prop_meshes_.push_back(brittle::box_mesh(prop.centre, prop.half_extents, 1));
  }
  prop_meshes_.back().name = prop.name;
  if (piece_of_body_.size() <= static_cast<size_t>(id)) piece_of_body_.resize(static_cast<size_t>(id) + 1, -1);
  static_material_[id] = prop.material;
}

rigid::Pose ShatterLoop::world_from_material(size_t piece) const {
  const Piece& p = pieces_[piece];
  return world_.state(p.body).pose * p.material_to_body;
}

brittle::TriMesh ShatterLoop::world_mesh(size_t piece) const {
  return rigid::transformed(pieces_[piece].mesh, world_from_material(piece));
}

RigidMoments ShatterLoop::moments(const std::vector<size_t>& pieces) const {
  std::vector<double> masses;
  std::vector<rigid::Vec3> inertia;
  std::vector<rigid::BodyState> states;
  for (size_t i : pieces) {
    const int id = pieces_[i].body;
    masses.push_back(world_.mass(id));
    inertia.push_back(world_.principal_inertia(id));
    states.push_back(world_.state(id));
  }
  return rigid_moments(masses, inertia, states);
}

brittle::HertzBody ShatterLoop::hertz_body(int body, const rigid::Vec3& point) const {
  const int piece = body >= 0 && static_cast<size_t>(body) < piece_of_body_.size() ? piece_of_body_[body] : -1;
  if (piece < 0) {  // ground, prop or static mesh: infinite radius and mass
    if (const auto it = static_material_.find(body); it != static_material_.end()) return it->second;
    return ground_ ? ground_->material : brittle::HertzBody{3e10, 0.2};
  }
  const Piece& p = pieces_[static_cast<size_t>(piece)];
  brittle::HertzBody h;
  const rigid::BodyState s = world_.state(body);
  if (p.root < 0) {
    const ProjectileSpec& pr = projectiles_[static_cast<size_t>(-1 - p.root)];
    h = pr.material;
    h.radius = pr.radius;
    h.mass = pr.kinematic ? kInf : world_.mass(body);
  } else {
    const brittle::BrittleMaterial& m = roots_[static_cast<size_t>(p.root)].particles->material;
    h.youngs_modulus = m.youngs_modulus;
    h.poisson_ratio = m.poisson_ratio;
    // thesis sec. 3.6.2: the equivalent radius is the distance from the contact to the centre of mass
    h.radius = std::max((point - s.pose.translation).norm(), 1e-9);
    h.mass = world_.mass(body);
  }
  return h;
}

void ShatterLoop::advance_to(double t) {
  while (time_ + 0.5 * options_.dt <= t) step();
}

void ShatterLoop::step() {
  const auto t0 = Clock::now();
  world_.step(options_.dt);
  time_ += options_.dt;
  ++totals_.rigid_steps;
  release_separated_siblings();
  totals_.seconds_rigid += seconds_since(t0);
  // Every collision's impacts of the last steps; a step without contact still ages its window.
  const size_t window = static_cast<size_t>(std::max(options_.impulse_window, 1));
  std::map<std::pair<int, int>, BodyImpact> now;
  for (const BodyImpact& i : gather_impacts(world_.contacts())) now[{i.body, i.partner}] = i;
  for (auto& [key, list] : recent_)
    if (!now.count(key)) list.push_back(BodyImpact{});
  for (const auto& [key, i] : now) recent_[key].push_back(i);
  std::map<size_t, BodyImpact> triggered;  // per piece, its strongest collision
  for (auto it = recent_.begin(); it != recent_.end();) {
    std::deque<BodyImpact>& list = it->second;
    while (list.size() > window) list.pop_front();
    const int body = it->first.first;
    const bool empty = std::none_of(list.begin(), list.end(), [](const BodyImpact& i) { return i.impulse > 0; });
    if (empty || !world_.has_body(body)) {
      it = recent_.erase(it);
      continue;
    }
    const int piece = static_cast<size_t>(body) < piece_of_body_.size() ? piece_of_body_[static_cast<size_t>(body)] : -1;
    // Judged once the collision has passed its peak (this step's impulse below the last one's), so that
    // the event carries the whole collision, not its first step.
    const bool peaked = list.size() >= 2 && list.back().impulse < list[list.size() - 2].impulse;
    if (piece >= 0 && pieces_[static_cast<size_t>(piece)].breakable && peaked) {
      const BreakableSpec& root = roots_[static_cast<size_t>(pieces_[static_cast<size_t>(piece)].root)];
      const BodyImpact total = merge_impacts({list.begin(), list.end()});
      if (total.impulse > root.impulse_threshold) {
        const auto [t, added] = triggered.try_emplace(static_cast<size_t>(piece), total);
        if (!added && total.impulse > t->second.impulse) t->second = total;
      }
    }
    ++it;
  }
  for (const auto& [piece, impact] : triggered) {
    // this body's collisions are spent, whatever the event made of them
    for (auto it = recent_.begin(); it != recent_.end();)
      it = it->first.first == impact.body ? recent_.erase(it) : std::next(it);
    fracture(piece, impact);
  }
}

void ShatterLoop::release_separated_siblings() {
  std::vector<std::pair<int, int>> kept;
  for (const auto& [a, b] : ignored_siblings_) {
    if (!world_.has_body(a) || !world_.has_body(b)) continue;
    if (world_.bounds_overlap(a, b)) kept.emplace_back(a, b);
    else world_.ignore_pair(a, b, false);
  }
  ignored_siblings_ = std::move(kept);
}

std::shared_ptr<const brittle::BrittleSolid> ShatterLoop::particles_for(const Piece& p) {
  if (p.particles) return p.particles;
  // a large fragment is resampled at its first fracture event, with its root's spacing and strength
  const BreakableSpec& root = roots_[static_cast<size_t>(p.root)];
  auto s = std::make_shared<brittle::BrittleSolid>(brittle::make_solid(
      p.mesh, root.particles->material, root.particles->spacing, root.sampling, root.seed, p.name));
  s->set_strength(root.strength_regions, root.weibull, root.solver.dx);
  return s;
}

brittle::Impact ShatterLoop::event_load(size_t index, const BodyImpact& impact, const brittle::BrittleSolid& solid,
                                        EventRecord& r) const {
  const Piece& p = pieces_[index];
  const rigid::Pose mat_from_world = world_from_material(index).inverse();
  // The contact lies on the decimated collision shape: move it onto the render surface.
  brittle::Vec3 point = mat_from_world.apply(impact.point);
  brittle::Vec3 lo, hi;
  brittle::bounding_box(p.mesh, lo, hi);
  const double reach = (hi - lo).norm();
  const brittle::TriangleIndex surface(p.mesh.positions, p.mesh.triangles, 2 * solid.spacing, reach);
  const brittle::TriangleIndex::Hit hit = surface.closest(point, reach);
  if (hit.found) point = hit.point;
  const double speed = std::max(impact.approach_speed, 1e-6);
  r.contact_time = brittle::hertz_contact_time(hertz_body(p.body, impact.point),
                                               hertz_body(impact.partner, impact.point), speed);  // Eq. 3.11
  brittle::Impact load;
  load.point = point;
  load.direction = mat_from_world.rotate(impact.direction);
  load.impulse = impact.impulse;
  load.duration = r.contact_time;
  load.radius = roots_[static_cast<size_t>(p.root)].impact_radius;
  load.normal_if_outward = true;
  return load;
}

bool ShatterLoop::run_event_mpm(const Piece& p, brittle::BrittleSolid& solid,
                                const std::vector<brittle::GhostParticle>& ghosts, EventRecord& r) {
  // thesis sec. 3.2: a short fracture run of the body at rest in object space
  const BreakableSpec& root = roots_[static_cast<size_t>(p.root)];
  const auto t_mpm = Clock::now();
  brittle::SolverOptions so = root.solver;
  so.gravity = brittle::Vec3::Zero();
  const double cap = root.contact_times * r.contact_time;
  so.stop.max_time = so.stop.max_time > 0 ? std::min(so.stop.max_time, cap) : cap;
  brittle::BrittleSolver solver(solid, so);
  solver.add_ghosts(ghosts);
  const size_t interval = static_cast<size_t>(std::max(root.crack_interval, 1));
  bool abandoned = false;
  while (!solver.should_stop() && !abandoned) {
    solver.step();
    if (so.two_fields && solver.steps() % interval == 0 && solver.damaged_count() > 0)
      solver.update_crack(root.event.crack);
    abandoned = observer_ && !observer_(EventProgress{p.name, solver.steps(), solver.time(), so.stop.max_time,
                                                      solver.damaged_count(), solid.size()});
  }
  r.mpm_steps = solver.steps();
  r.damaged_particles = solver.damaged_count();
  r.rubble_particles = solver.rubble_count();
  r.seconds_mpm = seconds_since(t_mpm);
  r.seconds_mpm_cracks = solver.times().cracks;
  totals_.mpm_steps += r.mpm_steps;
  totals_.seconds_mpm += r.seconds_mpm;
  return !abandoned;
}

brittle::FractureEvent ShatterLoop::cut_fragments(const Piece& p, const brittle::BrittleSolid& solid, EventRecord& r) {
  const BreakableSpec& root = roots_[static_cast<size_t>(p.root)];
  brittle::FractureEventOptions eo = root.event;
  if (!(eo.density > 0)) eo.density = solid.material.density;
  brittle::FractureEvent ev = brittle::fracture_event(solid, p.mesh, eo, p.name);
  // Damage that fills most of the body leaves no intact structure for the crack surface to run
  // between (docs/brittle.md, "Breakage order"): such a body came out whole although it is shattered.
  // Split it along the order in which it broke instead.
  if (ev.fragments.fragments.size() < 2 && !eo.breakage.enabled &&
      static_cast<double>(r.damaged_particles) >= root.breakage_order_above * static_cast<double>(r.particles)) {
    eo.breakage.enabled = true;
    const double extract = ev.seconds_extract, cut = ev.seconds_cut;
    ev = brittle::fracture_event(solid, p.mesh, eo, p.name);
    ev.seconds_extract += extract;
    ev.seconds_cut += cut;
    r.breakage_order = true;
  }
  r.seconds_extract = ev.seconds_extract;
  r.seconds_cut = ev.seconds_cut;
  totals_.seconds_extract += ev.seconds_extract;
  totals_.seconds_cut += ev.seconds_cut;
  r.fragments = ev.fragments.fragments.size();
  r.volume_change = ev.fragments.volume_change();
  return ev;
}

void ShatterLoop::spawn_fragments(size_t index, const brittle::FractureEvent& ev, EventRecord& r) {
  const auto t_spawn = Clock::now();
  const Piece& p = pieces_[index];
  const BreakableSpec& root = roots_[static_cast<size_t>(p.root)];
  const rigid::Pose world_from_mat = world_from_material(index);
  const int parent_body = p.body;
  const RigidMoments before = moments({index});
  const rigid::BodyState parent = r.parent;
  const std::shared_ptr<const brittle::BrittleSolid> parent_particles = p.particles;
  const int generation = p.generation + 1, root_index = p.root;
  world_.remove_body(parent_body);
  piece_of_body_[static_cast<size_t>(parent_body)] = -1;
  pieces_[index].body = -1;
  pieces_[index].died = time_;
  std::vector<size_t> children;
  for (const brittle::Fragment& f : ev.fragments.fragments) {
    const SpawnedFragment s =
        rigid_piece(f.mesh, f.properties, world_from_mat, parent.pose.translation, parent.velocity,
                    parent.angular_velocity, root_volume_[static_cast<size_t>(root_index)], root.spawn, f.mesh.name);
    Piece c;
    c.name = f.mesh.name;
    c.root = root_index;
    c.generation = generation;
    c.fragment_class = s.fragment_class;
    c.breakable = breakable(s.fragment_class);
    c.mesh = f.mesh;
    c.properties = f.properties;
    c.material_to_body = s.material_to_body;
    if (s.fragment_class == FragmentClass::NearlyWhole) c.particles = particles_inside(*parent_particles, f.mesh);
    ++r.by_class[static_cast<int>(s.fragment_class)];
    children.push_back(pieces_.size());
    add_piece(std::move(c), s.body);
  }
  for (size_t i = 0; i < children.size(); ++i)
    for (size_t j = i + 1; j < children.size(); ++j) {
      const int a = pieces_[children[i]].body, b = pieces_[children[j]].body;
      world_.ignore_pair(a, b, true);
      ignored_siblings_.emplace_back(a, b);
    }
  const RigidMoments after = moments(children);
  // Scales for the relative errors that stay meaningful when the parent does not spin or move:
  // sqrt(2 M E) is the momentum of the parent's kinetic energy, times its size for angular momentum.
  const double p_scale = std::max(before.momentum.norm(), std::sqrt(2 * before.mass * before.kinetic_energy));
  const double l_scale = std::max(before.angular_momentum.norm(), p_scale * std::cbrt(ev.fragments.input_volume));
  r.mass_error = std::abs(after.mass - before.mass) / before.mass;
  r.momentum_error = relative(after.momentum, before.momentum, p_scale);
  r.angular_momentum_error = relative(after.angular_momentum, before.angular_momentum, l_scale);
  r.energy_ratio = before.kinetic_energy > 0 ? after.kinetic_energy / before.kinetic_energy : 1.0;
  r.seconds_spawn = seconds_since(t_spawn);
  totals_.seconds_spawn += r.seconds_spawn;
}

void ShatterLoop::fracture(size_t index, const BodyImpact& impact) {
  EventRecord r;
  r.time = time_;
  r.body = pieces_[index].name;
  r.generation = pieces_[index].generation;
  r.partner = world_.has_body(impact.partner) ? world_.name(impact.partner) : "";
  r.impulse = impact.impulse;
  r.point = impact.point;
  r.approach_speed = impact.approach_speed;
  ++totals_.events;
  try {
    pieces_[index].particles = particles_for(pieces_[index]);
    const Piece& p = pieces_[index];
    brittle::BrittleSolid solid = *p.particles;
    for (brittle::Vec3& v : solid.particles.v) v.setZero();  // sec. 3.2: the body at rest in object space
    r.particles = solid.size();
    r.parent = world_.state(p.body);
    const std::vector<brittle::GhostParticle> ghosts =
        brittle::impact_ghosts(event_load(index, impact, solid, r), p.mesh, solid, p.name);
    if (!run_event_mpm(p, solid, ghosts, r)) {
      r.outcome = "interrupted";
    } else {
      const brittle::FractureEvent ev = cut_fragments(p, solid, r);
      if (r.fragments < 2) {
        r.outcome = "intact";
      } else {
        spawn_fragments(index, ev, r);
        r.outcome = "broken";
        ++totals_.broken;
      }
    }
  } catch (const core::Error& e) {
    // thesis loop goes on: the body keeps flying unbroken and the shot is not lost
    r.outcome = "failed";
    r.message = e.what();
    ++totals_.failed;
  }
  events_.push_back(r);
}

}  // namespace shellfrac::shatter
