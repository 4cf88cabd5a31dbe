#pragma once
#include <optional>
#include <vector>

#include "brittle/damage.hpp"
#include "brittle/fragments.hpp"

namespace shellfrac::brittle {

// Fracture detail from the damage time (thesis sec. 3.7, Algorithm 4, Table 3.2): chevron marks traced
// along the gradient of the time at which the material broke, raised out of the crack faces. The crack
// surface of the medial-axis extraction is flat at the scale of the crack grid; this adds the plateaus and
// ledges that show which way the crack ran.
//
// It works on the cut fragments: their crack triangles are refined to the edge length d, every crack
// vertex (welded by position across the fragments) gets tau and grad tau from the particles (Eq. 3.13,
// 3.14), Algorithm 4 traces the chevron lines over those vertices, the lines' heights beta are smoothed
// through a grid of spacing h_c, and each vertex moves by n beta' G. Both faces of a crack see the same
// welded vertex, normal and height, so the fragments still fit together; vertices on the object's surface
// (the rims of the crack faces) and where three or more fragments meet stay where they are.
struct FractureDetailOptions {
  double height = 0;     // G: global perturbation magnitude [m]; 0 adds no detail (the default)
  double edge = 0;       // d: crack faces are refined until no edge is longer [m]
  double step = 0;       // extension step of a chevron line [m]
  int max_steps = 50;    // l_c: steps a chevron line takes at most (Table 3.3 uses 50 and 60)
  double radius = 0;     // s: a line marks the vertices within this distance across it as visited [m]
  double grid = 0;       // h_c: spacing of the grid that smooths the heights and the damage time [m]
  double max_triangles = 2e7;  // crack triangles the refinement may make (over all fragments, both sides)
  double enhanced = 0.1; // m: share of the longest lines whose height grows away from their source (Table 3.3: 0.05, 0.1)
  bool enabled() const { return height > 0; }
};

struct FractureDetailReport {
  double edge = 0;              // the refinement edge used: d, or larger where d would pass max_triangles
  size_t crack_vertices = 0;    // welded crack vertices after refinement
  size_t timed_vertices = 0;    // of which the damage time reaches (a broken particle within the stencil)
  size_t lines = 0, enhanced_lines = 0;
  size_t longest_line = 0;      // vertices on the longest chevron line
  size_t moved_vertices = 0;
  double max_displacement = 0;  // [m]
  size_t folded_triangles = 0;  // crack triangles the moves turned over (a height too large for d)
  double seconds = 0;
};

// Damage time on a grid of spacing h (thesis Eq. 3.13) from the particles that broke (tau >= 0), with
// quadratic B-spline weights; nodes that no broken particle reaches have no value.
class DamageTimeGrid {
 public:
  DamageTimeGrid(const std::vector<Vec3>& rest, const std::vector<ParticleDamage>& damage, double h);
  // tau at x, the weighted mean of the valued nodes of x's stencil; none when no node has a value.
  std::optional<double> time(const Vec3& x) const;
  // grad tau at x (Eq. 3.14, M = h^2/4): sum_i w_i M^-1 (x_i - x) (tau_i - tau(x)) over the valued nodes,
  // divided by their weight. With every node of the stencil valued this is Eq. 3.14 itself (the weights
  // sum to one and their first moment vanishes); subtracting tau(x) keeps a partly valued stencil from
  // pointing at the missing nodes. Zero where no node has a value.
  Vec3 gradient(const Vec3& x) const;
  size_t nodes() const { return nodes_.size(); }

 private:
  struct Node {
    double weighted = 0, weight = 0;
  };
  const Node* find(long i, long j, long k) const;
  double h_;
  std::vector<std::pair<long long, Node>> nodes_;  // sorted by key
};

// Splits every crack triangle (crack[t] != 0) edge longer than `edge` at its midpoint, with the
// non-crack triangles that share it, until no crack edge is longer. Which edges split depends on their end
// positions only, so two fragments with the same crack face split it the same way, and the mesh stays
// closed. New vertices interpolate normals and UVs; `crack` follows the triangles.
void refine_crack_faces(TriMesh& mesh, std::vector<char>& crack, double edge);

// Algorithm 4 on a point set with normals: starting from the earliest unvisited point, each line steps
// `step` along the tangential part of grad tau to the nearest point, marking the points within `radius`
// across its direction (and within step/2 along it) as visited, for at most max_steps steps or until the
// nearest point was visited. Points without a time come last and start lines of one point. Returns the
// lines as point indices from their source on.
std::vector<std::vector<size_t>> trace_chevron_lines(const std::vector<Vec3>& points, const std::vector<Vec3>& normals,
                                                     const std::vector<double>& time, const std::vector<Vec3>& gradient,
                                                     double step, int max_steps, double radius);

// Adds the detail to every fragment of `set` that records its crack triangles, then recomputes their
// normals and mass properties (density). Throws InputError for non-positive lengths.
FractureDetailReport add_fracture_detail(FragmentSet& set, const std::vector<Vec3>& rest,
                                         const std::vector<ParticleDamage>& damage, const FractureDetailOptions& options,
                                         double density);

}  // namespace shellfrac::brittle
