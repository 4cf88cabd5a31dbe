#include "brittle/solver.hpp"

#include <Eigen/SVD>
#include <tbb/parallel_for.h>
#include <tbb/parallel_reduce.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "brittle/errors.hpp"
#include "brittle/split_elasticity.hpp"

namespace shellfrac::brittle {

namespace {

class Timer {
 public:
  explicit Timer(double& sink) : sink_(sink), start_(std::chrono::steady_clock::now()) {}
  ~Timer() { pause(); }
  // Stops counting (while a nested stage runs under its own timer) until resume().
  void pause() {
    if (running_) sink_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
    running_ = false;
  }
  void resume() {
    start_ = std::chrono::steady_clock::now();
    running_ = true;
  }

 private:
  bool running_ = true;
  double& sink_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace

const char* to_string(StopReason r) {
  switch (r) {
    case StopReason::None: return "none";
    case StopReason::DamagedFraction: return "damaged_fraction";
    case StopReason::StepCount: return "max_steps";
    case StopReason::Time: return "max_time";
  }
  return "none";
}

BrittleSolver::BrittleSolver(BrittleSolid& solid, SolverOptions options)
    : solid_(solid), options_(options), grid_(options.dx) {
  if (!(options_.dx > 0)) throw InputError("solver: grid spacing dx must be > 0");
  if (options_.dt < 0) throw InputError("solver: dt must be >= 0");
  if (!(options_.cfl > 0)) throw InputError("solver: cfl must be > 0");
  if (solid_.brittleness.size() != solid_.size() || solid_.failure_stress.size() != solid_.size())
    throw InputError("solver: call BrittleSolid::set_strength before solving");
  if (!grid_.set_transfer_isa(options_.transfer_isa))
    throw InputError("solver: the requested instruction set for the grid transfers is not available on this processor");
  fixed_dt_ = options_.dt > 0;
  dt_ = fixed_dt_ ? options_.dt : stable_time_step();
  if (solid_.material.model == DamageModel::PhaseField && options_.damage) {
    phase_field_ = std::make_unique<PhaseFieldSystem>(options_.phase_field, solid_.material.fracture_energy, options_.dx);
    const size_t n = solid_.size();
    const mpm::SolidParticles& q = solid_.particles;
    const double kappa = bulk_modulus(q.material.mu, q.material.lambda);
    pf_c_.resize(n);
    pf_history_.resize(n);
    pf_volume_.resize(n);
    for (size_t p = 0; p < n; ++p) {
      pf_c_[p] = std::clamp(1.0 - solid_.damage[p].c, 0.0, 1.0);
      // The history outlives a solver (a fracture event or the shatter loop builds a new one).
      pf_history_[p] = std::max(solid_.damage[p].history, split_energy(q.F[p], q.material.mu, kappa).tensile);
      solid_.damage[p].history = pf_history_[p];
    }
  }
  if (solid_.material.model == DamageModel::Nacc) {
    nacc_branch_.assign(solid_.size(), static_cast<uint8_t>(NaccCase::Elastic));
    for (const ParticleDamage& d : solid_.damage)
      if (!(d.alpha < 0) && !(d.c_his >= 1.0))
        throw InputError("solver: NACC particles need their hardening state; call BrittleSolid::set_strength");
  }
  if (solid_.material.retire_rubble && options_.damage && solid_.material.model == DamageModel::Rankine) {
    rubble_ = Rubble(solid_.rest, options_.dx);
    retire_rubble();  // a solid may start with damage (a fragment that breaks again)
  }
  damaged_ = solid_.count_damaged();
}

double BrittleSolver::stable_time_step() const {
  const auto& v = solid_.particles.v;
  const double vmax = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, v.size(), 8192), 0.0,
      [&](const tbb::blocked_range<size_t>& r, double m) {
        for (size_t p = r.begin(); p != r.end(); ++p) m = std::max(m, v[p].norm());
        return m;
      },
      [](double a, double b) { return std::max(a, b); });
  return options_.cfl * options_.dx / (solid_.material.wave_speed() + vmax);
}

double BrittleSolver::crack_radius() const { return 3.0 * std::sqrt(3.0) * options_.dx * 1.05; }

void BrittleSolver::add_ghosts(const std::vector<GhostParticle>& ghosts) {
  for (const GhostParticle& g : ghosts) {
    if (g.anchor >= solid_.size()) throw InputError("ghost particle anchored to a particle that does not exist");
    ghosts_.push_back(g);
  }
  if (rubble_.count() > 0) rubble_.reanchor(ghosts_, solid_.rest);
}

void BrittleSolver::set_crack(const TriMesh& crack) {
  Timer t(times_.cracks);
  crack_extracted_ = false;  // a crack from elsewhere: the next update_crack extracts again
  if (!options_.two_fields || crack.triangles.empty()) {
    sides_.clear();
    return;
  }
  sides_.set_crack(crack, solid_.rest, crack_radius(), options_.dx);
}

const CrackExtraction& BrittleSolver::update_crack(const CrackExtractionOptions& options) {
  {
    Timer t(times_.cracks);
    // The extraction is a function of the rest positions and the damage history alone: once damage has
    // stopped growing (most of a long event) the same crack would be extracted again.
    std::vector<double> history = solid_.damage_history();
    if (crack_extracted_ && history == crack_history_) return crack_;
    crack_ = CrackExtraction();
    ++crack_extractions_;
    if (solid_.count_damaged(options.grid.damage_threshold) > 0) crack_ = extract_crack(solid_.rest, history, options);
    crack_history_ = std::move(history);
  }
  set_crack(crack_surface_mesh(crack_));
  crack_extracted_ = true;
  return crack_;
}

double BrittleSolver::damaged_fraction() const {
  return solid_.size() ? static_cast<double>(damaged_) / static_cast<double>(solid_.size()) : 0.0;
}

Vec3 BrittleSolver::momentum() const {
  const double* m = transfer_mass();
  Vec3 p = Vec3::Zero();
  for (size_t i = 0; i < solid_.size(); ++i) p += m[i] * solid_.particles.v[i];
  return p;
}

std::string BrittleSolver::farthest_particle() const {
  const mpm::SolidParticles& q = solid_.particles;
  if (q.size() == 0) return "no particles";
  // Displacement from the rest position less the mean one: the particle that left the rest of the solid.
  Vec3 mean = Vec3::Zero();
  for (size_t p = 0; p < q.size(); ++p) {
    if (!q.x[p].allFinite()) return "particle " + std::to_string(p) + " has a position that is not finite";
    mean += q.x[p] - solid_.rest[p];
  }
  mean /= static_cast<double>(q.size());
  size_t far = 0;
  double far_d = -1;
  for (size_t p = 0; p < q.size(); ++p) {
    const double d = (q.x[p] - solid_.rest[p] - mean).norm();
    if (d > far_d) {
      far_d = d;
      far = p;
    }
  }
  std::ostringstream m;
  m << "the farthest particle from its place in the solid is " << far << " (rest position " << solid_.rest[far].transpose()
    << "), " << far_d << " m off at " << q.v[far].norm() << " m/s, largest damage " << solid_.damage[far].c_his
    << (is_rubble(far) ? ", rubble" : "") << ", at step " << steps_;
  return m.str();
}

void BrittleSolver::retire_rubble() {
  if (rubble_.retire(solid_.particles, solid_.damage) > 0) rubble_.reanchor(ghosts_, solid_.rest);
}

SolidView BrittleSolver::view() {
  SolidView s;
  mpm::SolidParticles& q = solid_.particles;
  s.count = q.size();
  s.x = q.x.data();
  s.v = q.v.data();
  s.m = transfer_mass();
  s.C = q.C.data();
  s.F = q.F.data();
  s.stress = q.stress.data();
  if (sides_.active()) {
    s.mask = sides_.masks();
    s.near_slot = sides_.slots();
    s.near_normal = sides_.normals();
  }
  return s;
}

void BrittleSolver::step() {
  if (!fixed_dt_) dt_ = stable_time_step();
  stage_p2g();
  stage_forces();
  stage_grid_update();
  stage_g2p();
  stage_damage();
}

namespace {
// Fraction of the step [t, t + dt) in which a ghost active on [start, end) acts: the impulse delivered
// is the force times the active time, exactly, whatever the step size.
double active_fraction(const GhostParticle& g, double t, double dt) {
  const double overlap = std::min(t + dt, g.end) - std::max(t, g.start);
  return overlap > 0 ? overlap / dt : 0.0;
}
}  // namespace

void BrittleSolver::stage_p2g() {
  Timer t(times_.p2g);
  ghost_x_.clear();
  for (const GhostParticle& g : ghosts_)
    if (active_fraction(g, time_, dt_) > 0) ghost_x_.push_back(g.rest + (solid_.particles.x[g.anchor] - solid_.rest[g.anchor]));
  try {
    grid_.rebuild(solid_.particles.x.data(), solid_.size(), ghost_x_, sides_.active(), options_.memory_limit);
  } catch (const NumericalError& e) {
    throw NumericalError(std::string(e.what()) + "; " + farthest_particle());
  }
  if (phase_field_) {
    pf_elapsed_ += dt_;  // the solve advances c over every step since the last one
    if (steps_ % options_.phase_field.interval == 0) {
      t.pause();
      stage_phase_field();
      t.resume();
    }
  }
  if (sides_.active()) sides_.classify(grid_, solid_.particles.x.data());
  grid_.transfer_to_grid(view(), dt_);
}

void BrittleSolver::stage_phase_field() {
  Timer t(times_.phase_field);
  mpm::SolidParticles& q = solid_.particles;
  const size_t n = solid_.size();
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 4096), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p != r.end(); ++p) pf_volume_[p] = q.volume[p] * q.F[p].determinant();
  });
  const PhaseFieldParticles view{n, q.x.data(), pf_volume_.data(), pf_history_.data(), pf_c_.data()};
  // Backward Euler over the time since the previous solve: with interval k that is k steps, so c relaxes
  // at the rate M_c whatever k is (with dt_ alone it relaxed k times too slowly, and the pulled bar did
  // not break at k = 100).
  const PhaseFieldStats st = phase_field_->solve(grid_, view, pf_elapsed_ > 0 ? pf_elapsed_ : dt_);
  pf_elapsed_ = 0;
  PhaseFieldTotals& tot = pf_totals_;
  ++tot.solves;
  tot.iterations += st.iterations;
  tot.max_iterations = std::max(tot.max_iterations, st.iterations);
  tot.unconverged += st.converged ? 0 : 1;
  tot.analyses = phase_field_->analyses();
  tot.worst_residual = std::max(tot.worst_residual, st.residual);
  tot.unknowns = st.unknowns;
  // The force of this step sees the new c (seed 001, sec. 4.1 step 2).
  tbb::parallel_for(tbb::blocked_range<size_t>(0, n, 2048), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t p = r.begin(); p != r.end(); ++p) phase_field_stress(p);
  });
}

