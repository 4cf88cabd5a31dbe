#pragma once
#include <Eigen/Core>
#include <cmath>

namespace shellfrac::mpm {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// Quadratic B-spline transfer weights of one particle along one axis (thesis Eq. 2.10, 2.11).
// Grid nodes sit at integer multiples of dx; the particle at x touches nodes base, base+1, base+2.
struct AxisWeights {
  int base;
  double w[3];   // N((x - x_i) / dx)
  double dw[3];  // dN/dx (already divided by dx)
};

inline AxisWeights quadratic_weights(double x, double inv_dx) {
  const double s = x * inv_dx;
  AxisWeights a;
  a.base = static_cast<int>(std::floor(s - 0.5));
  const double f = s - a.base;  // in [0.5, 1.5): distance to the base node in cells
  // Node i at distance d_i = f - i from the particle: N(d) from Eq. 2.10.
  a.w[0] = 0.5 * (1.5 - f) * (1.5 - f);
  a.w[1] = 0.75 - (f - 1.0) * (f - 1.0);
  a.w[2] = 0.5 * (f - 0.5) * (f - 0.5);
  // dN/dx_p = N'(d) / dx with d = f - i (Eq. 2.11).
  a.dw[0] = (f - 1.5) * inv_dx;
  a.dw[1] = -2.0 * (f - 1.0) * inv_dx;
  a.dw[2] = (f - 0.5) * inv_dx;
  return a;
}

// Weights and weight gradients of a particle on its 3x3x3 node stencil (dyadic products, Eq. 2.14).
struct StencilWeights {
  AxisWeights ax[3];
  double weight(int i, int j, int k) const { return ax[0].w[i] * ax[1].w[j] * ax[2].w[k]; }
  Vec3 gradient(int i, int j, int k) const {
    return {ax[0].dw[i] * ax[1].w[j] * ax[2].w[k], ax[0].w[i] * ax[1].dw[j] * ax[2].w[k],
            ax[0].w[i] * ax[1].w[j] * ax[2].dw[k]};
  }
};

inline StencilWeights stencil_weights(const Vec3& x, double inv_dx) {
  return {{quadratic_weights(x.x(), inv_dx), quadratic_weights(x.y(), inv_dx),
           quadratic_weights(x.z(), inv_dx)}};
}

// For quadratic B-splines the APIC/MLS-MPM inertia-like tensor is D_p = dx^2 / 4 I (thesis Eq. 2.24).
inline double apic_inverse_d(double dx) { return 4.0 / (dx * dx); }

}  // namespace shellfrac::mpm
