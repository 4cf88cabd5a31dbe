#pragma once
#include "nurbs/nurbs_surface.hpp"
#include "render_mesh/poly_mesh.hpp"

namespace shellfrac::render_mesh {

// An uncracked render mesh of a NURBS patch: an R x S quad grid, uniform in the parametric domain and
// independent of the simulation resolution. Vertices, normals and UVs are evaluated on the surface
// itself (UVs are the parameters normalised to [0, 1]).
PolyMesh tessellate(const nurbs::NurbsSurface& surface, int resolution_u, int resolution_v,
                    const std::string& name);

}  // namespace shellfrac::render_mesh
