#include "sim/probes.hpp"

#include <cmath>
#include <limits>

namespace shellfrac::sim {

ProbeSampler::ProbeSampler(const scene::Model& model, const World& world) {
  nurbs::SurfaceBasis basis;
  for (const scene::model::Probe& probe : model.output.probes) {
    const shell::ShellPatch& patch = world.shell(probe.shell);
    patch.reference().rational_basis(probe.at.x(), probe.at.y(), basis);
    Point p;
    p.shell = probe.shell;
    const auto n = static_cast<size_t>(basis.count);
    p.index.assign(basis.index.begin(), basis.index.begin() + static_cast<long>(n));
    p.R.assign(basis.R.begin(), basis.R.begin() + static_cast<long>(n));
    p.Ru.assign(basis.Ru.begin(), basis.Ru.begin() + static_cast<long>(n));
    p.Rv.assign(basis.Rv.begin(), basis.Rv.begin() + static_cast<long>(n));
    Eigen::Matrix3d G = Eigen::Matrix3d::Zero();  // reference A_1, A_2 (the mid-surface layer's metric)
    for (size_t k = 0; k < n; ++k) {
      const Eigen::Vector3d& X = world.initial_positions(probe.shell)[static_cast<size_t>(p.index[k])];
      p.start += p.R[k] * X;
      G.col(0) += p.Ru[k] * X;
      G.col(1) += p.Rv[k] * X;
    }
    p.reference = shell::reference_layer(G);
    probes_.push_back(std::move(p));
  }
}

ProbeSample ProbeSampler::sample(size_t i, const World& world, double time) const {
  const Point& p = probes_[i];
  const shell::ShellPatch& patch = world.shell(p.shell);
  ProbeSample s;
  s.time = time;
  Eigen::Vector3d a1 = Eigen::Vector3d::Zero(), a2 = Eigen::Vector3d::Zero();
  for (size_t k = 0; k < p.index.size(); ++k) {
    const auto c = static_cast<size_t>(p.index[k]);
    s.position += p.R[k] * patch.x[c];
    s.velocity += p.R[k] * patch.v[c];
    a1 += p.Ru[k] * patch.x[c];
    a2 += p.Rv[k] * patch.x[c];
  }
  s.displacement = s.position - p.start;
  const shell::ShellMaterial& m = patch.material();
  const shell::InPlaneStress st = shell::neo_hookean_in_plane(a1, a2, p.reference, m.mu, m.lambda, m.transverse);
  if (!st.ok) {
    s.stress.fill(std::numeric_limits<double>::quiet_NaN());
    return s;
  }
  // sigma = tau^{ab} a_a (x) a_b / (J lambda_3)
  const Eigen::Matrix3d sigma =
      (st.t11 * a1 * a1.transpose() + st.t12 * (a1 * a2.transpose() + a2 * a1.transpose()) + st.t22 * a2 * a2.transpose()) /
      (st.J * st.lambda3);
  s.stress = {sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(0, 2)};
  return s;
}

}  // namespace shellfrac::sim
