#pragma once
#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "brittle/solid_grid.hpp"

namespace shellfrac::brittle {

class CholmodSolver;

enum class PhaseFieldSolver {
  ConjugateGradient,  // matrix-free, Jacobi preconditioned (as CD-MPM sec. 4.2.2)
  Cholmod,            // assembled, supernodal Cholesky (SuiteSparse)
};
const char* to_string(PhaseFieldSolver s);

// The gradient of the grid shape functions at a particle in the Laplace term H.
enum class PhaseFieldGradient {
  Spline,  // the derivative of the quadratic B-spline: second-order accurate (the default)
  Mls,     // the MLS gradient of CD-MPM sec. 4.2.2, (4 / dx^2) w_ip (x_i - x_p): exact for linear
           // fields only, so the crack profile converges at first order
};
const char* to_string(PhaseFieldGradient g);

// Parameters of the non-local phase field of CD-MPM (seed 001, sec. 3.4.2 and 4.2). SI units.
struct PhaseFieldOptions {
  double length_scale = 0;   // l_0 [m]; 0 = half the grid spacing (the paper's default)
  double mobility = 0;       // M_c [1/s]: how fast c relaxes to its equilibrium; must be > 0
  double residual = 1e-3;    // r in g(c) = (1 - r) c^2 + r (Eq. 3)
  PhaseFieldSolver solver = PhaseFieldSolver::ConjugateGradient;
  PhaseFieldGradient gradient = PhaseFieldGradient::Spline;
  size_t interval = 1;       // solve every k-th step
  double tolerance = 1e-10;  // CG: stop when |b - A c| <= tolerance |b|
  size_t max_iterations = 200;
  // A particle whose c falls to this value counts as fully broken (its damage history reaches 1 and
  // its damage time is set): g(0.05) = 0.0035, the stiffness left is negligible.
  double broken_below = 0.05;
  // Empty when valid, else what is wrong (for the scene reader's message).
  std::string validate() const;
};

// What the system reads from the particles, and the phase value it writes back.
struct PhaseFieldParticles {
  size_t count = 0;
  const GVec3* x = nullptr;
  const double* volume = nullptr;   // current volume V_p^n = V_p^0 J_p
  const double* history = nullptr;  // Psi^H_p: the largest tensile energy density so far [J/m^3]
  double* c = nullptr;              // c_p, 1 healthy .. 0 broken; updated in place
};

struct PhaseFieldStats {
  size_t unknowns = 0;       // free active nodes
  size_t iterations = 0;     // CG iterations (0 for CHOLMOD)
  double residual = 0;       // |b - A c| / |b| after the solve
  bool analysed = false;     // CHOLMOD redid its symbolic analysis (the active set changed)
  bool converged = true;
};

// The phase-field system (M + H) c = r of CD-MPM Eq. 7 on a SolidGrid's nodes, built from the
// particles every solve:
//   M_ii = sum_p V_p (4 l0 M_c (1 - r) Psi^H_p / G + M_c + 1/dt) w_ip          (lumped)
//   H_ij = sum_p V_p 4 l0^2 M_c grad Theta_i(x_p) . grad Theta_j(x_p),  grad Theta_i = 4/dx^2 w_ip (x_i - x_p)
//   r_i  = sum_p V_p (M_c + c_p^n / dt) w_ip
// with c_i^n = sum_p w_ip c_p / sum_p w_ip, and back to the particles by the non-healing FLIP update
// c_p = max(0, min(c_p, c_p + sum_i w_ip (c_i^{n+1} - c_i^n))) (sec. 4.2.1). dt = 0 solves the static
// equation (no 1/dt terms). The free surface needs nothing: the weak form's natural condition is
// Neumann. All scatters run in the grid's slab colours, so results do not depend on the thread count.
class PhaseFieldSystem {
 public:
  PhaseFieldSystem(const PhaseFieldOptions& options, double fracture_energy, double dx);
  ~PhaseFieldSystem();

  // One solve on `grid` (already rebuilt over the particles). At each of `broken_points` the
  // interpolated field c_h(x) = sum_i w_i(x) c_i is held at 0 by a penalty (a prescribed crack, and
  // the Dirichlet condition of the 1D validation). A penalty on the field value rather than on node
  // values: a quadratic B-spline's node values are not its values, and holding nodes at 0 would move
  // the crack by a fraction of a cell.
  PhaseFieldStats solve(const SolidGrid& grid, const PhaseFieldParticles& p, double dt,
                        const std::vector<GVec3>& broken_points = {});

  // After a solve: c_i^{n+1} per grid node (1 at nodes no particle reaches).
  const std::vector<double>& node_values() const { return c_; }
  double length_scale() const { return l0_; }
  const PhaseFieldOptions& options() const { return options_; }
  // Symbolic analyses CHOLMOD has run so far.
  size_t analyses() const;

  // For tests: y = (M + H) x on the free nodes of the last assembly (dense node vectors).
  void apply(const SolidGrid& grid, const PhaseFieldParticles& p, const std::vector<double>& x, std::vector<double>& y) const;
  // For tests: the assembled upper triangle of the last CHOLMOD solve as (row, column, value) in free-
  // node numbering, and the node index of each unknown.
  struct Entry {
    int row, col;
    double value;
  };
  std::vector<Entry> assembled_upper() const;
  const std::vector<long>& unknown_nodes() const { return unknown_node_; }

 private:
  void assemble(const SolidGrid& grid, const PhaseFieldParticles& p, double dt);
  void add_penalty(const SolidGrid& grid, const std::vector<GVec3>& points);
  void solve_cg(const SolidGrid& grid, const PhaseFieldParticles& p, PhaseFieldStats& stats);
  void solve_cholmod(const SolidGrid& grid, const PhaseFieldParticles& p, PhaseFieldStats& stats);
  void update_pattern(const SolidGrid& grid, PhaseFieldStats& stats);

  PhaseFieldOptions options_;
  double G_, dx_, l0_;
  // Dense node vectors over the grid box.
  std::vector<double> c_old_, c_, diag_, rhs_, precond_;
  std::vector<uint8_t> free_;
  // The assembly's scratch: the four w-weighted sums of a node side by side (one vector per node).
  struct alignas(32) LumpedNode {
    double weight, weighted_c, mass, source;
  };
  std::vector<LumpedNode> lumped_;
  std::vector<GVec3> penalty_points_;
  double penalty_ = 0;  // weight of the broken-point penalty
  // CHOLMOD: unknown number per node (-1 if not free), node per unknown, and per unknown column the
  // position of each of its 125 neighbours' upper entries (-1 where there is none).
  std::vector<int> unknown_of_;
  std::vector<long> unknown_node_;
  std::vector<Eigen::Vector3i> unknown_coord_;
  std::vector<int> entry_of_;
  std::vector<int> column_start_, row_index_;
  std::unique_ptr<CholmodSolver> cholmod_;
};

}  // namespace shellfrac::brittle
