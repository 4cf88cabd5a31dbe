#pragma once
#include <string>
#include <vector>

#include "brittle/regions.hpp"
#include "brittle/tri_mesh.hpp"

namespace shellfrac::brittle {

// How fragments are cut out of the input mesh (thesis sec. 3.5.2, Fig. 3.9).
enum class Cutter {
  Exact,     // CGAL corefinement of region and domain meshes: volume-preserving, keeps the input surface
             // (with its UVs and normals) on the uncracked parts (Fig. 3.9d)
  LevelSet,  // OpenVDB level-set CSG at a voxel size (Fig. 3.9e): robust, loses a little volume
};
const char* to_string(Cutter c);

struct FragmentOptions {
  Cutter cutter = Cutter::Exact;
  double voxel = 0;             // LevelSet voxel; 0: the default, h_v / 4 from the crack grid
  double density = 1.0;         // for mass and inertia [kg/m^3]
  double uv_scale = 1.0;        // crack faces get box-projected UVs: position / uv_scale
  size_t memory_limit = size_t{2} << 30;
};

// One fragment: a closed mesh (its outer surface and any cavities) with per-vertex normals and UVs, and
// the mass properties of the solid it bounds.
struct Fragment {
  TriMesh mesh;            // name "<input name>_fragment_<k>"
  MassProperties properties;
  int region = -1;         // the Voronoi region it was cut from (-1 for the thickened-crack cut)
  size_t crack_triangles = 0;  // triangles on new (crack) surface, the rest come from the input
  std::vector<char> crack_faces;  // per triangle of mesh: 1 on the crack surface (fracture detail reads it)
};

struct FragmentSet {
  std::vector<Fragment> fragments;  // largest first
  Cutter cutter = Cutter::Exact;
  double voxel = 0;                 // LevelSet only
  double input_volume = 0;          // volume of the input mesh
  double total_volume() const;
  // (sum of fragment volumes - input volume) / input volume: ~1e-15 exact, a small loss with LevelSet.
  double volume_change() const;
};

// Fragments as region n domain for every Voronoi region (thesis sec. 3.5): the domain must be a closed
// solid (require_closed_solid, naming `source`). Pieces of one region that fall apart become separate
// fragments; cavities stay with the piece that encloses them. Throws InputError for an unusable mesh or
// a voxel too small for memory (with the estimate), NumericalError when a boolean fails (naming the region).
FragmentSet cut_fragments(const TriMesh& domain, const VoronoiDiagram& diagram, const Regions& regions,
                          const FragmentOptions& options, const std::string& source);

// Whether the exact cutter can take `mesh` as its domain: its CGAL surface (vertices welded by position,
// triangles added one by one) builds. A mesh require_closed_solid accepts always does; the tests hold the
// two checks to that.
bool exact_cutter_accepts(const TriMesh& mesh);

// Bytes the level-set cutter needs for narrow bands around `area` m^2 of surface at a voxel size (the
// estimate its memory check uses; the scene build refuses a voxel with it before the run).
double level_set_cut_bytes(double voxel, double area);

// Partial cracks as hairline gaps (thesis Fig. 3.9f): the domain minus the crack surface thickened to
// `width`, by OpenVDB level sets; every connected piece is a fragment (a crack that does not go through
// leaves one fragment with a gap). Uses options.voxel (0: width / 2).
FragmentSet cut_thickened_crack(const TriMesh& domain, const TriMesh& crack_surface, double width,
                                const FragmentOptions& options, const std::string& source);

// The crack surface clipped to the inside of the domain (for output): triangles split where the domain's
// signed distance (a level set of the given voxel size) changes sign.
TriMesh clip_to_domain(const TriMesh& crack_surface, const TriMesh& domain, double voxel);

// --- shared by the cutters (fragment_mesh.cpp) ---

// Splits a closed triangle soup into solids: connected components (by shared welded vertices) with
// positive volume, each with the negative-volume components (cavities) it encloses.
std::vector<TriMesh> split_solids(const TriMesh& mesh);
// Per-vertex normals and UVs for a cut piece: triangles lying on the input surface take the input's
// attributes (interpolated on the source triangle), the others (crack faces) a flat normal and a box
// projection. Returns the number of crack triangles; `crack`, when given, gets 1 per crack triangle.
size_t transfer_attributes(TriMesh& piece, const TriMesh& domain, double surface_tolerance, double uv_scale,
                           std::vector<char>* crack = nullptr);
// Builds the FragmentSet from the cut pieces of each region: splits, attributes, mass properties, names.
void add_fragments(FragmentSet& set, const TriMesh& cut, int region, const TriMesh& domain, const FragmentOptions& o,
                   double surface_tolerance);
// Largest first, named "<base>_fragment_<k>".
void finish_fragments(FragmentSet& set, const std::string& base);

}  // namespace shellfrac::brittle
