#include "output/run.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <climits>
#include <cmath>
#include <cstdio>
#include <ostream>

#include "core/version.hpp"
#include "output/brittle_output.hpp"
#include "output/shatter_output.hpp"
#include "output/frame_render.hpp"
#include "output/interrupt.hpp"
#include "output/mesh_metrics.hpp"
#include "output/progress.hpp"
#include "output/seam_metrics.hpp"
#include "output/step_watchdog.hpp"
#include "output/verification.hpp"
#include "render_mesh/atomic_write.hpp"
#include "render_mesh/cracked_tessellation.hpp"
#include "render_mesh/exporter.hpp"
#include "sim/simulation.hpp"

namespace shellfrac::output {

namespace fs = std::filesystem;

namespace {

// "fracture event of spot: MPM step 2300, 6.10 of 116.4 ms, 812 of 16059 particles fully damaged"
std::string event_detail(const shatter::EventProgress& e) {
  char buf[160];
  std::snprintf(buf, sizeof buf, "MPM step %zu, %.2f of %.1f ms, %zu of %zu particles fully damaged", e.steps,
                1e3 * e.time, 1e3 * e.end_time, e.damaged, e.particles);
  return "fracture event of " + e.body + ": " + buf;
}

std::string frame_stem(int frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%05d", frame);
  return buf;
}

void remove_or_throw(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
  if (ec) throw std::runtime_error("cannot remove " + p.string() + ": " + ec.message());
}

// Makes out_dir/frames/ ready for a run: creates it, removes staging folders that killed runs left
// (render_mesh::StagingDirectory names them ".staging-*"), and unless `keep_old` removes the frames and
// summary of an earlier run, so that the folder never holds frames the summary does not list.
void prepare_output(const fs::path& out_dir, bool keep_old, std::ostream& log) {
  const fs::path frames = out_dir / "frames";
  std::error_code ec;
  fs::create_directories(frames, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + frames.string() + ": " + ec.message());
  size_t stale = 0, old = 0;
  for (const auto& entry : fs::directory_iterator(frames)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(".staging-", 0) == 0) {
      remove_or_throw(entry.path());
      ++stale;
    } else if (!keep_old && name.rfind("frame_", 0) == 0 && entry.is_regular_file()) {
      remove_or_throw(entry.path());
      ++old;
    }
  }
  if (!keep_old && fs::exists(out_dir / "summary.json")) remove_or_throw(out_dir / "summary.json");
  if (stale) log << "removed " << stale << " staging folder(s) left by an interrupted run in " << frames.string() << "\n";
  if (old) log << "removed " << old << " file(s) of an earlier run from " << frames.string() << " (--keep-old-frames keeps them)\n";
}

// Writes the frames of a run and keeps what is measured on them.
class FrameWriter {
 public:
  FrameWriter(const scene::Model& model, fs::path out_dir) : model_(model), out_dir_(std::move(out_dir)), seams_(model) {}

  void write(const sim::Simulation& sim, int frame) {
    auto scope = timer_.time("output");
    SeamCrackPositions cracks;
    for (size_t i = 0; i < model_.interfaces.size(); ++i) cracks.push_back(sim.seam_cracks(i));
    seams_.record(frame, sim.time(), sim.world(), cracks);
    const FrameMeshes meshes = renderer_.render(sim);
    record_quality(measure_mesh_quality(sim, meshes), frame);
    penetration_ = std::max(penetration_, collider_penetration(sim, meshes.meshes));
    const render_mesh::ExportOptions options{model_.output.triangulate, model_.output.double_precision};
    const fs::path written =
        render_mesh::export_meshes(meshes.meshes, frames_dir(), frame_stem(frame), model_.output.format, options);
    files_.push_back(fs::relative(written, out_dir_).string());
  }

  const std::vector<std::string>& files() const { return files_; }
  double penetration() const { return penetration_; }
  const MeshReport& mesh() const { return mesh_; }
  const sim::StageTimer& timer() const { return timer_; }
  const SeamRecorder& seams() const { return seams_; }

 private:
  fs::path frames_dir() const { return out_dir_ / "frames"; }
  FrameRenderer renderer_;  // keeps cracked patches' vertex bases between frames
  void record_quality(const MeshQuality& q, int frame) {
    mesh_.pieces = q.pieces;
    mesh_.sliver_count = q.slivers;
    mesh_.sliver_area = q.sliver_area;
    mesh_.piece_areas = q.piece_areas;
    mesh_.max_edge_stretch = q.max_edge_stretch;
    mesh_.strand_area = q.strand_area;
    mesh_.strand_faces = q.strand_faces;
    if (q.max_edge_stretch > mesh_.peak_edge_stretch) {
      mesh_.peak_edge_stretch = q.max_edge_stretch;
      mesh_.peak_edge_stretch_frame = frame;
    }
    mesh_.peak_strand_area = std::max(mesh_.peak_strand_area, q.strand_area);
  }

