// The MLS shape functions (thesis sec. 4.6) against an independent weighted least-squares fit solved by
// Ceres, on open grids and on the one-sided supports beside a slit.
#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "shell/mls_basis.hpp"
#include "tests/shell/mls_test_grids.hpp"

namespace shellfrac::shell {
namespace {

using test::quadratic_grid;
using test::slit_visible;

// Eq. 4.18 (corrected), written out again so the reference does not share code with the module.
double reference_weight(double r) {
  if (r <= 0.5) return 2.0 / 3.0 - 4.0 * r * r + 4.0 * r * r * r;
  if (r <= 1.0) return 4.0 / 3.0 - 4.0 * r + 4.0 * r * r - 4.0 / 3.0 * r * r * r;
  return 0.0;
}

// Residual sqrt(W_k) (p(x_k)^T a - u_k) with the basis of thesis Eq. 4.16 in coordinates x centred at the
// support's centroid and scaled by the cell sizes. The fitted value at xi does not depend on that affine
// frame (the basis is a complete quadratic); the frame differs from the module's (centred at xi, scaled by d)
// and only keeps the reference fit well conditioned.
struct WeightedFitResidual {
  double sqrt_w, x1, x2, u;
  template <class T>
  bool operator()(const T* a, T* r) const {
    r[0] = T(sqrt_w) * (a[0] + a[1] * x1 + a[2] * x2 + a[3] * x1 * x1 + a[4] * x1 * x2 + a[5] * x2 * x2 - T(u));
    return true;
  }
};

double ceres_fit_value(const Eigen::Vector2d& xi, const Eigen::Vector2d& cell, const std::vector<Eigen::Vector2d>& pts,
                       const std::vector<double>& weights, const std::vector<double>& data) {
  Eigen::Vector2d centre = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& p : pts) centre += p / static_cast<double>(pts.size());
  auto frame = [&](const Eigen::Vector2d& x) -> Eigen::Vector2d { return (x - centre).cwiseQuotient(cell); };
  std::array<double, 6> a{};
  ceres::Problem problem;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const Eigen::Vector2d x = frame(pts[k]);
    problem.AddResidualBlock(new ceres::AutoDiffCostFunction<WeightedFitResidual, 1, 6>(
                                 new WeightedFitResidual{std::sqrt(weights[k]), x.x(), x.y(), data[k]}),
                             nullptr, a.data());
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::DENSE_QR;
  // A linear problem: a huge initial trust region makes the first Levenberg-Marquardt step Gauss-Newton.
  options.initial_trust_region_radius = 1e16;
  options.function_tolerance = 1e-16;
  options.gradient_tolerance = 1e-16;
  options.parameter_tolerance = 1e-16;
  options.max_num_iterations = 100;
  options.logging_type = ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  EXPECT_TRUE(summary.IsSolutionUsable()) << summary.BriefReport();
  const Eigen::Vector2d x = frame(xi);
  return a[0] + a[1] * x.x() + a[2] * x.y() + a[3] * x.x() * x.x() + a[4] * x.x() * x.y() + a[5] * x.y() * x.y();
}

template <class Visible>
void cross_check_with_ceres(const ControlGrid& grid, const Eigen::Vector2d& xi, Visible visible, std::mt19937& rng,
                            double& worst) {
  MlsBasis b;
  ASSERT_TRUE(mls_basis(xi, grid, visible, MlsSettings{}, b)) << b.reason;
  const double du = b.factor * grid.cell_u, dv = b.factor * grid.cell_v;
  std::vector<Eigen::Vector2d> pts;
  std::vector<double> weights;
  for (int id : b.index) {
    const Eigen::Vector2d p = grid.point(id);
    pts.push_back(p);
    weights.push_back(reference_weight(std::abs(xi.x() - p.x()) / du) *
                      reference_weight(std::abs(xi.y() - p.y()) / dv));  // rectangular support
    ASSERT_GT(weights.back(), 0.0);
  }
  std::uniform_real_distribution<double> data(-1.0, 1.0);
  for (int trial = 0; trial < 4; ++trial) {  // random data vectors
    std::vector<double> u(pts.size());
    double mls = 0.0;
    for (std::size_t k = 0; k < u.size(); ++k) {
      u[k] = data(rng);
      mls += b.R[k] * u[k];
    }
    const double ref = ceres_fit_value(xi, Eigen::Vector2d(grid.cell_u, grid.cell_v), pts, weights, u);
    EXPECT_NEAR(mls, ref, 1e-9) << "data fit at " << xi.transpose();
    worst = std::max(worst, std::abs(mls - ref));
  }
  for (std::size_t i = 0; i < pts.size(); ++i) {  // shape functions: fit unit data e_i
    std::vector<double> e(pts.size(), 0.0);
    e[i] = 1.0;
    const double ref = ceres_fit_value(xi, Eigen::Vector2d(grid.cell_u, grid.cell_v), pts, weights, e);
    EXPECT_NEAR(b.R[i], ref, 1e-9) << "shape function of point " << b.index[i] << " at " << xi.transpose();
    worst = std::max(worst, std::abs(b.R[i] - ref));
  }
}

TEST(MlsBasis, AgreesWithIndependentCeresWeightedLeastSquares) {
  const ControlGrid grid = quadratic_grid(10, 8);
  std::mt19937 rng(21);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  double worst = 0.0;
  for (int trial = 0; trial < 8; ++trial) {
    cross_check_with_ceres(grid, Eigen::Vector2d(unit(rng), unit(rng)), AlwaysVisible{}, rng, worst);
  }
  for (double v : {0.1, 0.35}) {  // enlarged one-sided supports at the slit
    cross_check_with_ceres(grid, Eigen::Vector2d(0.46, v), slit_visible, rng, worst);
    cross_check_with_ceres(grid, Eigen::Vector2d(0.55, v), slit_visible, rng, worst);
  }
  std::printf("[ ceres ] worst |MLS - Ceres fit| = %.2e\n", worst);
}

}  // namespace
}  // namespace shellfrac::shell
