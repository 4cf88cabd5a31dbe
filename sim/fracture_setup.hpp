#pragma once
// Per-point strength of the shells that fracture: the brittleness H of the damage law, failure-stress
// regions and the seeded Weibull factors (thesis sec. 2.3.1, 4.4.1; Fig. 4.23b).
#include "scene/model.hpp"
#include "sim/world.hpp"

namespace shellfrac::sim {

// Sets H from sigma_f, G_f, E and the characteristic length l_ch = sqrt(3) dx of the grid, then the regions'
// failure stresses (and their own H when they give a fracture energy), then the Weibull factors, on every
// shell with a fracture material. Throws SceneError, at the fracture energy's path, when G_f is too small for
// the grid (linear softening would snap back).
void init_fracture(const scene::Model& model, World& world, double grid_dx);

}  // namespace shellfrac::sim