void BrittleSolver::phase_field_stress(size_t p) {
  mpm::SolidParticles& q = solid_.particles;
  const double mu = q.material.mu, kappa = bulk_modulus(mu, q.material.lambda);
  const double c = pf_c_[p];
  q.stress[p] = q.volume[p] * split_kirchhoff(q.F[p], mu, kappa, degradation(c, options_.phase_field.residual));
  // Damage in the thesis's convention (0 healthy, 1 broken) for crack extraction and the damage time.
  ParticleDamage& d = solid_.damage[p];
  d.c = 1.0 - c;
  if (c <= options_.phase_field.broken_below) d.c_his = 1.0;
  else d.c_his = std::max(d.c_his, d.c);
  if (d.c_his >= 1.0 && d.tau < 0) d.tau = time_;
}

void BrittleSolver::nacc_stress(size_t p) {
  mpm::SolidParticles& q = solid_.particles;
  const double mu = q.material.mu, kappa = bulk_modulus(mu, q.material.lambda);
  const NaccParams& m = solid_.material.nacc;
  ParticleDamage& d = solid_.damage[p];
  // F holds F^E: the trial state after g2p, projected back onto the yield surface (seed 001, sec. 6.2).
  const NaccCase branch = nacc_project(q.F[p], d.alpha, mu, kappa, m);
  nacc_branch_[p] = static_cast<uint8_t>(branch);
  q.stress[p] = q.volume[p] * split_kirchhoff(q.F[p], mu, kappa, 1.0);
  d.c = nacc_damage(d.alpha, kappa, m);
  d.c_his = std::max(d.c_his, d.c);
  if (d.c_his >= 1.0 && d.tau < 0) d.tau = time_;
}

