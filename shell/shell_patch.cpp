#include "shell/shell_patch.hpp"

#include "core/rigid_rotation.hpp"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <cstdint>
#include <limits>
#include <cmath>
#include <stdexcept>

namespace shellfrac::shell {

ShellPatch::ShellPatch(const nurbs::NurbsSurface& reference, const ShellMaterial& material,
                       const QuadratureRule& rule)
    : reference_(reference), material_(material) {
  if (!(material.thickness > 0) || !(material.density > 0) || !(material.mu > 0))
    throw std::invalid_argument("shell material needs thickness, density and shear modulus > 0");
  if (material.stress_model != StressModel::KirchhoffLove && material.plasticity.enabled)
    throw std::invalid_argument("plasticity needs the Kirchhoff-Love stress model");
  x = reference_.control_points().empty() ? std::vector<Vec3>{}
                                          : std::vector<Vec3>(reference_.control_points().begin(),
                                                              reference_.control_points().end());
  v.assign(x.size(), Vec3::Zero());
  force.assign(x.size(), Vec3::Zero());
  quad_ = build_quadrature(reference_, thickness_layers(rule.layers, material.thickness), rule);
  lanes_ = lay_out_basis_lanes(quad_);
  build_masses();
  gather_ = make_force_gather(quad_.support, x.size());
  build_shear_particles();
  if (material_.plasticity.enabled) state_.plastic_strain.assign(quad_.ref.size(), 0.0);
  cut_ = uncut_bases(x.size(), quad_.param.size(), quad_.num_cells);
  if (material_.fracture.enabled) {
    state_.damage.assign(quad_.ref.size(), 0.0);
    state_.damage_history.assign(quad_.ref.size(), 0.0);
    state_.failure_stress.assign(quad_.param.size(), material_.fracture.failure_stress);
    state_.brittleness.assign(quad_.param.size(), material_.brittleness);
  }
  stiffness_.added_mass.assign(x.size(), 0.0);
  stiffness_.reference = stiffness_.current = stiffness_of(basis_rows(), mass, stiffness_.added_mass);
}

nurbs::NurbsSurface ShellPatch::current_surface() const {
  return nurbs::NurbsSurface(reference_.knots_u(), reference_.knots_v(),
                             nurbs::Vec3List(x.begin(), x.end()), reference_.weights());
}

void ShellPatch::build_masses() {
  // Consistent-row-sum lumped mass: m_s = rho sum_q V_q R_s(xi_q), times the control points' share.
  mass.assign(x.size(), 0.0);
  for (size_t q = 0; q < quad_.param.size(); ++q) {
    const double vq = quad_.point_volume(q);
    const int* sup = support(cell_of(q));
    for (int s = 0; s < quad_.support_size; ++s)
      mass[static_cast<size_t>(sup[s])] +=
          (1.0 - material_.shear_mass_share) * material_.density * vq *
          quad_.basis[(q * quad_.support_size + static_cast<size_t>(s)) * kBasisStride];
  }
}

void ShellPatch::build_shear_particles() {
  const size_t L = quad_.num_layers();
  nurbs::SurfaceBasis basis;
  shear.basis.assign(quad_.num_cells * static_cast<size_t>(quad_.support_size * kShearStride), 0.0);
  for (size_t c = 0; c < quad_.num_cells; ++c) {
    const Vec2& uv = quad_.cell_center[c];
    reference_.rational_basis(uv.x(), uv.y(), basis);
    const int* sup = support(c);
    double* out = &shear.basis[c * static_cast<size_t>(quad_.support_size * kShearStride)];
    Vec3 pos = Vec3::Zero(), A1 = Vec3::Zero(), A2 = Vec3::Zero();
    for (int k = 0; k < basis.count; ++k) {
      const int idx = basis.index[static_cast<size_t>(k)];
      int local = 0;
      while (sup[local] != idx) ++local;  // the cell's support holds every non-zero function
      out[local * kShearStride + 0] = basis.R[static_cast<size_t>(k)];
      out[local * kShearStride + 1] = basis.Ru[static_cast<size_t>(k)];
      out[local * kShearStride + 2] = basis.Rv[static_cast<size_t>(k)];
      const Vec3& X = x[static_cast<size_t>(idx)];
      pos += basis.R[static_cast<size_t>(k)] * X;
      A1 += basis.Ru[static_cast<size_t>(k)] * X;
      A2 += basis.Rv[static_cast<size_t>(k)] * X;
    }
    const Vec3 N = A1.cross(A2).normalized();
    const Vec3 E1 = A1.normalized(), E2 = N.cross(E1);
    Mat3 E, D;
    E << E1, E2, N;
    D << A1, A2, N;
    D = E.transpose() * D;  // upper triangular in the local frame; third column e_3
    shear.x.push_back(pos);
    shear.v.push_back(Vec3::Zero());
    shear.mass.push_back(0.0);  // set below from the cell volume
    shear.director.push_back(N);
    shear.reference_inverse.push_back(D.inverse());
    shear.stress.push_back(Mat3::Zero());
    shear.velocity_gradient.push_back(Mat3::Zero());
    double V = 0;
    for (size_t q = c * quad_.points_per_cell; q < (c + 1) * quad_.points_per_cell; ++q)
      for (size_t l = 0; l < L; ++l) V += quad_.volume[q * L + l];
    shear.volume.push_back(V);
    shear.mass.back() = material_.shear_mass_share * material_.density * V;
  }
}

ShellPatch::BasisView ShellPatch::slot_view(int32_t slot) const {
  const MlsSupport& m = cut_.slots[static_cast<size_t>(slot)];
  return {static_cast<int>(m.index.size()), m.index.data(), m.basis.data(), kBasisStride};
}

ShellPatch::BasisView ShellPatch::shear_basis(size_t c) const {
  const int32_t slot = cut_.shear_slot[c];
  if (slot >= 0) return slot_view(slot);
  return {quad_.support_size, support(c), &shear.basis[c * static_cast<size_t>(quad_.support_size * kShearStride)], kShearStride};
}

Vec3* ShellPatch::shear_force_target(size_t c) {
  const int32_t slot = cut_.shear_slot[c];
  if (slot >= 0) return gather_.forces_of(cut_.slots[static_cast<size_t>(slot)]);
  return &gather_.cell_force[c * static_cast<size_t>(quad_.support_size)];
}

Vec3* ShellPatch::point_force_target(size_t q) {
  const int32_t slot = cut_.point_slot[q];
  if (slot >= 0) return gather_.forces_of(cut_.slots[static_cast<size_t>(slot)]);
  return &gather_.cell_force[cell_of(q) * static_cast<size_t>(quad_.support_size)];
}

Vec3 ShellPatch::shear_particle_frame(size_t c, Vec3& a1, Vec3& a2) const {
  // thesis Eq. 4.10 with the NURBS basis, or the MLS basis near a crack (sec. 4.6)
  const BasisView b = shear_basis(c);
  Vec3 pos = cut_.shear_slot[c] >= 0 ? cut_.slots[static_cast<size_t>(cut_.shear_slot[c])].rigid_offset : Vec3::Zero();
  a1.setZero();
  a2.setZero();
  for (int s = 0; s < b.n; ++s) {
    const Vec3& X = x[static_cast<size_t>(b.index[s])];
    const double* d = b.basis + s * b.stride;
    pos += d[0] * X;
    a1 += d[1] * X;
    a2 += d[2] * X;
  }
  return pos;
}

Mat3 ShellPatch::director_r(size_t c) const {
  if (shear_level(c) >= BasisLevel::Rigid) return Mat3::Identity();  // no tangents: unstrained
  Vec3 a1, a2;
  shear_particle_frame(c, a1, a2);
  Mat3 d;
  d << a1, a2, shear.director[c];
  Mat3 Q, R;
  qr_oriented(d * shear.reference_inverse[c], Q, R);
  return R;
}

double ShellPatch::director_stretch(size_t c) const { return director_r(c)(2, 2); }

namespace {

// Angular momentum about the origin of the particles' x_p x m_p v_p, summed in index order.
Vec3 moment_of_momentum(const ShearParticles& s) {
  Vec3 L = Vec3::Zero();
  for (size_t c = 0; c < s.x.size(); ++c) L += s.mass[c] * s.x[c].cross(s.v[c]);
  return L;
}

// Adds omega x (x_p - x_c) to every particle's velocity, x_c their centre of mass, with omega chosen so
// that sum x_p x m_p v_p changes by `change` (core::rotation_for; nothing for one row of cells).
void add_rotation(ShearParticles& s, const Vec3& change) {
  double mass = 0;
  Vec3 first = Vec3::Zero();
  for (size_t c = 0; c < s.x.size(); ++c) {
    mass += s.mass[c];
    first += s.mass[c] * s.x[c];
  }
  if (mass <= 0) return;
  const Vec3 centre = first / mass;
  Mat3 spread = Mat3::Zero();
  for (size_t c = 0; c < s.x.size(); ++c) spread += s.mass[c] * (s.x[c] - centre) * (s.x[c] - centre).transpose();
  const Vec3 omega = core::rotation_for(spread, change);
  for (size_t c = 0; c < s.x.size(); ++c) s.v[c] += omega.cross(s.x[c] - centre);
}

}  // namespace

void ShellPatch::update_shear_particles(double dt) {
  // Placing the particles by Eq. 4.10 moves them off the path their grid velocity would take (x + dt v),
  // and that move changes their angular momentum, which the transfers otherwise keep (APIC, and g2p's
  // correction of the FLIP shares). A rotation of their velocities about their centre of mass gives it
  // back: a spinning cut sheet lost 2.1e-5 of it in 400 steps without (docs/shell-model.md, "Transfer").
  const Vec3 before = moment_of_momentum(shear);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, quad_.num_cells, 64), [&](const tbb::blocked_range<size_t>& r) {
    for (size_t c = r.begin(); c != r.end(); ++c) {
      const BasisLevel level = shear_level(c);
      // A particle in a fragment without control points carries its mass on with its grid velocity; one in
      // a rigid sliver follows the sliver's control points. Neither has tangents: the director is kept.
      if (level == BasisLevel::Removed) {
        shear.x[c] += dt * shear.v[c];
        continue;
      }
      Vec3 a1, a2;
      shear.x[c] = shear_particle_frame(c, a1, a2);  // thesis Eq. 4.10
      if (level == BasisLevel::Rigid) continue;
      const Vec3 d3 = shear.director[c] + dt * (shear.velocity_gradient[c] * shear.director[c]);
      Mat3 d;
      d << a1, a2, d3;
      shear.director[c] = shear_return_map(d * shear.reference_inverse[c], material_.shear);
    }
  });
  add_rotation(shear, before - moment_of_momentum(shear));
}