  const scene::Model& model_;
  fs::path out_dir_;
  SeamRecorder seams_;  // metrics.interfaces
  sim::StageTimer timer_;
  std::vector<std::string> files_;
  double penetration_ = 0;
  MeshReport mesh_;
};

CrackReport crack_report(const sim::Simulation& sim) {
  const sim::CrackStats& c = sim.crack_stats();
  CrackReport r;
  static_cast<sim::CrackCounters&>(r) = c;
  for (size_t i = 0; i < sim.world().num_shells(); ++i) {
    const shell::ShellPatch& p = sim.world().shell(i);
    r.max_damage = std::max(r.max_damage, p.fractures() ? p.max_damage() : 0.0);
  }
  if (!c.first_mls_failure.empty()) r.first_mls_failure = c.first_mls_failure;
  if (!c.first_sliver.empty()) r.first_sliver = c.first_sliver;
  shell::BasisCensus total;
  for (size_t i = 0; i < sim.world().num_shells(); ++i) {
    const shell::BasisCensus& b = sim.world().shell(i).census();
    for (int l = 0; l < shell::kNumBasisLevels; ++l) {
      total.points[static_cast<size_t>(l)] += b.points[static_cast<size_t>(l)];
      total.shear[static_cast<size_t>(l)] += b.shear[static_cast<size_t>(l)];
    }
    total.nudged += b.nudged;
    total.membrane_only += b.membrane_only;
    total.rigid_area += b.rigid_area;
    total.rigid_mass += b.rigid_mass;
    total.removed_area += b.removed_area;
    total.removed_mass += b.removed_mass;
  }
  for (int l = 0; l < shell::kNumBasisLevels; ++l) {
    const char* name = shell::basis_level_name(static_cast<shell::BasisLevel>(l));
    r.basis_points.emplace_back(name, total.points[static_cast<size_t>(l)]);
    r.basis_shear.emplace_back(name, total.shear[static_cast<size_t>(l)]);
  }
  r.nudged = total.nudged;
  r.membrane_only = total.membrane_only;
  r.slivers = total.slivers();
  r.rigid_area = total.rigid_area;
  r.rigid_mass = total.rigid_mass;
  r.removed_area = total.removed_area;
  r.removed_mass = total.removed_mass;
  for (size_t i = 0; i < sim.world().num_shells(); ++i) {
    const shell::ShellPatch& p = sim.world().shell(i);
    const double added = p.added_mass_total(), mass = p.control_mass_total();
    r.added_mass += added;
    if (mass > 0) r.added_mass_share = std::max(r.added_mass_share, added / mass);
  }
  return r;
}

// The crack graphs in parameter coordinates (for plots and checks).
std::vector<CrackGraphReport> crack_graphs(const sim::Simulation& sim) {
  std::vector<CrackGraphReport> graphs;
  for (size_t i = 0; i < sim.world().num_shells(); ++i) {
    const crack2d::CrackGraph* g = sim.crack_graph(i);
    if (!g) continue;
    CrackGraphReport report;
    report.shell = sim.world().shell_name(i);
    for (const auto& v : g->vertices()) report.vertices.push_back({v.x(), v.y()});
    for (const auto& e : g->edges()) report.edges.push_back({e[0], e[1]});
    graphs.push_back(std::move(report));
  }
  return graphs;
}

// The record of a run so far.
Summary make_summary(const sim::Simulation& sim, const FrameWriter& frames, int threads, double peak_kinetic,
                     const std::string& status) {
  const scene::Model& model = sim.model();
  Summary s;
  s.shellfrac_version = kVersion;
  s.scene = model.name;
  s.scene_source = model.source;
  s.threads = threads;
  s.status = status;
  s.steps = sim.steps();
  if (sim.steps()) {
    s.dt = sim.max_dt();
    s.dt_min = sim.min_dt();
  }
  s.stable_dt_bound = model.time.cfl * sim.current_elastic_wave_bound();
  s.grid_dx = sim.dx();
  s.simulated_seconds = sim.time();
  s.frames = frames.files();
  s.particle_counts = {sim.num_solid_particles(), sim.num_control_points(), sim.num_shear_particles(),
                       sim.num_quadrature_points()};
  double step_seconds = 0;
  for (const auto& [name, seconds] : sim.timer().seconds()) {
    s.stage_seconds.emplace_back(name, seconds);
    step_seconds += seconds;
  }
  for (const auto& stage : frames.timer().seconds()) s.stage_seconds.push_back(stage);
  Metrics& m = s.metrics;
  m.mesh = frames.mesh();
  m.max_collider_penetration = frames.penetration();
  m.max_collider_penetration_cells = frames.penetration() / sim.dx();
  m.peak_kinetic_energy = peak_kinetic;
  m.final_kinetic_energy = sim.kinetic_energy();
  for (size_t i = 0; i < sim.world().num_shells(); ++i)
    m.max_plastic_strain = std::max(m.max_plastic_strain, sim.world().shell(i).max_plastic_strain());
  if (frames.seams().active()) m.interfaces = frames.seams().reports();
  if (model.has_cracks()) {
    m.cracks = crack_report(sim);
    s.crack_graphs = crack_graphs(sim);
  }
  if (step_seconds > 0) {
    const double qps = static_cast<double>(sim.num_quadrature_points()) * static_cast<double>(sim.steps()) / step_seconds;
    m.quadrature_point_steps_per_second = qps;
    m.quadrature_point_steps_per_second_per_core = qps / threads;
  }
  return s;
}

// What a user should look at before rendering the frames.
void warn_about_run(const Summary& s, std::ostream& log) {
  if (s.metrics.cracks && s.metrics.cracks->mls_failures > 0)
    log << "warning: " << s.metrics.cracks->mls_failures << " point(s) near cracks were left without a basis ("
        << s.metrics.cracks->first_mls_failure.value_or("") << "); see metrics.cracks.mls_failures in docs/cli.md\n";
  if (s.metrics.cracks && s.metrics.cracks->slivers > 0)
    log << "warning: " << s.metrics.cracks->slivers << " point(s) lie in crack-isolated pieces too small for a basis ("
        << s.metrics.cracks->rigid_area << " m^2 rigid, " << s.metrics.cracks->removed_area
        << " m^2 removed; first: " << s.metrics.cracks->first_sliver.value_or("") << ")\n";
  const MeshReport& m = s.metrics.mesh;
  if (m.sliver_count > 0)
    log << "warning: the last frame has " << m.sliver_count << " sliver(s) smaller than a grid cell (" << m.sliver_area
        << " m^2 in all; metrics.slivers)\n";
  if (m.strand_faces > 0)
    log << "warning: the last frame has " << m.strand_faces << " render face(s) stretched beyond the strand threshold ("
        << m.strand_area << " m^2; largest edge stretch " << m.max_edge_stretch
        << "): material that joins pieces, see metrics.strand_area in docs/cli.md\n";
}

// What stepping towards a frame time ended with.
enum class FrameEnd { reached, stopped, resting };

// The run's frames: the steps to every frame time, taken here so that progress, callbacks and interrupts
// see every step (sim/ does no I/O), then the frame's files. Ends early when a stop is requested, the
// scene comes to rest (time.until_rest) or only broken brittle solids are left.
struct FrameLoop {
  const scene::Model& model;
  const RunOptions& options;
  sim::Simulation& sim;
  FrameWriter& frames;
  BrittleWriter& brittle;
  ShatterWriter& shatter;
  VerificationRecorder& verification;
  StepWatchdog& watchdog;
  Progress& progress;
  int last_frame;
  double peak_kinetic = 0;

