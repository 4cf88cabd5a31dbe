#pragma once
// The shatter loop (thesis secs. 3.2 and 3.6, Table 3.3): a rigid-body world carries breakable objects
// and their fragments. After every rigid step, a breakable body whose contacts delivered more than its
// impulse threshold RB_imp starts a fracture event: the impact becomes ghost-particle tractions (Eq. 3.12)
// over the Hertz contact time (Eq. 3.8-3.11), a short MPM fracture run of the body at rest in its own
// (material) space damages it (ch. 2.3), its crack surface is extracted and its fragments cut (sec.
// 3.3-3.5), and the fragments replace it in the rigid world with its rigid velocity field. An event that
// fails numerically is reported and the body goes on unbroken.
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brittle/brittle_solid.hpp"
#include "brittle/fracture_event.hpp"
#include "brittle/hertz.hpp"
#include "brittle/solver.hpp"
#include "brittle/strength.hpp"
#include "rigid/rigid_world.hpp"
#include "shatter/fragment_spawn.hpp"
#include "shatter/impact_trigger.hpp"

namespace shellfrac::shatter {

// A breakable object as the scene gives it.
struct BreakableSpec {
  std::string name;
  brittle::TriMesh mesh;  // closed, in material coordinates (= world coordinates at t = 0)
  std::shared_ptr<const brittle::BrittleSolid> particles;  // sampled once, at rest, undamaged
  brittle::Sampling sampling = brittle::Sampling::Regular;  // for resampling large fragments
  unsigned seed = 1;
  std::vector<brittle::StrengthRegion> strength_regions;   // reapplied to resampled particles
  brittle::WeibullStrength weibull;
  brittle::SolverOptions solver;  // dx, cfl, fields, stop; its gravity is ignored (object space, sec. 3.2)
  int crack_interval = 20;        // MPM steps between crack extractions for the two fields
  brittle::FractureEventOptions event;
  double contact_times = 3;       // an event's MPM run lasts at most this many contact times t_c
  // An event whose crack surface leaves the body whole although at least this share of its particles
  // broke is cut again along the damage time (brittle::BreakageOrderOptions).
  double breakage_order_above = 0.5;
  double impulse_threshold = 0;   // RB_imp [N s]
  double impact_radius = 0;       // traction radius around the contact (0: two particle spacings)
  rigid::Vec3 velocity = rigid::Vec3::Zero(), angular_velocity = rigid::Vec3::Zero();
  SpawnSettings spawn;            // volume ratios, N_df, margin, surface
};

// An unbreakable sphere (billiard ball, marble), dynamic or kinematic.
struct ProjectileSpec {
  std::string name;
  double radius = 0, density = 0;
  brittle::HertzBody material;  // E, nu (radius and mass are filled in)
  rigid::Vec3 centre = rigid::Vec3::Zero(), velocity = rigid::Vec3::Zero(), angular_velocity = rigid::Vec3::Zero();
  bool kinematic = false;
  rigid::Surface surface;
};

// A static box in the world (a column, a table top, a wall).
// A static prop: a box at centre, or, when `mesh` has triangles, that mesh where it stands.
struct PropSpec {
  std::string name;
  rigid::Vec3 centre = rigid::Vec3::Zero(), half_extents = rigid::Vec3::Zero();
  brittle::TriMesh mesh;
  rigid::Surface surface;
  brittle::HertzBody material{3e10, 0.2};  // infinite radius and mass
};

struct GroundSpec {
  rigid::Vec3 point = rigid::Vec3::Zero(), normal = rigid::Vec3(0, 0, 1);
  rigid::Surface surface;
  brittle::HertzBody material{3e10, 0.2};  // concrete; infinite radius and mass
};

struct ShatterOptions {
  double dt = 1e-3;  // rigid step [s]
  rigid::Vec3 gravity = rigid::Vec3(0, 0, -9.81);
  int solver_iterations = 20;
  // A body's impulse is summed over this many consecutive rigid steps: Bullet resolves one collision over
  // two or three (a 1 kg cube at 5 m/s: 1.37, 4.21 and 0.09 N s), and a threshold is meant for the whole.
  int impulse_window = 3;
  std::optional<GroundSpec> ground;
};

// One fracture event, for summary.json (thesis Table 3.3's columns per event).
struct EventRecord {
  double time = 0;
  std::string body;
  std::string partner;   // what hit it ("ground", a prop, a projectile, another piece)
  int generation = 0;
  std::string outcome;   // "broken", "intact" (the crack did not separate it), "failed", "interrupted"
  std::string message;   // why it failed
  bool breakage_order = false;  // cut along the damage time (the body was shattered through)
  double impulse = 0, contact_time = 0, approach_speed = 0;
  rigid::Vec3 point = rigid::Vec3::Zero();  // world
  rigid::BodyState parent;                  // the body's state after the rigid step that broke it
  size_t particles = 0, mpm_steps = 0, damaged_particles = 0, fragments = 0;
  size_t rubble_particles = 0;  // taken out of the transfers (material.fully_damaged "rubble")
  size_t by_class[4] = {0, 0, 0, 0};  // fragments per FragmentClass
  double seconds_mpm = 0, seconds_extract = 0, seconds_cut = 0, seconds_spawn = 0;
  double seconds_mpm_cracks = 0;  // of seconds_mpm: the crack updates for the two fields every crack_interval steps
  // relative errors of the fragments against the parent (thesis sec. 3.6.1 bookkeeping)
  double mass_error = 0, momentum_error = 0, angular_momentum_error = 0, energy_ratio = 1, volume_change = 0;
};

// How far the MPM run of a fracture event has come, after one of its steps.
struct EventProgress {
  const std::string& body;
  size_t steps = 0;        // MPM steps taken
  double time = 0;         // MPM time reached [s]
  double end_time = 0;     // the most it runs: contact_times x t_c, or the solid's own stop.max_time
  size_t damaged = 0, particles = 0;
};

// Called after every MPM step of a fracture event, on the thread that steps the loop (the loop does no
// I/O: the run driver reports progress through it). Returning false abandons the event: it is recorded
// with outcome "interrupted" and the body goes on unbroken; events that follow in the same call are
// abandoned at their first step if the observer keeps saying so.
using EventObserver = std::function<bool(const EventProgress&)>;

struct ShatterTotals {
  size_t rigid_steps = 0, mpm_steps = 0, events = 0, broken = 0, failed = 0;
  double seconds_rigid = 0, seconds_mpm = 0, seconds_extract = 0, seconds_cut = 0, seconds_spawn = 0;
};

// A piece in the world: an original object, a fragment, or a projectile.
struct Piece {
  std::string name;
  int body = -1;                        // rigid world id; -1 once broken
  int root = -1;                        // index of the breakable it came from (-1: projectile)
  int generation = 0;                   // 0: the original object
  FragmentClass fragment_class = FragmentClass::NearlyWhole;
  bool breakable = false;
  brittle::TriMesh mesh;                // render mesh in the root's material coordinates
  brittle::MassProperties properties;   // of `mesh`, material coordinates
  rigid::Pose material_to_body;
  std::shared_ptr<const brittle::BrittleSolid> particles;  // at rest; empty until an event needs them
  double born = 0, died = -1;           // times it entered and left the world
};

class ShatterLoop {
 public:
  explicit ShatterLoop(const ShatterOptions& options);
  ~ShatterLoop();

