#pragma once
#include <cstddef>
#include <memory>
#include <vector>

namespace shellfrac::brittle {

// A sparse symmetric positive definite system A x = b solved by CHOLMOD's supernodal Cholesky
// (SuiteSparse). The pattern is given once as the upper triangle in compressed columns; analyse() runs
// the fill-reducing ordering and the supernodal symbolic factorisation, which is the expensive part and
// is redone only when the pattern changes. Each factorize() is numeric only. The CHOLMOD types stay in
// the .cpp file.
class CholmodSolver {
 public:
  CholmodSolver();
  ~CholmodSolver();
  CholmodSolver(const CholmodSolver&) = delete;
  CholmodSolver& operator=(const CholmodSolver&) = delete;

  // Upper-triangle pattern of an n x n matrix: column j holds rows row_index[column_start[j] ..
  // column_start[j + 1]), sorted, each <= j, the diagonal included. Throws NumericalError when CHOLMOD
  // fails (out of memory).
  void analyse(size_t n, const std::vector<int>& column_start, const std::vector<int>& row_index);
  // The values of the pattern's entries, in its order; the caller fills them before factorize().
  double* values();
  size_t nonzeros() const;
  size_t size() const;
  // Numeric Cholesky of the current values. Throws NumericalError when the matrix is not positive
  // definite (naming the column CHOLMOD stopped at).
  void factorize();
  // x = A^{-1} b with the last factorisation.
  void solve(const double* b, double* x) const;
  size_t analyses() const { return analyses_; }
  // Nonzeros of the factor L (fill), for reports.
  double factor_nonzeros() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
  size_t analyses_ = 0;
};

}  // namespace shellfrac::brittle
