#pragma once
// What a run reports, as a typed record: serialised to OUT/summary.json by the run driver and read back
// by `verify` and the Python module. docs/cli.md describes every field.
#include <array>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/crack_counters.hpp"

namespace shellfrac::output {

struct ParticleCounts {
  size_t solid_particles = 0, control_points = 0, shear_particles = 0, quadrature_points = 0;
};

// One limit check of a seam over the run: the largest value, where it happened, the limit and the verdict
// ("pass", "fail", "unchecked", "not measured").
struct SeamCheck {
  std::optional<double> max;
  std::optional<int> frame;
  std::optional<double> time;
  std::optional<double> limit;
  std::string result;
};

struct SeamSample {
  int frame = 0;
  double time = 0;
  double gap = 0, angle_degrees = 0;
  std::optional<double> stress_ratio;
};

// metrics.interfaces[i]: one scene interface measured at every frame.
struct InterfaceReport {
  std::string interface, leader, follower, continuity;
  bool reversed = false, momentum_correction = false;
  SeamCheck gap, angle_degrees, stress_ratio;
  bool pass = true;
  std::vector<SeamSample> frames;
};

// metrics.cracks: the crack machinery over the run (docs/fracture.md, "What a run reports").
struct CrackReport : sim::CrackCounters {
  double max_damage = 0;
  std::optional<std::string> first_mls_failure;
  // The bases of the points a crack cut off from part of their NURBS support (docs/mls.md, the chain):
  // in-plane points and shear particles per level, and the material that carries no stress.
  std::vector<std::pair<std::string, size_t>> basis_points, basis_shear;
  size_t nudged = 0, membrane_only = 0, slivers = 0;
  double rigid_area = 0, rigid_mass = 0, removed_area = 0, removed_mass = 0;
  std::optional<std::string> first_sliver;
  // Mass scaling (cracks.mass_scaling): added mass over all patches now [kg], and the largest share of a
  // patch's control-point mass it makes up.
  double added_mass = 0, added_mass_share = 0;
};

// The render mesh of the last frame (metrics.pieces, ...) and the largest stretch seen in any frame.
struct MeshReport {
  int pieces = 0;  // connected components (across patches and coupled seams) of at least one grid cell
  int sliver_count = 0;  // smaller components: metrics.slivers.count and .area
  double sliver_area = 0;
  std::vector<double> piece_areas;
  double max_edge_stretch = 0;  // render-edge length over rest length, largest in the last frame
  double strand_area = 0;       // area of faces stretched beyond the strand threshold, last frame
  int strand_faces = 0;
  double peak_edge_stretch = 0;  // the largest max_edge_stretch of any frame, and that frame
  int peak_edge_stretch_frame = 0;
  double peak_strand_area = 0;
};

// crack_graphs[i]: the crack of one shell in its parameter plane.
struct CrackGraphReport {
  std::string shell;
  std::vector<std::array<double, 2>> vertices;
  std::vector<std::array<int, 2>> edges;
};

// brittle[i].fragments[k]: one piece of a fracture event, in the solid's material space (docs/brittle.md).
struct BrittleFragmentReport {
  std::string name;
  double volume = 0, mass = 0;
  std::array<double, 3> centroid{};
  std::array<double, 9> inertia{};  // about the centroid, row-major [kg m^2]
  size_t triangles = 0, crack_triangles = 0;
  bool sliver = false;  // smaller than sliver_volume: kept in the mesh, not counted
};

// brittle[i]: the fracture run of one brittle solid and its fracture event (docs/cli.md).
struct BrittleSolidReport {
  std::string solid, json_path;
  size_t particles = 0;
  long steps = 0;
  double simulated_seconds = 0;
  std::string stop_reason;  // the criterion met, or "scene_end"
  double damaged_fraction = 0;
  size_t crack_updates = 0;
  bool event = false;  // false: the run failed before the event
  std::string fragments_file, crack_file, particles_file;  // relative to the run folder
  std::string cutter;
  size_t fragment_count = 0, sliver_count = 0;  // counted pieces and slivers
  double sliver_volume_threshold = 0, sliver_volume = 0;
  double input_volume = 0, total_volume = 0, volume_change = 0;
  size_t crack_faces = 0, regions = 0;
  double crack_area = 0;  // of the crack surface inside the object [m^2]
  // Breakage ordered by damage time (docs/brittle.md): whether the crack followed it, and the regions
  // merged for being under the minimum share.
  bool breakage_order = false;
  size_t merged_regions = 0;
  // Chevron detail (fracture.detail): lines traced, crack vertices moved, the largest move [m].
  bool detail = false;
  size_t detail_lines = 0, detail_moved_vertices = 0, detail_folded_triangles = 0;
  double detail_max_displacement = 0;
  std::vector<BrittleFragmentReport> fragments;  // largest first, slivers included (flagged)
  std::vector<std::pair<std::string, double>> stage_seconds;
  // The damage model ("rankine", "phase_field" or "nacc"); for the phase field its solve totals, for
  // NACC the particle-steps through each branch of the return mapping.
  std::string damage_model = "rankine";
  size_t pf_solves = 0, pf_iterations = 0, pf_max_iterations = 0, pf_unconverged = 0, pf_analyses = 0;
  double pf_worst_residual = 0;
  std::array<size_t, 4> nacc_branches{};  // elastic, compression, tension, shear
};

// probes[i]: one output.probes entry, every sample (docs/cli.md).
struct ProbeRow {
  double time = 0;
  std::array<double, 3> position{}, displacement{}, velocity{};
  std::array<double, 6> stress{};  // Cauchy xx, yy, zz, xy, yz, xz [Pa]
};
struct ProbeReport {
  std::string name, shell, every, file;  // file: the CSV, relative to the run folder
  std::vector<ProbeRow> samples;
};

// pins[i]: a scene pin and its support reaction over the last step [N].
struct PinReport {
  std::string pin, name, shell;
  std::array<double, 3> reaction{};
};

// loads[i]: a scene load and the total force it applied in the last step [N].
struct LoadReport {
  std::string load, type, shell;
  std::array<double, 3> applied{};
};

// until_rest: the criterion and whether (and when) the run reached rest.
struct RestReport {
  bool reached = false;
  std::optional<double> time;
  double kinetic_energy = 0, speed = 0, duration = 0;
};

// The kinetic energy at every written frame.
struct EnergyHistory {
  std::vector<double> time, kinetic_energy;
};

struct Metrics {
  MeshReport mesh;  // written at the top level of metrics
  double max_collider_penetration = 0, max_collider_penetration_cells = 0;
  double peak_kinetic_energy = 0, final_kinetic_energy = 0, max_plastic_strain = 0;
  std::optional<std::vector<InterfaceReport>> interfaces;
  std::optional<CrackReport> cracks;
  std::optional<double> quadrature_point_steps_per_second, quadrature_point_steps_per_second_per_core;
};

struct Summary {
  std::string shellfrac_version, scene, scene_source;
  int threads = 0;
  std::string status;  // "completed", "failed", "interrupted"
  std::optional<std::string> error;  // why a run failed or stopped
  long steps = 0;
  std::optional<double> dt, dt_min;
  double stable_dt_bound = 0, grid_dx = 0, simulated_seconds = 0;
  std::vector<std::string> frames;  // relative to the run folder
  ParticleCounts particle_counts;
  std::vector<std::pair<std::string, double>> stage_seconds;  // in the order the stages first ran
  Metrics metrics;
  std::optional<std::vector<CrackGraphReport>> crack_graphs;
  std::optional<std::vector<BrittleSolidReport>> brittle;  // scenes with brittle solids
  std::optional<nlohmann::json> shatter;  // scenes with rigid bodies (output/shatter_output.cpp)
  // Verification output (docs/cli.md): probes, pin reactions, applied loads, rest, energy per frame.
  std::vector<ProbeReport> probes;
  std::vector<PinReport> pins;
  std::vector<LoadReport> loads;
  std::optional<RestReport> until_rest;
  EnergyHistory kinetic_energy_history;
  double wall_seconds = 0;
};

// The verification sections of summary.json (output/verification_json.cpp).
void write_verification(const Summary& s, nlohmann::json& j);
void read_verification(const nlohmann::json& j, Summary& s);

// The "brittle" section of summary.json (output/brittle_output.cpp).
nlohmann::json brittle_json(const std::vector<BrittleSolidReport>& reports);
std::vector<BrittleSolidReport> brittle_reports_from_json(const nlohmann::json& j);

nlohmann::json to_json(const Summary& s);
// Reads a summary.json document; throws std::runtime_error naming the missing or mistyped field.
Summary summary_from_json(const nlohmann::json& j);
Summary read_summary(const std::string& path);

}  // namespace shellfrac::output
