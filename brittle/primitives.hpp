#pragma once
#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// Closed triangle meshes of simple solids with per-vertex normals and UVs (vertices are split at sharp
// edges and UV seams), for scenes and tests. `segments` counts subdivisions around, `rings` along.
TriMesh box_mesh(const Vec3& centre, const Vec3& half_extents, int subdivisions = 1);
TriMesh sphere_mesh(const Vec3& centre, double radius, int segments = 32, int rings = 16);
// Axis along z, from centre - h/2 to centre + h/2.
TriMesh cylinder_mesh(const Vec3& centre, double radius, double height, int segments = 32);
// Ring in the xy plane: major radius R (centre to tube centre), minor radius r.
TriMesh torus_mesh(const Vec3& centre, double major_radius, double minor_radius, int segments = 32, int tube_segments = 16);

}  // namespace shellfrac::brittle