void BrittleSolver::stage_forces() {
  Timer t(times_.forces);
  if (ghost_x_.empty()) return;
  std::vector<Vec3> f;
  std::vector<int> field;
  for (const GhostParticle& g : ghosts_) {
    const double active = active_fraction(g, time_, dt_);
    if (!(active > 0)) continue;
    f.push_back(active * g.force);
    // The ghost acts on the field of its anchor particle's side.
    const int32_t s = sides_.slot(g.anchor);
    const Vec3 xg = g.rest + (solid_.particles.x[g.anchor] - solid_.rest[g.anchor]);
    const long node = grid_.nearest_node(xg);
    field.push_back(s >= 0 && node >= 0 ? sides_.field_at(static_cast<size_t>(node), sides_.normals()[s]) : 0);
  }
  grid_.add_point_forces(ghost_x_, f, field, dt_);
}

void BrittleSolver::stage_grid_update() {
  Timer t(times_.grid_update);
  grid_.update_velocities(dt_, options_.gravity);
  contact_ = FieldContactStats{};
  if (sides_.active() && options_.field_contact) contact_ = grid_.resolve_field_contact();
  grid_.apply_colliders(colliders_, time_ + dt_);
}

void BrittleSolver::stage_g2p() {
  Timer t(times_.g2p);
  grid_.transfer_to_particles(view(), dt_);
  if (!colliders_.empty()) mpm::project_particles(solid_.particles.x, solid_.particles.v, colliders_, time_ + dt_);
  if (rubble_.count() > 0) rubble_.hold(solid_.particles);
  time_ += dt_;
  ++steps_;
}

