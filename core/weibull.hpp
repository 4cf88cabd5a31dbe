#pragma once
// Seeded heterogeneous strength: a Weibull-distributed factor per material point, drawn from a
// counter-based hash of (seed, point index), so a point's draw is the same for any thread count, any
// evaluation order and any other point. Brittle solids draw one per particle, shells one per in-plane
// quadrature point (all its layers).
namespace shellfrac::core {

struct WeibullStrength {
  bool enabled = false;
  double modulus = 0;  // m (Weibull modulus; glass ~ 5-15, ceramics ~ 10-20, paper and cloth ~ 5-30)
  // false: the local failure stress is the scale s0, P(s <= x) = 1 - exp(-(x / s0)^m).
  // true: it is the mean (s0 = mean / Gamma(1 + 1/m)).
  bool scale_is_mean = false;
  unsigned long long seed = 1;
};

// Uniform number in (0, 1) from (seed, index) by a SplitMix64 hash; never exactly 0 or 1.
double hashed_uniform(unsigned long long seed, unsigned long long index);

// The factor that multiplies the local failure stress of point `index`: the inverse Weibull CDF
// (-ln(1 - U))^(1/m) of U = hashed_uniform(seed, index), divided by Gamma(1 + 1/m) when scale_is_mean.
// 1 when disabled. Requires modulus > 0.
double weibull_factor(const WeibullStrength& w, unsigned long long index);

}  // namespace shellfrac::core
