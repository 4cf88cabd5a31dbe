#include "output/verification.hpp"

#include <cstdio>
#include <sstream>

#include "core/format.hpp"
#include "render_mesh/atomic_write.hpp"

namespace shellfrac::output {

namespace fs = std::filesystem;

namespace {

// Every digit a double needs to read back exactly.
std::string number(double x) { return core::format_number(x, 17); }

std::array<double, 3> arr(const Eigen::Vector3d& v) { return {v.x(), v.y(), v.z()}; }

const char* load_type(scene::model::Load::Kind k) {
  using Kind = scene::model::Load::Kind;
  return k == Kind::Pressure ? "pressure" : k == Kind::Point ? "point" : k == Kind::Edge ? "edge" : "body";
}

}  // namespace

VerificationRecorder::VerificationRecorder(const sim::Simulation& sim, fs::path out_dir)
    : model_(sim.model()), out_dir_(std::move(out_dir)), probes_(sim.model(), sim.world()), samples_(probes_.size()) {}

void VerificationRecorder::sample(const sim::Simulation& sim, bool step) {
  for (size_t i = 0; i < probes_.size(); ++i)
    if (model_.output.probes[i].every_step == step) samples_[i].push_back(probes_.sample(i, sim.world(), sim.time()));
}

bool VerificationRecorder::after_step(const sim::Simulation& sim) {
  sample(sim, true);
  if (!model_.time.until_rest || rest_time_) return rest_time_.has_value();
  const scene::model::RestCriterion& rest = *model_.time.until_rest;
  // The velocities the particles move with: a FLIP part the grid does not see would keep a settled
  // shell "moving" forever (World::advected_kinetic_energy).
  const bool quiet = sim.advected_kinetic_energy() <= rest.kinetic_energy &&
                     sim.max_advected_control_point_speed() <= rest.speed;
  if (!quiet) {
    quiet_since_ = -1;
    return false;
  }
  if (quiet_since_ < 0) quiet_since_ = sim.time();
  if (sim.time() - quiet_since_ >= rest.duration) rest_time_ = sim.time();
  return rest_time_.has_value();
}

void VerificationRecorder::at_frame(const sim::Simulation& sim, int frame) {
  if (frame == 0) sample(sim, true);  // the start belongs to both kinds of probes
  sample(sim, false);
  energy_.time.push_back(sim.time());
  energy_.kinetic_energy.push_back(sim.kinetic_energy());
  if (!model_.output.control_points) return;
  std::ostringstream csv;
  csv << "shell,i,j,x,y,z\n";
  for (size_t s = 0; s < sim.world().num_shells(); ++s) {
    const shell::ShellPatch& p = sim.world().shell(s);
    const auto nu = static_cast<size_t>(p.reference().num_u());
    for (size_t k = 0; k < p.x.size(); ++k)
      csv << sim.world().shell_name(s) << ',' << k % nu << ',' << k / nu << ',' << number(p.x[k].x()) << ','
          << number(p.x[k].y()) << ',' << number(p.x[k].z()) << '\n';
  }
  char name[48];
  std::snprintf(name, sizeof name, "frame_%05d.control_points.csv", frame);
  render_mesh::write_file_atomically(out_dir_ / "frames" / name, csv.str());
}

void VerificationRecorder::finish(const sim::Simulation& sim, Summary& s) const {
  if (!samples_.empty()) fs::create_directories(out_dir_ / "probes");
  for (size_t i = 0; i < samples_.size(); ++i) {
    const scene::model::Probe& probe = model_.output.probes[i];
    ProbeReport r;
    r.name = probe.name;
    r.shell = sim.world().shell_name(probe.shell);
    r.every = probe.every_step ? "step" : "frame";
    r.file = "probes/" + probe.name + ".csv";
    std::ostringstream csv;
    csv << "time,x,y,z,ux,uy,uz,vx,vy,vz,sxx,syy,szz,sxy,syz,sxz\n";
    for (const sim::ProbeSample& p : samples_[i]) {
      r.samples.push_back({p.time, arr(p.position), arr(p.displacement), arr(p.velocity), p.stress});
      csv << number(p.time);
      for (const Eigen::Vector3d* v : {&p.position, &p.displacement, &p.velocity})
        for (int d = 0; d < 3; ++d) csv << ',' << number((*v)[d]);
      for (double x : p.stress) csv << ',' << number(x);
      csv << '\n';
    }
    render_mesh::write_file_atomically(out_dir_ / r.file, csv.str());
    s.probes.push_back(std::move(r));
  }
  for (size_t i = 0; i < model_.pins.size(); ++i) {
    const scene::model::Pin& pin = model_.pins[i];
    s.pins.push_back({pin.json_path, pin.name, sim.world().shell_name(pin.shell), arr(sim.pin_set_reaction(i))});
  }
  for (size_t i = 0; i < model_.loads.size(); ++i) {
    const scene::model::Load& load = model_.loads[i];
    s.loads.push_back({load.json_path, load_type(load.kind), sim.world().shell_name(load.shell), arr(sim.applied_load(i))});
  }
  if (model_.time.until_rest) {
    const scene::model::RestCriterion& c = *model_.time.until_rest;
    s.until_rest = RestReport{rest_time_.has_value(), rest_time_, c.kinetic_energy, c.speed, c.duration};
  }
  s.kinetic_energy_history = energy_;
}

}  // namespace shellfrac::output
