#pragma once
// A scene as plain data: what the user wrote, nothing derived. Every key of the scene format
// (docs/scene-format.md) is a field here; optional fields are unset when the user left them out, so a
// scene read from JSON writes back to the same document (scene/json_io.hpp). Scenes can be built in C++
// directly: set the fields, then scene::build() (scene/build.hpp) validates them exactly as the JSON reader
// does (errors carry the JSON pointer of the offending field) and derives the solver inputs.
#include <array>
#include <optional>
#include <string>
#include <variant>
#include <vector>

namespace shellfrac::scene {

template <class T>
using Opt = std::optional<T>;
using Vec2 = std::array<double, 2>;
using Vec3 = std::array<double, 3>;
using Int2 = std::array<int, 2>;

// The NURBS patch of a shell: a built-in shape ("flat", "cylinder", "cone") or an explicit "control_net".
// Which fields apply depends on `type`.
struct Patch {
  Opt<std::string> type;
  Opt<Vec3> origin, axis_u, axis_v;             // placement of the built-in shapes
  Opt<Vec2> size;                               // flat
  Opt<Int2> cells;                              // flat, cylinder, cone
  Opt<double> radius;                           // cylinder
  Opt<double> radius_bottom, radius_top;        // cone
  Opt<double> height, sweep_degrees;            // cylinder, cone
  Opt<Int2> degree;                             // control_net (required); built-in shapes (default 2, 2)
  Opt<std::vector<double>> knots_u, knots_v;    // control_net
  Opt<std::vector<Vec3>> control_points;        // control_net, u running fastest
  Opt<std::vector<double>> weights;             // control_net
  Opt<Int2> refine;                             // control_net
  Opt<Int2> elevate;                            // control_net: degree elevation before `refine`

