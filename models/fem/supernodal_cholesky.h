// Sparse Cholesky factorisation K = P^T L L^T P with CHOLMOD (supernodal, OpenBLAS),
// made once; solve() then back-substitutes without touching the heap: CHOLMOD's
// solve2 reuses its solution and workspace arrays, sized by a first solve in the
// constructor. CHOLMOD picks the fill-reducing ordering itself (AMD, and METIS
// when AMD's fill is high; on the paper's cube METIS gives 2.8M nonzeros in L
// against AMD's 3.6M, so the per-frame read of the factor is 22% smaller).
#pragma once

#include <Eigen/SparseCore>
#include <memory>

namespace tb {

class SupernodalCholesky {
 public:
  /// Factorises the symmetric positive definite `matrix` (only its lower triangle
  /// is read). Throws std::runtime_error if it is not positive definite.
  explicit SupernodalCholesky(const Eigen::SparseMatrix<double>& matrix);
  ~SupernodalCholesky();
  SupernodalCholesky(const SupernodalCholesky&) = delete;
  SupernodalCholesky& operator=(const SupernodalCholesky&) = delete;

  /// x = K^-1 b. No heap allocation once constructed; x must have the size of b.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

  /// Nonzeros of the factor L, and CHOLMOD's name of the ordering it chose.
  double factor_nonzeros() const;
  const char* ordering() const;

 private:
  struct Cholmod;
  std::unique_ptr<Cholmod> c_;
};

}  // namespace tb
