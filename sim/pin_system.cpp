#include "sim/pin_system.hpp"

#include <Eigen/QR>
#include <map>

namespace shellfrac::sim {

namespace {

struct MergedPoint {
  size_t shell = 0, point = 0;
  Eigen::Matrix3d projector = Eigen::Matrix3d::Zero();
  bool kinematic = false;
  size_t pin = 0;
  std::vector<std::pair<size_t, Eigen::Matrix3d>> shares;  // each pin holding the point, its own projector
};

// One entry per held control point: the union of the directions all pins hold there (several static
// pins may share a point: a roller edge meeting a symmetry plane; scene::build refuses shared points
// when a pin moves them), following the first pin that holds it.
std::vector<MergedPoint> merge_pins(const scene::Model& model) {
  std::map<std::pair<size_t, size_t>, std::pair<size_t, std::vector<Eigen::Vector3d>>> points;
  std::map<std::pair<size_t, size_t>, std::vector<std::pair<size_t, Eigen::Matrix3d>>> shares;
  for (size_t p = 0; p < model.pins.size(); ++p) {
    const scene::model::Pin& pin = model.pins[p];
    for (size_t k = 0; k < pin.control_points.size(); ++k) {
      auto key = std::make_pair(pin.shell, static_cast<size_t>(pin.control_points[k]));
      auto it = points.find(key);
      if (it == points.end()) it = points.emplace(key, std::make_pair(p, std::vector<Eigen::Vector3d>{})).first;
      std::vector<Eigen::Vector3d>& dirs = it->second.second;
      Eigen::Matrix3d own = Eigen::Matrix3d::Zero();  // a pin's directions at a point are orthonormal
      if (pin.holds_all(k)) {
        for (int d = 0; d < 3; ++d) dirs.push_back(Eigen::Vector3d::Unit(d));
        own.setIdentity();
      } else {
        dirs.insert(dirs.end(), pin.held[k].begin(), pin.held[k].end());
        for (const Eigen::Vector3d& d : pin.held[k]) own += d * d.transpose();
      }
      shares[key].emplace_back(p, own);
    }
  }
  std::vector<MergedPoint> out;
  for (const auto& [key, value] : points) {
    MergedPoint m;
    m.shell = key.first;
    m.point = key.second;
    m.pin = value.first;
    Eigen::Matrix<double, 3, Eigen::Dynamic> D(3, static_cast<Eigen::Index>(value.second.size()));
    for (size_t c = 0; c < value.second.size(); ++c) D.col(static_cast<Eigen::Index>(c)) = value.second[c];
    Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(D);
    qr.setThreshold(1e-9);
    const Eigen::Index rank = qr.rank();
    const Eigen::MatrixXd Q = Eigen::MatrixXd(qr.householderQ()).leftCols(rank);
    m.projector = Q * Q.transpose();
    m.kinematic = rank == 3;
    m.shares = shares[key];
    out.push_back(m);
  }
  return out;
}

}  // namespace

std::vector<std::vector<bool>> kinematic_points(const scene::Model& model) {
  std::vector<std::vector<bool>> out;
  for (const scene::model::Shell& s : model.shells)
    out.emplace_back(static_cast<size_t>(s.surface.num_u()) * static_cast<size_t>(s.surface.num_v()), false);
  for (const MergedPoint& m : merge_pins(model)) out[m.shell][m.point] = m.kinematic;
  return out;
}

PinSystem::PinSystem(const scene::Model& model, const World&) : model_(model), reaction_(model.pins.size(), Eigen::Vector3d::Zero()) {
  for (const MergedPoint& m : merge_pins(model)) held_.push_back({m.shell, m.point, m.projector, m.kinematic, m.pin, m.shares});
  for (size_t p = 0; p < model.pins.size(); ++p) {
    const scene::model::Pin& pin = model.pins[p];
    const Eigen::Matrix3d T = Eigen::Matrix3d::Identity() - pin.symmetry_normal * pin.symmetry_normal.transpose();
    for (size_t k = 0; k < pin.tied.size(); ++k)
      if (pin.tied[k] >= 0)
        ties_.push_back({pin.shell, static_cast<size_t>(pin.control_points[k]), static_cast<size_t>(pin.tied[k]), T, p});
  }
  // Points in more than one tie (the corner of two symmetry planes) need repeated sweeps.
  std::map<std::pair<size_t, size_t>, int> count;
  for (const Tie& t : ties_)
    if (++count[{t.shell, t.a}] > 1 || ++count[{t.shell, t.b}] > 1) sweeps_ = kCornerSweeps;
}

void PinSystem::hold_initial_velocities(World& world) const {
  for (const Held& h : held_) {
    shell::ShellPatch& patch = world.shell(h.shell);
    const Eigen::Vector3d target = model_.pins[h.pin].motion.velocity_at(patch.x[h.point], 0.0);
    Eigen::Vector3d& v = patch.v[h.point];
    v -= h.projector * (v - target);
  }
}

void PinSystem::add_reaction(const Held& h, Eigen::Vector3d r) {
  if (h.shares.size() > 1)
    for (const auto& [pin, own] : h.shares) {
      const Eigen::Vector3d part = own * r;
      reaction_[pin] += part;
      r -= part;
    }
  reaction_[h.pin] += r;  // all of it for a point of one pin; round-off otherwise
}

void PinSystem::hold_forces(World& world) {
  for (auto& r : reaction_) r.setZero();
  auto holds = [&] {
    for (const Held& h : held_) {
      Eigen::Vector3d& f = world.shell(h.shell).force[h.point];
      const Eigen::Vector3d held = h.kinematic ? f : Eigen::Vector3d(h.projector * f);
      add_reaction(h, -held);
      f -= held;
    }
  };
  // Sharing a tie's force in proportion to mass is the mass-weighted projection of the accelerations;
  // alternating it with the holds converges to their joint projection (ties meeting at a corner). The
  // holds come last, so that held components leave exactly cleared.
  for (int sweep = 0; sweep < sweeps_ && !ties_.empty(); ++sweep) {
    holds();
    for (const Tie& t : ties_) {
      const std::vector<double>& m = world.transfer_mass(t.shell);
      const double ma = m[t.a], mb = m[t.b];
      if (ma <= 0 || mb <= 0) continue;  // a kinematic partner: nothing to share
      std::vector<Eigen::Vector3d>& f = world.shell(t.shell).force;
      const Eigen::Vector3d sum = t.in_plane * (f[t.a] + f[t.b]);
      f[t.a] += ma / (ma + mb) * sum - t.in_plane * f[t.a];
      f[t.b] += mb / (ma + mb) * sum - t.in_plane * f[t.b];
    }
  }
  holds();
}

void PinSystem::hold_velocities(World& world, double dt, double t) {
  auto holds = [&] {
    for (const Held& h : held_) {
      if (h.kinematic) continue;  // set with the position in hold_positions
      shell::ShellPatch& patch = world.shell(h.shell);
      const Eigen::Vector3d target = model_.pins[h.pin].motion.velocity_at(patch.x[h.point], t);
      const Eigen::Vector3d removed = h.projector * (patch.v[h.point] - target);
      add_reaction(h, -world.transfer_mass(h.shell)[h.point] * removed / dt);
      patch.v[h.point] -= removed;
      // A held component moves with the pin, none of it is FLIP part (World::flip_part: advection).
      std::vector<Eigen::Vector3d>& flip = world.flip_part(h.shell);
      if (!flip.empty()) flip[h.point] -= h.projector * flip[h.point];
    }
  };
  for (int sweep = 0; sweep < sweeps_ && !ties_.empty(); ++sweep) {
    holds();
    for (const Tie& tie : ties_) {
      const std::vector<double>& m = world.transfer_mass(tie.shell);
      const double ma = m[tie.a], mb = m[tie.b];
      if (ma <= 0 || mb <= 0) continue;
      std::vector<Eigen::Vector3d>& v = world.shell(tie.shell).v;
      const Eigen::Vector3d mean = tie.in_plane * (ma * v[tie.a] + mb * v[tie.b]) / (ma + mb);
      v[tie.a] += mean - tie.in_plane * v[tie.a];
      v[tie.b] += mean - tie.in_plane * v[tie.b];
      std::vector<Eigen::Vector3d>& flip = world.flip_part(tie.shell);  // tied points also advect alike
      if (!flip.empty()) {
        const Eigen::Vector3d flip_mean = tie.in_plane * (ma * flip[tie.a] + mb * flip[tie.b]) / (ma + mb);
        flip[tie.a] += flip_mean - tie.in_plane * flip[tie.a];
        flip[tie.b] += flip_mean - tie.in_plane * flip[tie.b];
      }
    }
  }
  holds();
}

void PinSystem::hold_positions(World& world, double t) const {
  for (const Held& h : held_) {
    shell::ShellPatch& patch = world.shell(h.shell);
    const scene::model::Pin& pin = model_.pins[h.pin];
    const Eigen::Vector3d target = pin.motion.pose(t) * world.initial_positions(h.shell)[h.point];
    if (h.kinematic) {
      patch.x[h.point] = target;
      patch.v[h.point] = pin.motion.velocity_at(target, t);
      std::vector<Eigen::Matrix3d>& affine = world.affine(h.shell);
      if (!affine.empty()) affine[h.point].setZero();
    } else {
      patch.x[h.point] -= h.projector * (patch.x[h.point] - target);
    }
  }
}

}  // namespace shellfrac::sim