  static Patch flat(Vec2 size, Int2 cells) {
    Patch p;
    p.type = "flat";
    p.size = size;
    p.cells = cells;
    return p;
  }
};

struct Plasticity {
  Opt<double> yield_stress, hardening;
};

// A parameter-plane polygon with its own failure stress (thesis Fig. 4.23b).
struct FailureRegion {
  Opt<std::vector<Vec2>> polygon;
  Opt<double> failure_stress, fracture_energy;
};

// A seeded Weibull draw of the failure stress per material point (core/weibull.hpp).
struct WeibullSpec {
  Opt<double> modulus;
  Opt<bool> scale_is_mean;
  Opt<int> seed;
};

// Rankine damage with explicit cracks (thesis sec. 4.4.1).
struct Fracture {
  Opt<double> failure_stress, fracture_energy;
  Opt<std::string> damage_rule;  // "healing" or "monotone"
  Opt<double> residual_stiffness;  // share of the tensile stress a fully damaged point keeps
  std::vector<FailureRegion> regions;
  Opt<WeibullSpec> weibull;  // heterogeneous strength per in-plane point, after the regions
};

struct Material {
  Opt<std::string> model;
  Opt<double> youngs_modulus, poisson_ratio, density;  // keys E, nu, density
  Opt<std::string> transverse, stress_model;
  Opt<double> shear_stiffness, compression_stiffness, shear_friction;
  Opt<double> strand_stretch;  // render faces stretched more than this count as strands (metrics)
  Opt<Plasticity> plasticity;
  Opt<Fracture> fracture;
};

struct Quadrature {
  Opt<int> points, layers;
};

// A prescribed cut: a polyline (or closed curve) in the patch's parameter plane.
struct Cut {
  Opt<std::vector<Vec2>> points;
  Opt<bool> closed;
};

// A per-control-point initial velocity from one of a fixed set of shapes over the normalised parameter
// coordinates (s, t) in [0, 1]^2 of each control point's Greville point (no expressions are evaluated):
//   "sine":   amplitude * direction * sin(m pi s) sin(n pi t), modes = [m, n];
//   "linear": at_origin + s * per_u + t * per_v;
//   "list":   one velocity per control point, u running fastest.
struct VelocityField {
  Opt<std::string> shape;  // "sine", "linear", "list"
  Opt<Int2> modes;
  Opt<double> amplitude;
  Opt<Vec3> direction;
  Opt<Vec3> at_origin, per_u, per_v;
  Opt<std::vector<Vec3>> values;
};

struct Shell {
  Opt<std::string> name;
  Opt<Patch> patch;
  Opt<double> thickness;
  Opt<Material> material;
  Quadrature quadrature;
  Opt<Vec3> initial_velocity;
  Opt<VelocityField> initial_velocity_field;  // added to initial_velocity
  std::vector<Cut> cuts;
};

// The CD-MPM phase field's material parameters (seed 001, sec. 3.4.2; docs/phase-field.md).
struct PhaseFieldMaterial {
  Opt<double> length_scale, mobility, residual, broken_below;
};

// CD-MPM's NACC plasticity parameters (seed 001, sec. 6.2; docs/nacc.md).
struct NaccMaterial {
  Opt<double> alpha0, beta, xi, friction;
  Opt<bool> hardening;
};

struct SolidMaterial {
  Opt<std::string> model;
  Opt<double> youngs_modulus, poisson_ratio, density;
  // Damage of a brittle solid, read only with a "fracture" object: Rankine (thesis Eq. 2.28-2.31), the
  // default, the CD-MPM phase field, or CD-MPM's NACC plasticity.
  Opt<std::string> damage_model;  // "rankine", "phase_field" or "nacc"
  Opt<double> failure_stress, fracture_energy, characteristic_length, residual_stiffness;
  Opt<std::string> damage_rule;  // "healing" or "monotone" (Rankine)
  Opt<std::string> fully_damaged;  // Rankine, at c_his = 1: "tensionless" (the thesis), "bounded" or "rubble"
  Opt<PhaseFieldMaterial> phase_field;
  Opt<NaccMaterial> nacc;
};

// A box or sphere in a brittle solid's material space: particles removed there ("remove", notches) or a
// region of its own failure stress ("strength.regions").
struct SolidRegion {
  Opt<std::string> shape;  // "box", "sphere"
  Opt<Vec3> center, half_extents;
  Opt<double> radius;
  Opt<double> failure_stress;  // strength regions only
};

// Heterogeneous strength of a brittle solid: regions, then an optional seeded Weibull draw per particle.
struct SolidStrength {
  std::vector<SolidRegion> regions;
  Opt<WeibullSpec> weibull;
};

// The projectile of an impact, for the Hertz contact time (thesis Eq. 3.8-3.11).
struct HertzSpec {
  Opt<double> youngs_modulus, poisson_ratio, radius, mass, speed;  // keys E, nu, radius, mass, speed
};

// An impact load on a brittle solid (thesis sec. 3.6.2, Eq. 3.12), in its material space.
struct ImpactSpec {
  Opt<Vec3> point, direction;
  Opt<double> impulse, duration, start_time, radius;
  Opt<HertzSpec> hertz;
};

struct FractureStop {
  Opt<double> damaged_fraction, max_time;
  Opt<int> max_steps;
};

// Breakage ordered by the damage time (docs/brittle.md, brittle/breakage_order.hpp).
struct BreakageOrder {
  Opt<double> dynamics, min_share;
  Opt<int> smoothing_steps;  // 0: the crack sheets stay staircases of the lattice's cells
};

// Chevron marks on the fragments' crack faces from the damage time (docs/brittle.md, thesis sec. 3.7,
// brittle/fracture_detail.hpp). Lengths in metres; unset ones follow the crack grid spacing h_v.
struct FractureDetail {
  Opt<double> height, edge, step, radius, grid, enhanced;
  Opt<int> max_steps;
};

// How the phase-field system is solved (docs/phase-field.md).
struct PhaseFieldSolve {
  Opt<std::string> solver;    // "cg" or "cholmod"
  Opt<std::string> gradient;  // "spline" or "mls"
  Opt<int> interval, max_iterations;
  Opt<double> tolerance;
};

// The brittle run of a solid (docs/brittle.md): a solid with this object is broken by the brittle solver.
struct SolidFracture {
  Opt<PhaseFieldSolve> phase_field;
  Opt<double> grid_spacing, crack_grid_spacing, cfl;
  Opt<bool> two_fields, field_contact;
  Opt<int> crack_interval;
  Opt<FractureStop> stop;
  Opt<std::string> cutter;  // "exact", "level_set"
  Opt<double> voxel, gap_width, sliver_volume;
  Opt<BreakageOrder> breakage_order;
  Opt<FractureDetail> detail;
};

// A mesh file placed in the scene (solids and colliders of shape "mesh").
struct MeshFile {
  Opt<std::string> file;  // relative paths are relative to the scene file
  Opt<double> scale;
  Opt<Vec3> translate;
  Opt<double> voxel_size, band_voxels;
  Opt<bool> repair;  // brittle solids: make a closed solid of a mesh that is not one (brittle/mesh_repair.hpp)
};

// A brittle solid carried by the rigid-body world of the shatter loop (docs/brittle.md, "The shatter
// loop"): contacts whose impulse in one rigid step passes the threshold start its fracture events.
struct RigidBodySpec {
  Opt<double> impulse_threshold;     // RB_imp [N s]
  Opt<Vec3> angular_velocity;        // [rad/s], world axes
  Opt<int> collision_faces;          // N_df
  Opt<double> friction, restitution;
  Opt<double> impact_radius;         // traction radius of an event's impact [m]
  Opt<double> contact_times;         // an event's MPM run lasts at most this many t_c
};

struct Solid {
  Opt<std::string> name;
  Opt<std::string> shape;  // "sphere", "box", "mesh"; brittle solids also "cylinder", "torus"
  Opt<Vec3> center;
  Opt<double> radius;
  Opt<Vec3> half_extents;
  Opt<double> height;                       // cylinder (axis z)
  Opt<double> major_radius, minor_radius;   // torus (in the xy plane)
  MeshFile mesh;
  Opt<double> spacing;
  Opt<std::string> sampling;  // "jittered", "poisson_disk"
  Opt<int> seed;
  Opt<SolidMaterial> material;
  Opt<Vec3> initial_velocity;
  // Brittle solids (with "fracture"): removed particles, strength, impacts and the fracture run.
  std::vector<SolidRegion> remove;
  Opt<SolidStrength> strength;
  std::vector<ImpactSpec> impacts;
  Opt<SolidFracture> fracture;
  Opt<RigidBodySpec> rigid_body;  // brittle solids only
};

// The ground of the rigid-body world: a plane, its surface, and its material for the Hertz contact time.
struct RigidGround {
  Opt<Vec3> point, normal;
  Opt<double> friction, restitution, youngs_modulus, poisson_ratio;
};

// An unbreakable ball of the rigid-body world (billiard ball, marble).
struct Projectile {
  Opt<std::string> name;
  Opt<Vec3> center, velocity, angular_velocity;
  Opt<double> radius, density, youngs_modulus, poisson_ratio, friction, restitution;
  Opt<bool> kinematic;
};

// A static prop of the rigid-body world: a box (a column, a table top) or a triangle mesh from a file
// (a plinth, a staircase; any surface, open or closed), placed with the file's scale and translate.
struct RigidProp {
  Opt<std::string> name;
  Opt<std::string> shape;  // "box" (the default) or "mesh"
  Opt<Vec3> center, half_extents;
  MeshFile mesh;           // file, scale, translate of a "mesh" prop
  Opt<double> friction, restitution, youngs_modulus, poisson_ratio;
};

// The rigid-body world of the shatter loop (thesis sec. 3.6): read when a solid has "rigid_body".
struct RigidWorldSpec {
  Opt<double> dt;
  Opt<int> solver_iterations;
  Opt<Vec3> volume_ratios;  // VR_t, VR_s, VR_l
  Opt<RigidGround> ground;
  std::vector<Projectile> projectiles;
  std::vector<RigidProp> props;
};

struct Keyframe {
  Opt<double> time;
  Opt<Vec3> translation, rotation;
};

// Rigid motion of a collider or pinned control points: constant velocities or keyframes.
struct Motion {
  Opt<Vec3> pivot;
  Opt<Vec3> linear_velocity, angular_velocity;
  Opt<std::vector<Keyframe>> keyframes;
};

struct Collider {
  Opt<std::string> name;
  Opt<std::string> shape;  // "half_space", "sphere", "box", "mesh"
  MeshFile mesh;
  Opt<Vec3> point, normal;  // half_space
  Opt<Vec3> center;         // sphere, box
  Opt<double> radius;       // sphere
  Opt<Vec3> half_extents;   // box
  Opt<std::string> boundary;  // "sticky", "slip", "friction"
  Opt<double> friction;
  Opt<Motion> motion;
};

// A shell named by its name or by its index in `shells`.
using ShellRef = std::variant<std::string, int>;

struct PinRegion {
  Opt<Vec2> u, v;  // ranges in [0, 1] of the normalised Greville abscissae
};

// A pin holds control points selected by a parameter region, an index list or patch edges (the first
// `rows` rows from each named edge). It holds all three components of their motion unless `components`
// names a subset, in the frame `frame`:
//   "global": "x", "y", "z";
//   "plane":  "normal" (along plane_normal), "tangential" (the two directions in that plane);
//   "edge":   "normal" (the reference surface normal), "along" (the edge tangent), "across" (in the
//             surface, perpendicular to the edge), "tangential" (along and across); needs "edges".
// A symmetry pin (symmetry_normal, with edges and rows 1) holds the edge row along the plane's normal and
// ties the next row to it in the plane's directions (zero slope across the plane).
struct Pin {
  Opt<std::string> name;
  Opt<ShellRef> shell;
  Opt<PinRegion> region;
  Opt<std::vector<Int2>> control_points;  // [i, j] pairs
  Opt<std::vector<std::string>> edges;    // "u0", "u1", "v0", "v1"
  Opt<int> rows;                          // with edges: rows held from each edge (default 1)
  Opt<std::string> frame;                 // "global", "plane", "edge"
  Opt<std::vector<std::string>> components;
  Opt<Vec3> plane_normal;                 // frame "plane"
  Opt<Vec3> symmetry_normal;
  Opt<Motion> motion;
};

// A load on one shell, scaled by the ramp's piecewise-linear factor (keyframes [time, factor], constant
// before the first and after the last; no ramp: factor 1):
//   "pressure": follower pressure [Pa] along the deformed surface normal a_3 (positive along a_1 x a_2);
//   "point":    a force [N] at normalised parameter point `at`, spread through the basis;
//   "edge":     a force per reference length [N/m] along a patch edge;
//   "body":     an acceleration [m/s^2] of the shell's mass (a per-shell gravity).
struct Load {
  Opt<std::string> type;  // "pressure", "point", "edge", "body"
  Opt<ShellRef> shell;
  Opt<double> pressure;
  Opt<Vec2> at;
  Opt<Vec3> force;
  Opt<std::string> edge;
  Opt<Vec3> force_per_length;
  Opt<Vec3> acceleration;
  Opt<std::vector<Vec2>> ramp;
};

struct Edge {
  Opt<ShellRef> shell;
  Opt<std::string> side;  // "u0", "u1", "v0", "v1"
};

// A limit of `verify coupling`: absent takes the default, present without value (JSON null) is off.
struct VerifyLimit {
  std::optional<double> value;
};

struct InterfaceVerify {
  Opt<VerifyLimit> max_gap, max_angle_degrees, max_stress_ratio;
};

// The top-level "verify" object: whole-scene limits of `verify coupling` on the render mesh.
struct SceneVerify {
  Opt<VerifyLimit> max_edge_stretch;  // on metrics.peak_edge_stretch; default 3, null: unchecked
};

struct Interface {
  Opt<Edge> a, b;
  Opt<bool> reversed;
  Opt<std::string> continuity;  // "C0", "C1", "none"
  Opt<double> tolerance;
  Opt<std::string> closure;        // "least_squares", "exact"
  Opt<std::string> seam_velocity;  // "leader", "projected"
  Opt<bool> momentum_correction;
  Opt<InterfaceVerify> verify;
};

// time.until_rest: the run stops once the kinetic energy and the largest control-point speed have both
// stayed below their thresholds for `duration` seconds.
struct UntilRest {
  Opt<double> kinetic_energy, speed, duration;
};

struct Time {
  Opt<double> end, frame_rate, dt, cfl;
  Opt<bool> allow_substepping, enforce_stability_bound;
  Opt<UntilRest> until_rest;
};

// A probe: a named point of a shell at normalised parameter coordinates, sampled every step or frame.
struct Probe {
  Opt<std::string> name;
  Opt<ShellRef> shell;
  Opt<Vec2> at;
  Opt<std::string> every;  // "step", "frame"
};

struct Output {
  Opt<std::string> format;
  Opt<Int2> resolution;
  Opt<bool> triangulate;
  Opt<std::string> precision;  // "float", "double"
  std::vector<Probe> probes;
  Opt<bool> control_points;  // write every frame's control-point positions (CSV)
};

struct Grid {
  Opt<double> dx;
  Opt<std::string> transfer;  // "adaptive" (default), "pic", "apic", "flip", "aflip"
  Opt<double> flip_ratio;     // FLIP share of "flip"/"aflip", or of intact material with "adaptive", in [0, 1]
  Opt<double> flip_ratio_active;  // "adaptive": share next to damage, plastic flow or a crack, in [0, 1]
  // "adaptive" only, how shells that can crack run: "pic_where_damaged" (default), "pic_while_damaged",
  // "rpic_while_damaged", "adaptive_then_pic", "adaptive_then_apic", "adaptive", "pic" (scene/model.hpp,
  // GridSettings)
  Opt<std::string> cracking_shells;
};

struct Cracks {
  Opt<int> extraction_interval;
  Opt<bool> phantom_nodes;
  Opt<double> contact_friction, max_support, shadow_offset;
  Opt<std::string> tip_weights;  // "visibility" or "diffraction"
  Opt<std::string> support;      // "continuous" (default) or "stepped"
  Opt<double> support_margin;
  Opt<double> mass_scaling;      // added-mass budget beside cracks, a share of each patch's mass
};

struct Scene {
  Opt<std::string> name;
  Opt<std::string> quality;  // "draft", "default", "high"
  Time time;
  Output output;
  std::vector<Shell> shells;
  std::vector<Solid> solids;
  Opt<Vec3> gravity;
  Opt<double> damping;
  Grid grid;
  std::vector<Collider> colliders;
  std::vector<Pin> pins;
  std::vector<Load> loads;
  Cracks cracks;
  std::vector<Interface> interfaces;
  Opt<SceneVerify> verify;
  Opt<RigidWorldSpec> rigid;

  // Where the scene came from (a file path, "<built-in default>", "<python>"): errors name it, and relative
  // mesh paths are resolved against its folder. Not part of the document.
  std::string source = "<scene>";
};

}  // namespace shellfrac::scene