  // Throws core::InputError naming the spec (threshold not positive, bad ratios, unusable mesh).
  void add_breakable(const BreakableSpec& spec);
  void add_projectile(const ProjectileSpec& spec);
  void add_static_mesh(const std::string& name, const brittle::TriMesh& mesh, const rigid::Surface& surface);
  void add_prop(const PropSpec& prop);

  // Rigid steps (each followed by any fracture events it triggered) until the loop's time reaches t.
  void advance_to(double t);
  void step();
  double time() const { return time_; }

  const std::vector<Piece>& pieces() const { return pieces_; }   // alive and dead
  // The static props' surfaces where they stand (boxes as box meshes), for the frames.
  const std::vector<brittle::TriMesh>& prop_meshes() const { return prop_meshes_; }
  bool alive(size_t piece) const { return pieces_[piece].body >= 0; }
  rigid::Pose world_from_material(size_t piece) const;
  brittle::TriMesh world_mesh(size_t piece) const;
  const std::vector<EventRecord>& events() const { return events_; }
  void set_event_observer(EventObserver observer) { observer_ = std::move(observer); }
  const ShatterTotals& totals() const { return totals_; }
  rigid::RigidWorld& world() { return world_; }
  const rigid::RigidWorld& world() const { return world_; }
  // The rigid moments of the given pieces as the world reports them now.
  RigidMoments moments(const std::vector<size_t>& pieces) const;

 private:
  int add_piece(Piece piece, const rigid::BodyDesc& body);
  brittle::HertzBody hertz_body(int body, const rigid::Vec3& point) const;
  // One fracture event (thesis secs. 3.2 and 3.6.2): the load, the MPM run, the cut, the spawn.
  void fracture(size_t piece, const BodyImpact& impact);
  // The impact as ghost-particle load in the piece's material frame, with the Hertz contact time.
  brittle::Impact event_load(size_t piece, const BodyImpact& impact, const brittle::BrittleSolid& solid,
                             EventRecord& r) const;
  // The quasi-static MPM run; false when the observer abandoned it.
  bool run_event_mpm(const Piece& p, brittle::BrittleSolid& solid, const std::vector<brittle::GhostParticle>& ghosts,
                     EventRecord& r);
  // Crack extraction and cut, along the breakage order when damage fills the body.
  brittle::FractureEvent cut_fragments(const Piece& p, const brittle::BrittleSolid& solid, EventRecord& r);
  // Replaces the piece by its fragments and books the conservation errors.
  void spawn_fragments(size_t piece, const brittle::FractureEvent& ev, EventRecord& r);
  std::shared_ptr<const brittle::BrittleSolid> particles_for(const Piece& p);

  ShatterOptions options_;
  rigid::RigidWorld world_;
  std::vector<BreakableSpec> roots_;
  std::vector<double> root_volume_;
  std::vector<ProjectileSpec> projectiles_;
  std::vector<Piece> pieces_;
  // Sibling fragments touch along their crack, and their collision shapes (hulls, decimated meshes) only
  // approximate the cut surfaces, so they may overlap at birth; contacts between them would push them
  // apart with energy the fracture never had. They ignore each other until their bounds part.
  std::vector<std::pair<int, int>> ignored_siblings_;
  void release_separated_siblings();
  std::vector<int> piece_of_body_;                 // rigid id -> piece (-1: ground, static)
  // per (body, partner): the impacts of the last impulse_window steps
  std::map<std::pair<int, int>, std::deque<BodyImpact>> recent_;
  std::optional<GroundSpec> ground_;
  std::map<int, brittle::HertzBody> static_material_;  // static bodies other than the ground
  std::vector<brittle::TriMesh> prop_meshes_;
  int ground_id_ = -1;
  std::vector<EventRecord> events_;
  ShatterTotals totals_;
  EventObserver observer_;
  double time_ = 0;
};

}  // namespace shellfrac::shatter
