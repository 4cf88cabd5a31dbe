#pragma once
#include <limits>
#include <vector>

#include "brittle/crack_grid.hpp"
#include "brittle/voronoi.hpp"

namespace shellfrac::brittle {

struct CrackExtractionOptions {
  CrackGridOptions grid;          // h_v, damage threshold, N radius, memory limit
  double site_jitter = 0.05;      // sites move up to this fraction of h_v off their nodes (general position)
  unsigned long long seed = 1;    // of the jitter
  int orientation_search = 4000;  // states the BFS of Algorithm 3 may visit before it gives up
  // A box the Voronoi container must also cover (the object's mesh, whose surface may reach past the
  // particles' B' nodes where a thin feature holds no particle). Empty by default.
  Vec3 cover_lo = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 cover_hi = Vec3::Constant(-std::numeric_limits<double>::infinity());
};

// The extracted crack (thesis sec. 3.3): the Voronoi diagram of V u B' and, per face, whether it is a
// crack face (interior medial face, Algorithm 1, or extension face, Algorithms 2-3).
struct CrackExtraction {
  std::vector<long> site_node;     // grid node of each Voronoi site
  VoronoiDiagram diagram;
  std::vector<char> crack_face;    // per diagram face: 0 no, 1 interior (Alg. 1), 2 extension (Alg. 2-3)
  size_t interior_faces = 0, extension_faces = 0;
  size_t undecided_pairs = 0;      // extension candidates whose orientation search found no path
  Vec3 grid_lower = Vec3::Zero();  // for diagnostics
  // Node-set sizes (thesis Table 3.1).
  size_t count_D = 0, count_B = 0, count_Bd = 0, count_S = 0, count_V = 0, count_I = 0, count_E = 0, count_N = 0;
  bool empty() const { return interior_faces + extension_faces == 0; }
};

// Runs sec. 3.3 on material-space particle positions and damage histories. Degenerate inputs (no damaged
// particle, damage only at the boundary, sites in a plane) give an empty or partial crack, never a crash.
// Throws InputError for bad options (h_v, memory) and NumericalError when the Voronoi step fails.
CrackExtraction extract_crack(const std::vector<Vec3>& rest, const std::vector<double>& damage_history,
                              const CrackExtractionOptions& options);

// The crack faces as one triangle mesh (fans of the Voronoi polygons, stars around the centres of faces
// bent by the crack smoothing; vertices shared), possibly non-manifold. With `kinds`, per triangle 1 (interior) or 2 (extension).
TriMesh crack_surface_mesh(const CrackExtraction& crack, std::vector<char>* kinds = nullptr);

}  // namespace shellfrac::brittle
