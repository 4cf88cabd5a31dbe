#pragma once
// The particles of one shell patch as the grid transfers see them (thesis sec. 4.3.2): the control points
// (Type II, the advected degrees of freedom) and one Type III particle per cell. Structure of arrays.
#include <vector>

#include "shell/kinematics.hpp"

namespace shellfrac::shell {

// Type-III particles: one per cell at the parameter location of the cell's middle control point
// (thesis sec. 4.3.2). They carry the elastic director d_3 that the grid velocity advects, and resist
// compression and (under friction) shear.
struct ShearParticles {
  std::vector<Vec3> x, v;              // position (NURBS-interpolated, thesis Eq. 4.10); grid velocity
  std::vector<double> mass;            // ShellMaterial::shear_mass_share of the cell's mass
  std::vector<Vec3> director;          // elastic d_3
  std::vector<Mat3> reference_inverse; // D^-1 with D = E^T [A_1 A_2 N] in the local frame E = [E_1 E_2 N]
  std::vector<Mat3> stress;            // grid stress term S_p = V dpsi/dd_3 (x) d_3
  std::vector<Mat3> velocity_gradient; // grid velocity gradient at x, written by g2p
  std::vector<double> volume;          // cell area x thickness
  std::vector<double> basis;           // per particle: support x {R, R_1, R_2}
};

struct PatchParticles {
  // Type II state.
  std::vector<Vec3> x, v;
  std::vector<double> mass;  // consistent-row-sum lumped: the control points' share of the patch's mass
  std::vector<Vec3> force;   // Kirchhoff-Love force per control point, written by the force pass
  // Type III state.
  ShearParticles shear;
};

}  // namespace shellfrac::shell
