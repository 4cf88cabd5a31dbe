#pragma once
// The solver inputs of a scene: what scene::build() derives from a validated Scene (scene/scene.hpp). Patches
// are NURBS surfaces, pins are control-point lists, interfaces carry their coupling operators, colliders
// and solids their shapes, and every default is filled in. The simulation (sim/) reads only this.
#include <algorithm>
#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "brittle/fracture_event.hpp"
#include "core/weibull.hpp"
#include "brittle/impact.hpp"
#include "brittle/solver.hpp"
#include "shatter/shatter_loop.hpp"
#include "coupling/interface.hpp"
#include "mpm/colliders.hpp"
#include "nurbs/nurbs_surface.hpp"
#include "shell/damage.hpp"
#include "shell/in_plane_stress.hpp"
#include "shell/plasticity.hpp"
#include "shell/quadrature.hpp"
#include "shell/stress_model.hpp"

namespace shellfrac::scene::model {

// A polygon in a patch's parameter plane whose points get their own failure stress (thesis Fig. 4.23b).
struct FailureRegion {
  std::vector<Eigen::Vector2d> polygon;
  double failure_stress = 0;
  std::optional<double> fracture_energy;  // unset: keep the material's brittleness H
};

// Rankine damage of a shell material (thesis Eq. 2.28-2.31, sec. 4.4.1); enabled by a "fracture" object.
struct FractureSpec : shell::FractureParams {  // what the shell's damage law reads, then the scene's parts
  std::vector<FailureRegion> regions;  // later regions win where they overlap
  core::WeibullStrength weibull;       // then a seeded factor per in-plane point (keeps each point's H)
};

// Elastic material of a shell (SI units). Lamé parameters follow thesis Eq. 2.4.
struct Material {
  std::string model = "neo_hookean";
  double youngs_modulus = 0;  // E [Pa]
  double poisson_ratio = 0;   // nu, in (-1, 0.5)
  double density = 0;         // rho [kg/m^3]
  // Type-III shearing/compression model (shell/shear_model.hpp); unset stiffnesses default to mu and E.
  std::optional<double> shear_stiffness, compression_stiffness;
  double shear_friction = 0.0;
  // Render faces whose largest principal stretch against the rest mesh exceeds this are strands
  // (metrics.strand_area, docs/cli.md).
  double strand_stretch = 3.0;
  // Von Mises plasticity of the in-plane stress (metal sheets); enabled by a "plasticity" object.
  shell::PlasticityParams plasticity;
  // Thickness treatment of the Kirchhoff-Love in-plane stress (see shell/in_plane_stress.hpp).
  shell::TransverseModel transverse = shell::TransverseModel::Condensed;
  // The Type IV stress: the thesis's Kirchhoff-Love in-plane stress, or a comparison model.
  shell::StressModel stress_model = shell::StressModel::KirchhoffLove;
  FractureSpec fracture;