ShellPatch::BasisView ShellPatch::point_basis(size_t q) const {
  const int32_t slot = cut_.point_slot[q];
  if (slot >= 0) return slot_view(slot);
  const size_t c = cell_of(q);
  return {quad_.support_size, support(c), &quad_.basis[q * static_cast<size_t>(quad_.support_size) * kBasisStride], kBasisStride};
}

double ShellPatch::parameter_spacing() const {
  return std::min(quad_.control_grid.cell_u, quad_.control_grid.cell_v) / std::sqrt(static_cast<double>(quad_.points_per_cell));
}

std::vector<unsigned char> ShellPatch::fully_damaged_points() const {
  std::vector<unsigned char> out(quad_.param.size(), 0);
  for (size_t q = 0; q < quad_.param.size() && !state_.damage_history.empty(); ++q) out[q] = state_.fully_damaged(q, quad_.num_layers());
  return out;
}

size_t ShellPatch::num_fully_damaged_points() const {
  return state_.count_fully_damaged(quad_.param.size(), quad_.num_layers());
}

double ShellPatch::max_damage() const {
  double m = 0;
  for (double c : state_.damage) m = std::max(m, c);
  return m;
}

double ShellPatch::max_plastic_strain() const {
  double m = 0;
  for (double a : state_.plastic_strain) m = std::max(m, a);
  return m;
}

