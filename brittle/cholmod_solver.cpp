#include "brittle/cholmod_solver.hpp"

#include <cholmod.h>

#include <cstring>
#include <sstream>

#include "brittle/errors.hpp"

namespace shellfrac::brittle {

struct CholmodSolver::State {
  cholmod_common common;
  cholmod_sparse* A = nullptr;
  cholmod_factor* L = nullptr;

  State() {
    cholmod_start(&common);
    common.supernodal = CHOLMOD_SUPERNODAL;
    common.print = 0;  // errors are reported by status, not printed
  }
  ~State() {
    release();
    cholmod_finish(&common);
  }
  void release() {
    if (L) cholmod_free_factor(&L, &common);
    if (A) cholmod_free_sparse(&A, &common);
  }
  void check(const char* what) const {
    if (common.status < CHOLMOD_OK) {
      std::ostringstream m;
      m << "phase field: CHOLMOD " << what << " failed (status " << common.status
        << (common.status == CHOLMOD_OUT_OF_MEMORY ? ", out of memory" : "") << ")";
      throw NumericalError(m.str());
    }
  }
};

CholmodSolver::CholmodSolver() : state_(std::make_unique<State>()) {}
CholmodSolver::~CholmodSolver() = default;

void CholmodSolver::analyse(size_t n, const std::vector<int>& column_start, const std::vector<int>& row_index) {
  State& s = *state_;
  s.release();
  const size_t nnz = row_index.size();
  // stype 1: only the upper triangle is stored and referenced.
  s.A = cholmod_allocate_sparse(n, n, nnz, /*sorted=*/1, /*packed=*/1, /*stype=*/1, CHOLMOD_REAL, &s.common);
  s.check("allocation");
  std::memcpy(s.A->p, column_start.data(), (n + 1) * sizeof(int));
  std::memcpy(s.A->i, row_index.data(), nnz * sizeof(int));
  std::memset(s.A->x, 0, nnz * sizeof(double));
  s.L = cholmod_analyze(s.A, &s.common);
  s.check("symbolic analysis");
  ++analyses_;
}

double* CholmodSolver::values() { return static_cast<double*>(state_->A->x); }
size_t CholmodSolver::nonzeros() const { return state_->A ? state_->A->nzmax : 0; }
size_t CholmodSolver::size() const { return state_->A ? state_->A->nrow : 0; }

void CholmodSolver::factorize() {
  State& s = *state_;
  cholmod_factorize(s.A, s.L, &s.common);
  s.check("factorisation");
  if (s.common.status == CHOLMOD_NOT_POSDEF) {
    std::ostringstream m;
    m << "phase field: the system matrix is not positive definite (CHOLMOD stopped at column " << s.L->minor << ")";
    throw NumericalError(m.str());
  }
}

void CholmodSolver::solve(const double* b, double* x) const {
  State& s = *state_;
  const size_t n = s.A->nrow;
  cholmod_dense* B = cholmod_allocate_dense(n, 1, n, CHOLMOD_REAL, &s.common);
  s.check("allocation");
  std::memcpy(B->x, b, n * sizeof(double));
  cholmod_dense* X = cholmod_solve(CHOLMOD_A, s.L, B, &s.common);
  cholmod_free_dense(&B, &s.common);
  s.check("solve");
  std::memcpy(x, X->x, n * sizeof(double));
  cholmod_free_dense(&X, &s.common);
}

double CholmodSolver::factor_nonzeros() const { return state_->common.lnz; }

}  // namespace shellfrac::brittle
