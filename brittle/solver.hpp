#pragma once
#include <array>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "brittle/brittle_solid.hpp"
#include "brittle/crack_sides.hpp"
#include "brittle/crack_surface.hpp"
#include "brittle/impact.hpp"
#include "brittle/phase_field.hpp"
#include "brittle/rubble.hpp"
#include "brittle/solid_grid.hpp"
#include "mpm/colliders.hpp"

namespace shellfrac::brittle {

// When a fracture run ends (thesis sec. 3.2, Table 3.3 MPM_dthresh): whichever criterion is met first.
struct StoppingCriteria {
  double damaged_fraction = 0;  // stop once this fraction of particles has c_his >= 1 (0 = off)
  size_t max_steps = 0;         // (0 = off)
  double max_time = 0;          // [s] (0 = off)
};

enum class StopReason { None, DamagedFraction, StepCount, Time };
const char* to_string(StopReason r);

struct SolverOptions {
  double dx = 0;               // MPM grid spacing h
  double dt = 0;               // time step; 0 = cfl * dx / (P-wave speed + max particle speed)
  double cfl = 0.3;
  Vec3 gravity = Vec3::Zero();
  bool damage = true;          // Rankine damage (thesis sec. 2.3); off = elastic
  bool two_fields = true;      // two velocity fields across extracted cracks (sec. 3.4); off = single field
  bool field_contact = true;   // normal contact between the fields (Eq. 3.6-3.7)
  StoppingCriteria stop;
  size_t memory_limit = size_t{4} << 30;  // bytes the dense grid may take
  // Instruction set of the p2g/g2p kernels (Auto: AVX2 with FMA where the processor has them); results
  // differ between sets by round-off only. The solver refuses a set the processor lacks.
  SolidGrid::TransferIsa transfer_isa = SolidGrid::TransferIsa::Auto;
  // The phase field's parameters and solver, used when the material's model is DamageModel::PhaseField.
  PhaseFieldOptions phase_field;
};

// Seconds spent in each stage since construction (wall clock, for summary.json).
struct StageTimes {
  double p2g = 0, forces = 0, grid_update = 0, g2p = 0, damage = 0, cracks = 0, phase_field = 0;
  double total() const { return p2g + forces + grid_update + g2p + damage + cracks + phase_field; }
};

// Counters of the phase-field solves since construction.
struct PhaseFieldTotals {
  size_t solves = 0;
  size_t iterations = 0;     // CG iterations, summed
  size_t max_iterations = 0; // the most in one solve
  size_t unconverged = 0;    // solves that stopped at max_iterations
  size_t analyses = 0;       // CHOLMOD symbolic analyses
  double worst_residual = 0; // largest |b - A c| / |b|
  size_t unknowns = 0;       // free nodes of the last solve
};

// Particle-steps through each branch of the NACC return mapping since construction.
struct NaccTotals {
  size_t steps = 0;
  std::array<size_t, 4> branch{};  // indexed by NaccCase: elastic, compression, tension, shear
};

// Advances one brittle solid with damage and (optionally) two velocity fields through named stages:
//   p2g          grid rebuild, crack-side classification, mass/momentum/MLS-stress scatter (Eq. 2.23,
//                2.24, 3.3-3.5)
//   forces       impact loads through ghost particles (Eq. 3.12)
//   grid_update  velocities and gravity (Eq. 2.19), field contact (Eq. 3.6-3.7), colliders
//   g2p          particle velocity, affine C, F and position (Eq. 2.20, 2.25, 2.26, 2.21); collider
//                projection of particles
//   damage       Rankine: effective stress, c, c_his, tau_p and the weakened stress (Eq. 2.28-2.31);
//                phase field: the history Psi^H and the degraded stress at the new F;
//                NACC: the return mapping of F^E and alpha, the stress of Eq. 10, damage from alpha
// step() runs them in this order. With the phase-field model, p2g first solves the grid phase field
// from F^n (seed 001, Eq. 7; every options.phase_field.interval steps, timed as "phase_field") and
// scatters the stress degraded by the new c: the staggered scheme of seed 001, sec. 4.3. Crack extraction is not a stage of the step: the caller extracts a
// crack surface from the damage history (extract_crack_surface) when it wants and hands it to set_crack,
// which re-classifies the particles for the two fields.
class BrittleSolver {
 public:
  BrittleSolver(BrittleSolid& solid, SolverOptions options);

