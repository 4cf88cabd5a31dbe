#include "sim/run.hpp"

#include <tbb/global_control.h>
#include <tbb/info.h>

#include <chrono>
#include <cmath>
#include <ostream>
#include <sstream>

#include "render_mesh/atomic_write.hpp"
#include "render_mesh/cracked_tessellation.hpp"
#include "render_mesh/exporter.hpp"
#include "sim/progress.hpp"
#include "sim/scene_error.hpp"
#include "sim/seam_metrics.hpp"
#include "sim/simulation.hpp"
#include "sim/version.hpp"

namespace shellfrac::sim {

namespace fs = std::filesystem;

namespace {

std::string frame_stem(int frame) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "frame_%05d", frame);
  return buf;
}

}  // namespace

std::string describe_scene(const Scene& scene) {
  std::ostringstream os;
  int control_points = 0;
  for (const Shell& s : scene.shells) control_points += s.surface.num_u() * s.surface.num_v();
  os << "scene \"" << scene.name << "\": " << scene.shells.size() << " shell(s), " << control_points
     << " control points, " << scene.solids.size() << " solid(s), " << scene.colliders.size() << " collider(s), "
     << scene.pins.size() << " pin(s), end time "
     << scene.time.end << " s at " << scene.time.frame_rate << " frames/s, output " << scene.output.format << " at "
     << scene.output.resolution_u << " x " << scene.output.resolution_v << " quads per patch\n";
  for (const Shell& s : scene.shells) {
    os << "  " << s.name << ": " << s.shape << " patch, " << s.surface.num_u() << " x " << s.surface.num_v()
       << " control points (degree " << s.surface.knots_u().degree() << " x " << s.surface.knots_v().degree() << ", "
       << s.surface.knots_u().num_spans() << " x " << s.surface.knots_v().num_spans() << " cells)"
       << (s.surface.is_rational() ? ", rational" : "") << ", thickness " << s.thickness << " m, "
       << s.material.model << " E=" << s.material.youngs_modulus << " nu=" << s.material.poisson_ratio
       << " rho=" << s.material.density << (s.material.plasticity.enabled ? ", plastic" : "")
       << (s.material.fracture.enabled ? ", fracturing (sigma_f=" : "");
    if (s.material.fracture.enabled)
      os << s.material.fracture.failure_stress << " Pa, G_f=" << s.material.fracture.fracture_energy << " J/m^2, "
         << (s.material.fracture.rule == shell::DamageRule::Monotone ? "monotone" : "healing") << " damage)";
    os << (s.cuts.empty() ? "" : ", " + std::to_string(s.cuts.size()) + " prescribed cut(s)") << "\n";
  }
  for (const SolidBody& b : scene.solids)
    os << "  " << b.name << ": " << b.shape << " solid, particle spacing " << b.spacing << " m ("
       << (b.poisson_disk ? "Poisson disk" : "jittered grid") << "), E=" << b.material.youngs_modulus
       << " nu=" << b.material.poisson_ratio << " rho=" << b.material.density << "\n";
  return os.str();
}

