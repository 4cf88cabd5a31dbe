// Mode-I crack in a notched beam under three-point bending (thesis Fig. 3.14, sec. 2.3 propagation), and
// the damage time along the running crack (sec. 3.7).
#include <gtest/gtest.h>

#include <algorithm>
#include <memory>
#include <numeric>

#include "brittle/crack_surface.hpp"
#include "brittle/solver.hpp"

namespace shellfrac::brittle {
namespace {

constexpr double kS = 0.0025, kDx = 0.005;
constexpr double kHeight = 0.04, kNotch = 0.012;

// A 0.2 x 0.01 x 0.04 m beam (80 x 4 x 16 particles) with a notch one cell wide and 0.3 H deep at the
// bottom middle (particles removed), on two slip supports at x = +-0.09, loaded at the top middle by a
// box pushed down at 0.6 m/s. E 10 MPa, nu 0.2, 1000 kg/m^3, sigma_f 100 kPa, G_f 8 J/m^2 (H = 0.76).
struct NotchedBeam {
  BrittleSolid solid;
  NotchedBeam() {
    BrittleMaterial m;
    m.youngs_modulus = 1e7;
    m.poisson_ratio = 0.2;
    m.density = 1000;
    m.failure_stress = 1e5;
    m.fracture_energy = 8;
    solid.material = m;
    solid.spacing = kS;
    std::vector<Vec3> pts;
    for (int k = 0; k < 16; ++k)
      for (int j = 0; j < 4; ++j)
        for (int i = 0; i < 80; ++i) {
          const Vec3 p(-0.1 + kS * (i + 0.5), kS * (j + 0.5), kS * (k + 0.5));
          if (std::abs(p.x()) < 0.003 && p.z() < kNotch) continue;
          pts.push_back(p);
        }
    solid.add_particles(pts, kS * kS * kS, Vec3::Zero());
    solid.set_strength({}, WeibullStrength{}, kDx);
  }
  void run(double duration) {
    SolverOptions o;
    o.dx = kDx;
    o.two_fields = false;
    o.stop.max_time = duration;
    BrittleSolver solver(solid, o);
    for (int side = -1; side <= 1; side += 2) {
      mpm::Collider support;
      support.shape = std::make_shared<mpm::Box>(Vec3(0.09 * side, 0.005, -0.005), Vec3(0.005, 0.02, 0.005));
      support.boundary = mpm::Boundary::Slip;
      solver.add_collider(support);
    }
    mpm::Collider load;
    load.shape = std::make_shared<mpm::Box>(Vec3(0, 0.005, kHeight + 0.005), Vec3(0.005, 0.02, 0.005));
    load.motion.linear_velocity = Vec3(0, 0, -0.6);
    load.boundary = mpm::Boundary::Slip;
    solver.add_collider(load);
    while (!solver.should_stop()) solver.step();
  }
};

// Spearman rank correlation.
double rank_correlation(const std::vector<double>& a, const std::vector<double>& b) {
  auto ranks = [](const std::vector<double>& v) {
    std::vector<size_t> order(v.size());
    std::iota(order.begin(), order.end(), 0);
    std::sort(order.begin(), order.end(), [&](size_t i, size_t j) { return v[i] < v[j]; });
    std::vector<double> r(v.size());
    for (size_t k = 0; k < order.size();) {  // ties share their mean rank
      size_t e = k;
      while (e + 1 < order.size() && v[order[e + 1]] == v[order[k]]) ++e;
      for (size_t q = k; q <= e; ++q) r[order[q]] = 0.5 * static_cast<double>(k + e);
      k = e + 1;
    }
    return r;
  };
  const std::vector<double> ra = ranks(a), rb = ranks(b);
  const double ma = std::accumulate(ra.begin(), ra.end(), 0.0) / ra.size(), mb = std::accumulate(rb.begin(), rb.end(), 0.0) / rb.size();
  double sab = 0, saa = 0, sbb = 0;
  for (size_t i = 0; i < ra.size(); ++i) {
    sab += (ra[i] - ma) * (rb[i] - mb);
    saa += (ra[i] - ma) * (ra[i] - ma);
    sbb += (rb[i] - mb) * (rb[i] - mb);
  }
  return sab / std::sqrt(saa * sbb);
}

TEST(NotchedBeam, ModeICrackRunsUpTheMidPlaneAndDamageTimeGrowsAlongIt) {
  NotchedBeam beam;
  beam.run(0.008);
  const double top = 0.75 * kHeight;  // the crack from the notch; above it the load nose damages too
  std::vector<double> z, tau;
  double worst_x = 0;
  std::vector<int> layer_hits(16, 0);
  for (size_t p = 0; p < beam.solid.size(); ++p) {
    const ParticleDamage& d = beam.solid.damage[p];
    const Vec3& x = beam.solid.rest[p];
    if (d.c_his < 1.0 || x.z() < kNotch || x.z() > top) continue;
    worst_x = std::max(worst_x, std::abs(x.x()));
    ++layer_hits[static_cast<size_t>(x.z() / kS)];
    z.push_back(x.z());
    tau.push_back(d.tau);
  }
  // Every particle layer from the notch tip to 3/4 of the height holds broken particles: one crack.
  const int first = static_cast<int>(std::ceil(kNotch / kS)), last = static_cast<int>(top / kS);
  for (int k = first; k < last; ++k) EXPECT_GT(layer_hits[static_cast<size_t>(k)], 0) << "layer " << k;
  std::printf("MEASURE beam: max |x| of the crack %.4g m (2 cells = %.4g), %zu broken particles\n", worst_x, 2 * kDx, z.size());
  EXPECT_LE(worst_x, 2 * kDx);
  // Damage time grows with height: the crack runs from the notch towards the load. Per particle layer
  // the mean damage time; its rank correlation with the height, and the last layers against the first.
  std::vector<double> layer_z, layer_tau;
  for (int k = first; k < last; ++k) {
    double sum = 0;
    int n = 0;
    for (size_t i = 0; i < z.size(); ++i)
      if (static_cast<int>(z[i] / kS) == k) sum += tau[i], ++n;
    if (n == 0) continue;
    layer_z.push_back((k + 0.5) * kS);
    layer_tau.push_back(sum / n);
    std::printf("MEASURE beam layer z %.4f: %d broken, mean tau %.5f s\n", (k + 0.5) * kS, n, sum / n);
  }
  const double rho = rank_correlation(layer_z, layer_tau);
  std::printf("MEASURE beam: rank correlation (layer height, mean damage time) %.3f\n", rho);
  EXPECT_GT(rho, 0.9);
  ASSERT_GE(layer_tau.size(), 4u);
  EXPECT_GT(layer_tau.back(), layer_tau.front() + 1e-3);  // 1 ms later at the top than at the notch
  // The extracted crack surface lies within two cells of the mid-plane over the same height.
  CrackExtractionOptions co;
  co.grid.spacing = kDx;
  const CrackExtraction crack = extract_crack(beam.solid.rest, beam.solid.damage_history(), co);
  const TriMesh surface = crack_surface_mesh(crack);
  double worst_face = 0;
  size_t counted = 0;
  for (const Vec3& v : surface.positions)
    if (v.z() > kNotch && v.z() < top && v.y() > 0 && v.y() < 0.01) {
      worst_face = std::max(worst_face, std::abs(v.x()));
      ++counted;
    }
  EXPECT_GT(counted, 0u);
  EXPECT_LE(worst_face, 2 * kDx);
}

}  // namespace
}  // namespace shellfrac::brittle