  bool stop_requested() const { return interrupt_signal() != 0 || (options.should_stop && options.should_stop()); }

  std::string where(int f) const {
    return "frame " + std::to_string(f) + "/" + std::to_string(last_frame) + ", step " + std::to_string(sim.steps());
  }

  void write_frame(int f) {
    watchdog.record(sim.time(), f, last_frame, sim.steps(), StepWatchdog::Activity::writing_frame);
    frames.write(sim, f);
    shatter.write_frame(sim, f);
    verification.at_frame(sim, f);
  }

  // The steps of sim.advance_to(t); advance_to then only lands the clock exactly on the frame time.
  FrameEnd step_to(double t, int f) {
    while (sim.time() < t - 1e-12 * std::max(1.0, t)) {
      if (stop_requested()) return FrameEnd::stopped;
      const double remaining = t - sim.time();
      const double n = std::ceil(remaining / sim.stable_dt() - 1e-9);
      watchdog.record(sim.time(), f, last_frame, sim.steps(), StepWatchdog::Activity::stepping);
      sim.step(n <= 1 ? remaining : remaining / n);
      const bool resting = verification.after_step(sim);
      if (options.on_step) options.on_step(StepReport{sim.steps(), sim.time(), model.time.end, f, last_frame});
      if (progress.due()) progress.update(sim.time(), where(f));
      if (resting) return FrameEnd::resting;  // time.until_rest: the last frame holds the state at rest
    }
    return FrameEnd::reached;
  }