nlohmann::json run_scene(const Scene& scene, const RunOptions& options, std::ostream& log) {
  const auto start = std::chrono::steady_clock::now();
  const int threads = options.threads > 0 ? options.threads : tbb::info::default_concurrency();
  tbb::global_control thread_limit(tbb::global_control::max_allowed_parallelism, static_cast<size_t>(threads));

  Simulation sim(scene);  // may throw SceneError (e.g. dt above the stability bound) before any output

  const fs::path frames_dir = options.out_dir / "frames";
  std::error_code ec;
  fs::create_directories(frames_dir, ec);
  if (ec) throw std::runtime_error("cannot create output directory " + frames_dir.string() + ": " + ec.message());

  const int last_frame = static_cast<int>(std::floor(scene.time.end * scene.time.frame_rate + 1e-9));
  nlohmann::json frames = nlohmann::json::array();
  double penetration = 0, peak_kinetic = 0;
  long fragments = 0;  // connected components of the shells' render meshes in the last frame
  StageTimer output_timer;
  SeamRecorder seams(scene);  // metrics.interfaces
  auto write_frame = [&](int f) {
    auto scope = output_timer.time("output");
    SeamCrackPositions cracks;
    for (size_t i = 0; i < scene.interfaces.size(); ++i) cracks.push_back(sim.seam_cracks(i));
    seams.record(f, sim.time(), sim.patches(), cracks);
    const auto meshes = sim.render_meshes();
    fragments = 0;
    for (size_t i = 0; i < scene.shells.size(); ++i) fragments += render_mesh::count_components(meshes[i]);
    penetration = std::max(penetration, sim.collider_penetration(meshes));
    const fs::path written = render_mesh::export_meshes(meshes, frames_dir, frame_stem(f), scene.output.format);
    frames.push_back(fs::relative(written, options.out_dir).string());
  };

  nlohmann::json summary;
  summary["shellfrac_version"] = kVersion;
  summary["scene"] = scene.name;
  summary["scene_source"] = scene.source;
  summary["threads"] = threads;
  auto finish_summary = [&](const std::string& status) {
    summary["status"] = status;
    summary["steps"] = sim.steps();
    summary["dt"] = sim.steps() ? nlohmann::json(sim.max_dt()) : nlohmann::json(nullptr);
    summary["dt_min"] = sim.steps() ? nlohmann::json(sim.min_dt()) : nlohmann::json(nullptr);
    summary["stable_dt_bound"] = scene.time.cfl * sim.elastic_wave_bound();
    summary["grid_dx"] = sim.dx();
    summary["simulated_seconds"] = sim.time();
    summary["frames"] = frames;
    summary["particle_counts"] = {{"solid_particles", sim.num_solid_particles()},
                                  {"control_points", sim.num_control_points()},
                                  {"shear_particles", sim.num_shear_particles()},
                                  {"quadrature_points", sim.num_quadrature_points()}};
    nlohmann::json stages = nlohmann::json::object();
    double step_seconds = 0;
    for (const auto& [name, seconds] : sim.timer().seconds()) {
      stages[name] = seconds;
      step_seconds += seconds;
    }
    for (const auto& [name, seconds] : output_timer.seconds()) stages[name] = seconds;
    summary["stage_seconds"] = stages;
    nlohmann::json metrics = nlohmann::json::object();
    metrics["max_collider_penetration"] = penetration;
    metrics["max_collider_penetration_cells"] = penetration / sim.dx();
    metrics["peak_kinetic_energy"] = peak_kinetic;
    metrics["final_kinetic_energy"] = sim.kinetic_energy();
    double plastic = 0;
    for (const auto& p : sim.patches()) plastic = std::max(plastic, p.max_plastic_strain());
    metrics["max_plastic_strain"] = plastic;
    if (seams.active()) metrics["interfaces"] = seams.to_json();
    if (scene.has_cracks()) {
      const CrackStats& c = sim.crack_stats();
      double max_damage = 0;
      for (const auto& p : sim.patches()) max_damage = std::max(max_damage, p.fractures() ? p.max_damage() : 0.0);
      metrics["cracks"] = {{"extractions", c.extractions},
                           {"subset_violations", c.subset_violations},
                           {"crack_segments", c.crack_edges},
                           {"mls_points", c.mls_points},
                           {"mls_failures", c.mls_failures},
                           {"max_split_nodes", c.max_split_nodes},
                           {"contact_pairs", c.contact_pairs},
                           {"max_contact_residual", c.max_contact_residual},
                           {"seam_continuations", c.seam_continuations},
                           {"body_fragments", sim.body_fragments()},
                           {"max_damage", max_damage},
                           {"fragments", fragments}};
      if (!c.first_mls_failure.empty()) metrics["cracks"]["first_mls_failure"] = c.first_mls_failure;
      // The crack graphs themselves, in parameter coordinates (for plots and checks).
      nlohmann::json graphs = nlohmann::json::array();
      for (size_t i = 0; i < scene.shells.size(); ++i) {
        const crack2d::CrackGraph* g = sim.crack_graph(i);
        if (!g) continue;
        nlohmann::json vertices = nlohmann::json::array(), edges = nlohmann::json::array();
        for (const auto& v : g->vertices()) vertices.push_back({v.x(), v.y()});
        for (const auto& e : g->edges()) edges.push_back({e[0], e[1]});
        graphs.push_back({{"shell", scene.shells[i].name}, {"vertices", vertices}, {"edges", edges}});
      }
      summary["crack_graphs"] = graphs;
    }
    if (step_seconds > 0) {
      const double qps = static_cast<double>(sim.num_quadrature_points()) * static_cast<double>(sim.steps()) / step_seconds;
      metrics["quadrature_point_steps_per_second"] = qps;
      metrics["quadrature_point_steps_per_second_per_core"] = qps / threads;
    }
    summary["metrics"] = metrics;
    summary["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    render_mesh::write_file_atomically(options.out_dir / "summary.json", summary.dump(2) + "\n");
  };

  Progress progress(log, options.interactive, scene.time.end > 0 ? scene.time.end : 1.0, "s");
  try {
    write_frame(0);
    for (int f = 1; f <= last_frame; ++f) {
      sim.advance_to(f / scene.time.frame_rate);
      peak_kinetic = std::max(peak_kinetic, sim.kinetic_energy());
      write_frame(f);
      progress.update(sim.time(), "frame " + std::to_string(f) + "/" + std::to_string(last_frame) + ", step " +
                                      std::to_string(sim.steps()));
    }
  } catch (const NumericalError& e) {
    summary["error"] = e.what();
    finish_summary("failed");
    throw;
  }
  progress.finish(std::to_string(last_frame + 1) + " frames, " + std::to_string(sim.steps()) + " steps");
  finish_summary("completed");
  return summary;
}

}  // namespace shellfrac::sim