  double mu() const { return youngs_modulus / (2.0 * (1.0 + poisson_ratio)); }
  double lambda() const {
    return youngs_modulus * poisson_ratio / ((1.0 + poisson_ratio) * (1.0 - 2.0 * poisson_ratio));
  }
};

// A prescribed cut in a patch's parameter plane: an open polyline or a closed curve (thesis Fig. 4.14,
// 4.21). Validated against the patch domain when the scene is read.
struct Cut {
  std::vector<Eigen::Vector2d> points;
  bool closed = false;
};

// One shell: a NURBS patch (its reference configuration), a thickness and a material.
struct Shell {
  std::string name;
  std::string shape;  // "flat", "cylinder", "cone" or "control_net"
  nurbs::NurbsSurface surface;
  double thickness = 0;  // tau [m]
  Material material;
  shell::QuadratureRule quadrature;
  Eigen::Vector3d initial_velocity = Eigen::Vector3d::Zero();
  std::vector<Cut> cuts;
  // Per control point, added to initial_velocity ("initial_velocity_field"); empty when not given.
  std::vector<Eigen::Vector3d> initial_velocity_field;
  // A fracture material or prescribed cuts: the shell can carry cracks.
  bool can_crack() const { return material.fracture.enabled || !cuts.empty(); }
};

// A piecewise-linear factor of time through keyframes (t, factor), constant before the first and after
// the last; no keyframes: 1.
struct Ramp {
  std::vector<Eigen::Vector2d> keys;  // times strictly increasing (checked when the scene is read)
  double at(double t) const {
    if (keys.empty()) return 1.0;
    if (t <= keys.front().x()) return keys.front().y();
    for (size_t k = 1; k < keys.size(); ++k)
      if (t <= keys[k].x()) {
        const double s = (t - keys[k - 1].x()) / (keys[k].x() - keys[k - 1].x());
        return (1.0 - s) * keys[k - 1].y() + s * keys[k].y();
      }
    return keys.back().y();
  }
};

// An external load on one shell (scene key "loads"), turned into generalized control-point forces
// f_k = integral of R_k t dA (thesis Eq. 4.8 with an applied traction) by sim/loads.cpp.
struct Load {
  enum class Kind { Pressure, Point, Edge, Body };
  Kind kind = Kind::Pressure;
  size_t shell = 0;
  double pressure = 0;                                 // Pressure [Pa], along a_1 x a_2 of the deformed surface
  Eigen::Vector2d at = Eigen::Vector2d::Zero();        // Point: parameter (u, v) of the patch
  Eigen::Vector3d vector = Eigen::Vector3d::Zero();    // Point: force [N]; Edge: [N/m]; Body: acceleration [m/s^2]
  int edge = 0;                                        // Edge: 0 u0, 1 u1, 2 v0, 3 v1
  Ramp ramp;
  std::string json_path;
};

// A probe (output.probes): a parameter point of a shell sampled every step or every frame.
struct Probe {
  std::string name;
  size_t shell = 0;
  Eigen::Vector2d at = Eigen::Vector2d::Zero();  // parameter (u, v) of the patch
  bool every_step = false;
};

// time.until_rest (docs/scene-format.md).
struct RestCriterion {
  double kinetic_energy = 0;  // [J]
  double speed = 0;           // largest control-point speed [m/s]
  double duration = 0;        // both below their thresholds this long [s]
};

// A volumetric solid (Type-I particles) sampled inside an analytic shape.
struct SolidBody {
  std::string name;
  std::string shape;  // "sphere" or "box"
  std::shared_ptr<const mpm::Shape> geometry;
  Eigen::Vector3d lo, hi;  // bounding box to sample
  double spacing = 0;      // particle spacing [m]
  bool poisson_disk = false;
  unsigned seed = 1;
  Material material;
  Eigen::Vector3d initial_velocity = Eigen::Vector3d::Zero();
};

// A brittle solid (a solid with a "fracture" object, docs/brittle.md): its closed mesh, its sampled particles
// with their strength, the impacts' ghost particles, and the settings of its fracture run (thesis ch. 3).
// Everything that can be refused is checked when the scene is built, naming the JSON path.
struct BrittleBody {
  std::string name;
  std::string json_path;  // "/solids/<i>", for messages
  brittle::TriMesh mesh;  // closed, in material space (the domain the fragments are cut from)
  std::shared_ptr<const brittle::BrittleSolid> solid;  // the particles at rest, undamaged
  std::vector<brittle::GhostParticle> ghosts;          // all impacts
  brittle::SolverOptions solver;  // dx, cfl, fields, stop (gravity: the scene's)
  int crack_interval = 20;        // steps between crack extractions for the two fields
  brittle::FractureEventOptions event;  // h_v, cutter, voxel, gap width
  double sliver_volume = 0;       // fragments smaller than this are slivers, not counted (docs/brittle.md)
  std::string mesh_repair;        // what "repair" changed in the mesh file; empty when it was not repaired
  // Set when the solid is a body of the shatter loop ("rigid_body"): its threshold, spin, collision mesh
  // budget and surface. Its impacts then come from its contacts.
  struct Rigid {
    double impulse_threshold = 0;
    Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();
    Eigen::Vector3d velocity = Eigen::Vector3d::Zero();
    size_t collision_faces = 10000;
    rigid::Surface surface;
    double impact_radius = 0;
    double contact_times = 3;
    std::vector<brittle::StrengthRegion> strength_regions;  // reapplied when fragments are resampled
    brittle::WeibullStrength weibull;
    brittle::Sampling sampling = brittle::Sampling::Regular;
    unsigned seed = 1;
  };
  std::optional<Rigid> rigid;
};

// The rigid-body world of the shatter loop (scene key "rigid"; docs/brittle.md, "The shatter loop").
struct RigidWorldSettings {
  shatter::ShatterOptions options;  // dt, gravity (the scene's), solver iterations, ground
  shatter::VolumeRatios ratios;
  std::vector<shatter::ProjectileSpec> projectiles;
  std::vector<shatter::PropSpec> props;
};

// FLIP share of grid.transfer "flip"/"aflip" when no flip_ratio is given (docs/shell-model.md).
inline constexpr double kDefaultFlipRatio = 0.99;
// Shares of the adaptive transfer: intact elastic material keeps all of its own velocity
// (energy-conserving affine-FLIP), material next to damage, plastic flow or a crack none of it (APIC).
inline constexpr double kDefaultIntactFlipRatio = 1.0;
inline constexpr double kDefaultActiveFlipRatio = 0.0;
// Under the adaptive transfer each cell's Type III particle carries this share of its mass instead of
// shell::kShearParticleMassShare (0.5). Those particles run the APIC share, so the grid filters the
// velocity of whatever mass they carry every step; with 0.5 the 16-cell simply supported plate's period
// was 3.15% long, with 0.2 it is 1.60% (docs/shell-model.md, "Transfer").
inline constexpr double kAdaptiveShearMassShare = 0.2;

// Background grid and transfer scheme.
struct GridSettings {
  std::optional<double> dx;  // node spacing [m]; unset: the smallest shell cell size
  bool apic = false;         // PIC (the thesis's choice) or APIC
  // FLIP share of the g2p velocity update, on every particle set (mpm/particle_set.hpp): 0 = plain PIC/APIC.
  double flip = 0.0;
  // Adaptive transfer (sim/transfer_shares.hpp): `flip` is the share on intact elastic material and
  // `flip_active` the share next to damage, plastic flow or a crack, chosen per particle every step.
  bool adaptive = false;
  double flip_active = 0.0;
  // Adaptive transfer only: how shells that can crack (Shell::can_crack) run (grid.cracking_shells;
  // docs/shell-model.md, "Transfer").
  //  - PicWhereDamaged (default): the adaptive transfer, like an intact shell (APIC beside cracks and
  //    cuts), but the particles whose support holds a damaged point run PIC (share 0, affine velocity
  //    dropped after every g2p); the rest of the shell keeps its shares while it tears.
  //  - PicWhileDamaged: the adaptive transfer, except while some point of the shell or of a shell a
  //    coupled seam ties to it is damaged (c > 0): then PIC for all of their particles.
  //  - RpicWhileDamaged: the same, but while damaged its particles keep the rotational part of their
  //    affine velocity (RPIC: angular momentum and rigid rotation kept, stretching modes damped like PIC).
  //  - AdaptiveThenPic: the adaptive transfer until damage or a crack first appears on the shell; from
  //    then on PIC for all of its particles.
  //  - AdaptiveThenApic: the same, but APIC (share 0, affine velocity kept) once damaged.
  //  - Adaptive: the adaptive transfer throughout.
  //  - Pic: PIC throughout, with half of each cell's mass on its shear particles (the rule before).
  enum class CrackingShells {
    PicWhereDamaged,
    PicWhileDamaged,
    RpicWhileDamaged,
    AdaptiveThenPic,
    AdaptiveThenApic,
    Adaptive,
    Pic
  };
  CrackingShells cracking = CrackingShells::PicWhereDamaged;
  // Adaptive transfer only: whether shell s runs it (false: PIC for that shell's particles).
  bool adaptive_shell(const Shell& s) const {
    return adaptive && (cracking != CrackingShells::Pic || !s.can_crack());
  }
  // Adaptive transfer only: whether shell s leaves it once damage or a crack appears on it.
  bool turns_once_damaged(const Shell& s) const {
    return adaptive && s.can_crack() &&
           (cracking == CrackingShells::AdaptiveThenPic || cracking == CrackingShells::AdaptiveThenApic);
  }
  // Adaptive transfer only: whether shell s runs PIC exactly while it (or its seam group) is damaged.
  bool pic_while_damaged(const Shell& s) const {
    return adaptive && s.can_crack() &&
           (cracking == CrackingShells::PicWhileDamaged || cracking == CrackingShells::RpicWhileDamaged);
  }
  // Adaptive transfer only: whether the particles beside damage on shell s run PIC while the rest keeps
  // the adaptive shares.
  bool pic_where_damaged(const Shell& s) const {
    return adaptive && s.can_crack() && cracking == CrackingShells::PicWhereDamaged;
  }
};

struct ColliderSpec {
  std::string name;
  std::string shape;  // "half_space", "sphere", "box"
  mpm::Collider collider;
};

// Dirichlet constraint: the listed control points follow `motion` from their initial positions, in all
// components or in the directions `held` (sim/pin_system.hpp). A symmetry pin also ties each held point
// to its partner in the next row in the directions of the symmetry plane.
struct Pin {
  std::string name;  // the scene's, or "pin<index>"
  size_t shell = 0;
  std::vector<int> control_points;
  // Per control point, the orthonormal directions held (1 to 3); empty: all three components.
  std::vector<std::vector<Eigen::Vector3d>> held;
  // Symmetry pins: the partner of each control point in the next row, and the plane's unit normal.
  std::vector<int> tied;
  Eigen::Vector3d symmetry_normal = Eigen::Vector3d::Zero();
  mpm::RigidMotion motion;
  std::string json_path;  // where the pin was defined, for messages
  bool holds_all(size_t k) const { return held.empty() || held[k].size() == 3; }
};

// One pass/fail limit of `shellfrac verify coupling`: no value takes the default (output/seam_metrics.hpp),
// checked = false (JSON null) turns the check off.
struct VerifyLimit {
  std::optional<double> value;
  bool checked = true;
};

// The interface's "verify" object: limits on the measured seam (output/seam_metrics.hpp).
struct InterfaceVerify {
  VerifyLimit max_gap;            // [m]
  VerifyLimit max_angle_degrees;  // between the two patches' normals along the seam
  VerifyLimit max_stress_ratio;   // seam stress over the patch median
};

// Two patch edges coupled C0 or C1 (thesis sec. 4.8); the coupling operators are built when the scene is
// read, so a bad interface (edges that do not meet, mismatched degrees) is bad input.
struct InterfaceSpec {
  coupling::Interface coupling;
  std::string json_path;
  // False for "continuity": "none": the seam is only measured (Scene::uncoupled_seams), never coupled.
  bool coupled = true;
  InterfaceVerify verify;
  // Momentum-correction velocity of thesis Eq. 4.30-4.32 (on by default); off only for comparisons.
  bool momentum_correction = true;
  // Follower control points near the seam that receive the corrected velocity from the grid (Eq. 4.32):
  // the rows within the quadratic stencil's reach (three rows) of the coupled ones.
  std::vector<int> follower_neighbours;
  // "seam_velocity": "leader" (default) is the thesis's update (sec. 4.8.1): the leader's rows move as the
  // grid moved them and the follower rows' grid velocities are dropped. "projected": the coupled rows of
  // both patches decide the seam's motion (mass-weighted projection onto the coupling constraint,
  // coupling/row_projection.hpp), which removes the leader/follower asymmetry (docs/coupling.md).
  bool project_both_sides = false;
  // Leader points near the seam that take the projection's correction from the grid (as Eq. 4.32).
  std::vector<int> leader_neighbours;
};

// Crack machinery shared by all fracturing shells (thesis sec. 4.4.2, 4.6, 4.7).
struct CrackSettings {
  int extraction_interval = 10;    // steps between consistent crack extractions
  bool phantom_nodes = true;       // false: a single velocity field (for comparison; fragments glue)
  double contact_friction = 0.3;   // Coulomb coefficient between fragments (Eq. 4.25)
  double max_support = 4.5;        // MLS support cap in cells (sec. 4.6)
  double shadow_offset = 1e-5;     // render-mesh shadow vertex offset Dv (sec. 4.9.3)
  // Weights of control points hidden behind a crack near its tip: true = diffraction (the default: the
  // surface stays closed at tips and around bends, docs/mls.md "Tip weights"), false = the thesis's
  // straight-line visibility (sec. 4.6).
  bool tip_diffraction = true;
  // How cut bases choose their support (shell::SupportRule, docs/mls.md "Support size"): true =
  // continuous (the default), false = the thesis's stepped growth from 1.5 cells; and the continuous
  // rule's margin.
  bool continuous_support = true;
  double support_margin = 1.5;
  // Selective mass scaling beside cracks (ShellPatch::set_mass_scaling_budget): at most this share of a
  // patch's control-point mass is added to the points whose cut bases would shrink the step; 0 adds none.
  double mass_scaling = 0.0;
};

// Frames of a run: frame 0 at t = 0, then one every 1 / rate, and a last one at `end` when `end` is not
// on a frame boundary (so the run always reaches `end`). The number of frames after frame 0 (a double:
// hostile scenes ask for more than an int holds, and callers refuse them), and the time of frame f.
inline double frames_after_start(double end, double rate) {
  const double whole = std::floor(end * rate + 1e-9);
  return whole + (end - whole / rate > 1e-9 * std::max(1.0, end) ? 1.0 : 0.0);
}
inline double frame_time(int f, double end, double rate) {
  return f <= std::floor(end * rate + 1e-9) ? f / rate : end;
}

struct TimeSettings {
  double end = 1.0;                // simulated seconds (the latest end with until_rest)
  std::optional<RestCriterion> until_rest;
  double frame_rate = 24.0;        // frames written per simulated second
  std::optional<double> dt;        // fixed step [s]; unset means "from the stability bound"
  double cfl = 0.5;                // safety factor on the stability bound, in (0, 1]
  bool allow_substepping = false;  // split frames into more steps when dt exceeds the bound
  // For stability studies only: accept a dt above the bound and run it as given (the run may then fail
  // with a numerical error, exit code 3). Off by default.
  bool enforce_stability_bound = true;
};

struct OutputSettings {
  std::string format = "obj";  // an assimp export format id
  int resolution_u = 32;       // render quads per patch along u (independent of the simulation)
  int resolution_v = 32;       // ... and along v
  bool triangulate = false;    // write triangles only (formats that need them are triangulated anyway)
  bool double_precision = false;  // 17 significant digits where the format allows it
  std::vector<Probe> probes;
  bool control_points = false;    // write frames/frame_NNNNN.control_points.csv
};

struct Model {
  std::string name;
  std::string source;  // file path, or "<built-in default>"
  TimeSettings time;
  OutputSettings output;
  Eigen::Vector3d gravity{0.0, -9.81, 0.0};
  double damping = 0.0;  // velocity damping rate [1/s] applied on the grid (for quasi-static runs)
  GridSettings grid;
  std::vector<Shell> shells;
  std::vector<SolidBody> solids;
  std::vector<BrittleBody> brittle_solids;  // solids with "fracture": run by the brittle solver or, with
                                            // "rigid_body", carried by the shatter loop
  std::optional<RigidWorldSettings> rigid;  // set when any brittle solid has "rigid_body"
  std::vector<ColliderSpec> colliders;
  std::vector<Pin> pins;
  std::vector<Load> loads;
  CrackSettings cracks;
  std::vector<InterfaceSpec> interfaces;
  // Interfaces declared with "continuity": "none": the edges are checked and measured like the coupled
  // ones (seam metrics, `verify coupling`) but the simulation leaves them free.
  std::vector<InterfaceSpec> uncoupled_seams;
  // What the build changed in the input (a repaired mesh): the commands print them as warnings.
  std::vector<std::string> warnings;
  // True when any shell can crack (fracture material or prescribed cuts).
  bool has_cracks() const {
    for (const Shell& s : shells)
      if (s.material.fracture.enabled || !s.cuts.empty()) return true;
    return false;
  }
};

}  // namespace shellfrac::scene::model

namespace shellfrac::scene {
using Model = model::Model;
}  // namespace shellfrac::scene