void BrittleSolver::stage_damage() {
  Timer t(times_.damage);
  mpm::SolidParticles& q = solid_.particles;
  const double mu = q.material.mu, lambda = q.material.lambda;
  const size_t n = solid_.size();
  const DamageRule rule = solid_.material.rule;
  const bool damage = options_.damage;
  const bool nacc = solid_.material.model == DamageModel::Nacc;
  const double now = time_;
  const double stretch_limit = solid_.material.broken_stretch_limit;
  const bool solve_next = phase_field_ && steps_ % options_.phase_field.interval == 0;  // see stage_p2g
  // The first bad particle (inverted or non-finite F) in index order, for the error message.
  const size_t bad = tbb::parallel_reduce(
      tbb::blocked_range<size_t>(0, n, 2048), std::numeric_limits<size_t>::max(),
      [&](const tbb::blocked_range<size_t>& r, size_t first_bad) {
        for (size_t p = r.begin(); p != r.end(); ++p) {
          if (rubble_.contains(p)) continue;  // out of the transfers, held by Rubble::hold
          const Mat3& F = q.F[p];
          const double J = F.determinant();
          if (!(J > 0) || !F.allFinite()) {
            first_bad = std::min(first_bad, p);
            continue;
          }
          if (phase_field_) {
            // Psi^H only grows: the crack cannot close (seed 001, sec. 3.4.2).
            pf_history_[p] = std::max(pf_history_[p], split_energy(F, mu, bulk_modulus(mu, lambda)).tensile);
            solid_.damage[p].history = pf_history_[p];
            // When the next step solves, its phase-field stage sets the stress from the new c and this F
            // (nothing reads the stress before that), so it is computed here only for steps without a solve.
            if (!solve_next) phase_field_stress(p);
          } else if (nacc && damage) {
            nacc_stress(p);
          } else if (damage) {
            // A fully damaged particle has no tensile stress to stop its stretch: bound it (docs/brittle.md).
            if (stretch_limit > 0 && solid_.damage[p].c_his >= 1.0) limit_stretch(q.F[p], stretch_limit);
            q.stress[p] = damage_step(F, q.volume[p], mu, lambda, solid_.failure_stress[p], solid_.brittleness[p], rule,
                                      solid_.material.residual_stiffness, now,
                                      solid_.damage[p]);
          } else
            q.stress[p] = q.volume[p] * neo_hookean_kirchhoff(F, mu, lambda);
        }
        return first_bad;
      },
      [](size_t a, size_t b) { return std::min(a, b); });
  if (bad != std::numeric_limits<size_t>::max()) {
    std::ostringstream m;
    m << "particle " << bad << " (rest position " << solid_.rest[bad].transpose() << ") inverted or diverged at step "
      << steps_ << " (det F = " << q.F[bad].determinant() << ", damage " << solid_.damage[bad].c << ", largest damage "
      << solid_.damage[bad].c_his;
    if (q.F[bad].allFinite())  // the stretches tell a slow runaway (huge) from one bad step (a flip)
      m << ", principal stretches " << Eigen::JacobiSVD<Mat3>(q.F[bad]).singularValues().transpose();
    m << "); lower the time step (cfl) or the loading";
    throw NumericalError(m.str());
  }
  if (nacc && damage) {
    for (const uint8_t b : nacc_branch_) ++nacc_totals_.branch[b];
    ++nacc_totals_.steps;
  }
  if (rubble_.enabled()) retire_rubble();
  damaged_ = solid_.count_damaged();
  const StoppingCriteria& s = options_.stop;
  if (s.damaged_fraction > 0 && damaged_fraction() >= s.damaged_fraction) reason_ = StopReason::DamagedFraction;
  else if (s.max_steps > 0 && steps_ >= s.max_steps) reason_ = StopReason::StepCount;
  else if (s.max_time > 0 && time_ >= s.max_time) reason_ = StopReason::Time;
}

}  // namespace shellfrac::brittle
