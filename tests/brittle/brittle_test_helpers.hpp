#pragma once
// Small builders shared by the brittle tests.
#include "brittle/brittle_solid.hpp"
#include "brittle/primitives.hpp"

namespace shellfrac::brittle::testing {

// A soft, light test material (fast explicit steps): E 1 MPa, nu 0.3, 1000 kg/m^3; strength and
// fracture energy chosen by the test.
inline BrittleMaterial soft_material(double failure_stress = 1e4, double fracture_energy = 10.0) {
  BrittleMaterial m;
  m.youngs_modulus = 1e6;
  m.poisson_ratio = 0.3;
  m.density = 1000;
  m.failure_stress = failure_stress;
  m.fracture_energy = fracture_energy;
  return m;
}

// A box of particles on a regular lattice of the given spacing (half-spacing from the faces).
inline BrittleSolid lattice_box(const Vec3& centre, const Vec3& half, double spacing, const BrittleMaterial& material,
                                double grid_dx) {
  BrittleSolid s = make_solid(box_mesh(centre, half, 1), material, spacing, Sampling::Regular, 1, "test box");
  s.set_strength({}, WeibullStrength{}, grid_dx);
  return s;
}

// A square (2 triangles) in the plane z = z0 covering [-h, h]^2 around (cx, cy).
inline TriMesh square_z(double cx, double cy, double z0, double h) {
  TriMesh m;
  m.positions = {Vec3(cx - h, cy - h, z0), Vec3(cx + h, cy - h, z0), Vec3(cx + h, cy + h, z0), Vec3(cx - h, cy + h, z0)};
  m.triangles = {Tri(0, 1, 2), Tri(0, 2, 3)};
  return m;
}

}  // namespace shellfrac::brittle::testing
