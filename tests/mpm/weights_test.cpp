#include "mpm/bspline_weights.hpp"

#include <gtest/gtest.h>

namespace shellfrac::mpm {
namespace {

// Eq. 2.10 evaluated directly.
double N(double x) {
  x = std::abs(x);
  if (x < 0.5) return 0.75 - x * x;
  if (x < 1.5) return 0.5 * (1.5 - x) * (1.5 - x);
  return 0.0;
}

TEST(QuadraticWeights, MatchEquationAndReproduceLinearFunctions) {
  const double dx = 0.1;
  for (double x = -0.33; x < 0.4; x += 0.0137) {
    const AxisWeights a = quadratic_weights(x, 1.0 / dx);
    double sum = 0, first = 0, dsum = 0, dfirst = 0;
    for (int i = 0; i < 3; ++i) {
      const double xi = (a.base + i) * dx;
      EXPECT_NEAR(a.w[i], N((x - xi) / dx), 1e-15);
      // derivative against central differences
      const double h = 1e-7;
      EXPECT_NEAR(a.dw[i], (N((x + h - xi) / dx) - N((x - h - xi) / dx)) / (2 * h), 1e-6);
      sum += a.w[i];
      first += a.w[i] * xi;
      dsum += a.dw[i];
      dfirst += a.dw[i] * xi;
    }
    EXPECT_NEAR(sum, 1.0, 1e-15);     // partition of unity
    EXPECT_NEAR(first, x, 1e-15);     // linear reproduction
    EXPECT_NEAR(dsum, 0.0, 1e-12);
    EXPECT_NEAR(dfirst, 1.0, 1e-12);
  }
}

}  // namespace
}  // namespace shellfrac::mpm
