// Conjugate gradients with an incomplete-Cholesky preconditioner on a symmetric
// positive definite matrix, warm-started from the caller's x. Written out (rather
// than Eigen's ConjugateGradient) so that a solve touches no heap: every work
// vector is allocated in the constructor.
#pragma once

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>

namespace tb {

class IncompleteCholeskyCG {
 public:
  ///   matrix              both triangles stored; kept by reference, must outlive this
  ///   relative_tolerance  stop when |b - K x| <= relative_tolerance |b|
  /// Throws std::runtime_error if the incomplete factorisation fails.
  IncompleteCholeskyCG(const Eigen::SparseMatrix<double>& matrix, double relative_tolerance, int max_iterations);

  /// Improves x (the warm start) until the tolerance is met; returns the number of
  /// iterations. Throws std::runtime_error if max_iterations is reached first.
  int solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

 private:
  /// z = M^-1 r with M = P^T S^-1 L L^T S^-1 P, Eigen's IncompleteCholesky factor.
  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z);

  const Eigen::SparseMatrix<double>& K_;
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> ic_;
  double tolerance_;
  int max_iterations_;
  Eigen::VectorXd r_, z_, p_, q_, t_;
};

}  // namespace tb