  // True when a stop request ended the run.
  bool run() {
    write_frame(0);
    for (int f = 1; f <= last_frame; ++f) {
      const double t = scene::model::frame_time(f, model.time.end, model.time.frame_rate);
      const FrameEnd end = step_to(t, f);
      if (end == FrameEnd::stopped) return true;
      if (end == FrameEnd::reached) sim.advance_to(t);
      peak_kinetic = std::max(peak_kinetic, sim.kinetic_energy());
      write_frame(f);
      progress.update(sim.time(), where(f));
      brittle.write_new_events(sim);
      if (sim.finished()) return false;  // only brittle solids, all broken
      if (stop_requested()) return true;
      if (end == FrameEnd::resting) return false;
    }
    return false;
  }
};

}  // namespace

Summary run_scene(const scene::Model& model, const RunOptions& options, std::ostream& log) {
  const auto start = std::chrono::steady_clock::now();
  if (options.out_dir.empty()) throw core::InputError("the output folder (--out) must not be empty");
  const double frame_count = scene::model::frames_after_start(model.time.end, model.time.frame_rate) + 1;
  if (!(frame_count < INT_MAX))
    throw core::InputError(model.source + ": /time/end: the run would write more than " + std::to_string(INT_MAX) + " frames");
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));

  // A last, shorter frame at `end` when it is not on a frame boundary (scene::model::frames_after_start).
  const int last_frame = static_cast<int>(frame_count) - 1;
  Progress progress(log, options.interactive, model.time.end > 0 ? model.time.end : 1.0, "s");
  // Progress lines also while the set-up, a single step or an export runs long.
  StepWatchdog watchdog(progress);
  using Activity = StepWatchdog::Activity;
  watchdog.record(0, 0, last_frame, 0, Activity::setting_up);
  sim::Simulation sim(model);  // may throw SceneError (e.g. dt above the stability bound) before any output
  prepare_output(options.out_dir, options.keep_old_frames, log);
  FrameWriter frames(model, options.out_dir);
  BrittleWriter brittle(model, options.out_dir);  // fracture events of brittle solids (docs/brittle.md)
  ShatterWriter shatter(model, options.out_dir);  // rigid bodies and their fragments per frame
  std::string animation;                          // their glTF animation, once the run ends
  VerificationRecorder verification(sim, options.out_dir);  // probes, reactions, rest (docs/cli.md)
  FrameLoop loop{model, options, sim, frames, brittle, shatter, verification, watchdog, progress, last_frame};
  auto finish = [&](const std::string& status, const std::string& error) {
    Summary s = make_summary(sim, frames, threads, loop.peak_kinetic, status);
    if (!error.empty()) s.error = error;
    if (!model.brittle_solids.empty()) s.brittle = brittle.reports(sim);
    if (!sim.shatter().empty()) s.shatter = shatter_json(sim.shatter().loop(), shatter.frames(), animation);
    verification.finish(sim, s);
    s.wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    render_mesh::write_file_atomically(options.out_dir / "summary.json", to_json(s).dump(2) + "\n");
    return s;
  };
  // A fracture event of the shatter loop can run for minutes inside one step: its MPM steps show in the
  // progress lines, and Ctrl-C abandons it (the body stays whole) instead of waiting for its end.
  sim.set_event_observer([&](const shatter::EventProgress& e) {
    watchdog.record_detail(event_detail(e));
    return !loop.stop_requested();
  });

  bool stopped = false;
  try {
    stopped = loop.run();
    sim.finish_brittle();
    brittle.write_new_events(sim);
    animation = shatter.write_animation(sim);
  } catch (const core::NumericalError& e) {
    finish("failed", e.what());
    throw;
  } catch (const std::exception& e) {
    // An I/O failure (a full disk, say): the frames written so far stay; record the failure if the disk
    // still takes a summary, and report the original error either way.
    try {
      finish("failed", e.what());
    } catch (const std::exception&) {
    }
    throw;
  }
  if (stopped) {
    const int signal = interrupt_signal();
    const std::string by = signal ? std::string("by ") + signal_name(signal) : std::string("on request");
    progress.finish("interrupted " + by + " at t = " + std::to_string(sim.time()) + " s, " +
                    std::to_string(frames.files().size()) + " frames kept");
    Summary summary = finish("interrupted", "interrupted " + by + " at t = " + std::to_string(sim.time()) + " s");
    return summary;
  }
  progress.finish(std::to_string(frames.files().size()) + " frames, " + std::to_string(sim.steps()) + " steps");
  const Summary summary = finish("completed", "");
  warn_about_run(summary, log);
  return summary;
}

}  // namespace shellfrac::output