  void add_collider(mpm::Collider collider) { colliders_.push_back(std::move(collider)); }
  // Adds the ghost particles of an impact (see impact_ghosts).
  void add_ghosts(const std::vector<GhostParticle>& ghosts);
  const std::vector<GhostParticle>& ghosts() const { return ghosts_; }
  // Crack surface (material space) for the two velocity fields; an empty mesh returns to one field.
  void set_crack(const TriMesh& crack);
  // Crack extraction on demand (thesis sec. 3.3, every ten steps in sec. 3.8): extracts the crack from
  // the current damage history and hands it to set_crack. Timed as the "cracks" stage.
  // Skipped (the last result returned) while the damage history is the one of the last extraction; callers
  // pass the same options every time.
  const CrackExtraction& update_crack(const CrackExtractionOptions& options);
  size_t crack_extractions() const { return crack_extractions_; }  // update_crack calls that extracted
  double crack_radius() const;  // material distance within which particles are classified

  void step();
  void stage_p2g();
  void stage_forces();
  void stage_grid_update();
  void stage_g2p();
  void stage_damage();
  void stage_phase_field();

  // Stops when a criterion of options().stop is met (checked after each step's damage stage).
  bool should_stop() const { return reason_ != StopReason::None; }
  StopReason stop_reason() const { return reason_; }
  double time() const { return time_; }
  size_t steps() const { return steps_; }
  double dt() const { return dt_; }
  size_t damaged_count() const { return damaged_; }
  // Particles taken out of the transfers as rubble (material.retire_rubble); 0 when that is off.
  size_t rubble_count() const { return rubble_.count(); }
  bool is_rubble(size_t p) const { return rubble_.contains(p); }
  // Ghost particles moved off rubble onto the nearest particle that is not (Rubble::reanchor).
  size_t reanchored_ghosts() const { return rubble_.reanchored_ghosts(); }
  // The momentum the rubble had when it left the transfers: momentum() plus this is the momentum the
  // loads delivered.
  Vec3 rubble_momentum() const { return rubble_.momentum(); }
  double damaged_fraction() const;
  const SolverOptions& options() const { return options_; }
  const SolidGrid& grid() const { return grid_; }
  const CrackSides& sides() const { return sides_; }
  const StageTimes& times() const { return times_; }
  FieldContactStats last_contact() const { return contact_; }
  const PhaseFieldTotals& phase_field_totals() const { return pf_totals_; }
  bool phase_field() const { return phase_field_ != nullptr; }
  const NaccTotals& nacc_totals() const { return nacc_totals_; }
  // c_p of the phase field (1 healthy, 0 broken); empty for Rankine damage.
  const std::vector<double>& phase() const { return pf_c_; }
  BrittleSolid& solid() { return solid_; }
  // Total linear momentum sum m v of the particles that take part in the transfers (not rubble).
  Vec3 momentum() const;
  // Stable time step for the current state: cfl dx / (P-wave speed + largest particle speed).
  double stable_time_step() const;
  void mark_fixed_time_step() { fixed_dt_ = true; }

 private:
  SolidView view();
  // Degraded stress and damage state of particle p from its phase value (phase-field model).
  void phase_field_stress(size_t p);
  // NACC return mapping of particle p's F^E, its stress and damage from alpha.
  void nacc_stress(size_t p);
  // Takes the particles that have become rubble out of the transfers (material.retire_rubble) and moves
  // the ghosts anchored on them.
  void retire_rubble();
  const double* transfer_mass() const { return rubble_.transfer_mass(solid_.particles); }
  // Which particle has left the solid farthest, for the message of a grid that would not fit.
  std::string farthest_particle() const;
  BrittleSolid& solid_;
  SolverOptions options_;
  SolidGrid grid_;
  CrackSides sides_;
  std::vector<mpm::Collider> colliders_;
  std::vector<GhostParticle> ghosts_;
  std::vector<Vec3> ghost_x_;
  double time_ = 0, dt_ = 0;
  bool fixed_dt_ = false;
  size_t steps_ = 0, damaged_ = 0;
  StopReason reason_ = StopReason::None;
  StageTimes times_;
  FieldContactStats contact_;
  // Phase-field model: the grid system, c_p, Psi^H_p and the current volumes V^0 J.
  std::unique_ptr<PhaseFieldSystem> phase_field_;
  std::vector<double> pf_c_, pf_history_, pf_volume_;
  double pf_elapsed_ = 0;  // simulated time since the last phase-field solve [s]
  PhaseFieldTotals pf_totals_;
  // NACC: the branch each particle took in the last damage stage.
  std::vector<uint8_t> nacc_branch_;
  NaccTotals nacc_totals_;
  Rubble rubble_;  // empty unless material.retire_rubble
  // The last crack update: its extraction and the damage history it was extracted from.
  CrackExtraction crack_;
  std::vector<double> crack_history_;
  bool crack_extracted_ = false;
  size_t crack_extractions_ = 0;
};

}  // namespace shellfrac::brittle
