#pragma once

namespace shellfrac::shell {

// Which stress the Type IV points use (docs/benchmarks.md compares them; thesis sec. 4.5, Fig. 4.10).
enum class StressModel {
  // Default: the Kirchhoff-Love in-plane stress of thesis Eq. 4.11-4.14 (see TransverseModel).
  KirchhoffLove,
  // Guo et al. 2018 style plane strain: F = [g_1 g_2 a_3] G^-1 with the fibre length kept and the full
  // 3D stress. Its transverse normal stress tau^33 = lambda ln J does no work (the fibre a_3 is a unit
  // vector, so da_3 is normal to it): the forces equal the rigid-fibre thesis stress, and tau^33 enters
  // only the damage criterion as a third principal stress.
  PlaneStrain,
  // Jiang et al. 2017 style: a 2D deformation gradient of the mid-surface and a 2D Neo-Hookean energy,
  // extrapolated through the thickness; the Type IV points carry no bending (the mid-surface metric only).
  MidSurface2D,
  // Jiang et al. 2017 with its third column: F = [a_1 a_2 d_3] D^-1 with d_3 the cell's Type III
  // director, so J = J_2D r_33 sees the director's compression r_33 (held fixed in the force pass).
  // Otherwise as MidSurface2D.
  DirectorF2D,
};

}  // namespace shellfrac::shell