SurfaceJet ShellPatch::point_jet(size_t q, std::vector<const Vec3*>& pts) const {
  const BasisView b = point_basis(q);
  pts.resize(static_cast<size_t>(b.n));
  for (int s = 0; s < b.n; ++s) pts[static_cast<size_t>(s)] = &x[static_cast<size_t>(b.index[s])];
  return surface_jet(pts.data(), b.basis + 1, b.n, kBasisStride);
}

double ShellPatch::elastic_energy() const {
  const size_t L = quad_.num_layers();
  std::vector<double> per_point(quad_.param.size(), 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, quad_.param.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<const Vec3*> pts;
    for (size_t q = r.begin(); q != r.end(); ++q) {
      if (point_level(q) >= BasisLevel::Rigid) continue;  // no stress, no energy
      const bool membrane = cut_.point_slot[q] >= 0 && cut_.slots[static_cast<size_t>(cut_.point_slot[q])].order == 1;
      const SurfaceJet jet = point_jet(q, pts);
      NormalJet nj;
      if (!normal_jet(jet, nj)) {
        per_point[q] = std::numeric_limits<double>::quiet_NaN();
        continue;
      }
      // Plane strain and the 2D model have lambda_3 = 1 (the rigid energy); the KL projection changes the
      // stress, not the energy, so only the condensed default is an exact gradient of its energy.
      const bool with_director = material_.stress_model == StressModel::DirectorF2D;
      const bool mid_surface = material_.stress_model == StressModel::MidSurface2D || with_director || membrane;
      const bool plastic = material_.plasticity.enabled;
      const TransverseModel model = material_.stress_model == StressModel::KirchhoffLove ? material_.transverse
                                    : with_director ? TransverseModel::Given
                                                    : TransverseModel::Rigid;
      const double r33 = with_director ? director_stretch(cell_of(q)) : 1.0;
      for (size_t l = 0; l < L; ++l) {
        const double xi3 = mid_surface ? 0.0 : quad_.layers.xi3[l];
        const bool mid_ref = (mid_surface && !membrane) || (membrane && !plastic);
        per_point[q] += quad_.volume[q * L + l] *
                        neo_hookean_in_plane_energy(jet.a1 + xi3 * nj.dn1, jet.a2 + xi3 * nj.dn2,
                                                    quad_.ref[q * L + (mid_ref ? L / 2 : l)], material_.mu,
                                                    material_.lambda, model, r33);
      }
    }
  });
  double e = 0;
  for (double v : per_point) e += v;
  // Type III shear/compression energy at the current directors.
  for (size_t c = 0; c < quad_.num_cells; ++c) e += shear.volume[c] * shear_energy_density(director_r(c), material_.shear);
  return e;
}

std::vector<double> ShellPatch::mid_surface_stress() const {
  const size_t L = quad_.num_layers();
  std::vector<double> out(quad_.param.size(), 0.0);
  tbb::parallel_for(tbb::blocked_range<size_t>(0, quad_.param.size(), 64), [&](const tbb::blocked_range<size_t>& r) {
    std::vector<const Vec3*> pts;
    for (size_t q = r.begin(); q != r.end(); ++q) {
      if (point_level(q) >= BasisLevel::Rigid) continue;
      const SurfaceJet jet = point_jet(q, pts);
      const InPlaneStress st = neo_hookean_in_plane(jet.a1, jet.a2, quad_.ref[q * L + L / 2], material_.mu, material_.lambda,
                                                    material_.transverse);
      if (!st.ok) continue;
      const InPlaneTensor tau{st.t11, st.t12, st.t22};
      const InPlaneTensor neg{-st.t11, -st.t12, -st.t22};
      out[q] = std::max(largest_principal(tau, jet.a1, jet.a2), largest_principal(neg, jet.a1, jet.a2)) /
               (st.J * st.lambda3);
    }
  });
  return out;
}

double ShellPatch::reference_volume() const {
  double V = 0;
  for (double v : quad_.volume) V += v;
  return V;
}

}  // namespace shellfrac::shell
