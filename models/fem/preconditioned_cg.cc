#include "preconditioned_cg.h"

#include <stdexcept>

namespace tb {

IncompleteCholeskyCG::IncompleteCholeskyCG(const Eigen::SparseMatrix<double>& matrix, double relative_tolerance,
                                           int max_iterations)
    : K_(matrix), tolerance_(relative_tolerance), max_iterations_(max_iterations) {
  ic_.compute(matrix);
  if (ic_.info() != Eigen::Success) throw std::runtime_error("incomplete Cholesky preconditioner failed");
  const Eigen::Index n = matrix.rows();
  for (Eigen::VectorXd* v : {&r_, &z_, &p_, &q_, &t_}) v->setZero(n);
}

void IncompleteCholeskyCG::precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z) {
  // Eigen's IncompleteCholesky::_solve_impl step by step, in place.
  const auto& perm = ic_.permutationP().indices();
  const Eigen::VectorXd& S = ic_.scalingS();
  const Eigen::Index n = r.size();
  for (Eigen::Index i = 0; i < n; ++i) t_(perm(i)) = r(i);  // t = P r
  t_.array() *= S.array();
  ic_.matrixL().triangularView<Eigen::Lower>().solveInPlace(t_);
  ic_.matrixL().transpose().triangularView<Eigen::Upper>().solveInPlace(t_);
  t_.array() *= S.array();
  for (Eigen::Index i = 0; i < n; ++i) z(i) = t_(perm(i));  // z = P^-1 t
}

int IncompleteCholeskyCG::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  const double threshold = tolerance_ * tolerance_ * b.squaredNorm();
  r_.noalias() = K_ * x;
  r_ = b - r_;
  if (r_.squaredNorm() <= threshold) return 0;
  precondition(r_, z_);
  p_ = z_;
  double rz = r_.dot(z_);
  for (int it = 1; it <= max_iterations_; ++it) {
    q_.noalias() = K_ * p_;
    const double alpha = rz / p_.dot(q_);
    x += alpha * p_;
    r_ -= alpha * q_;
    if (r_.squaredNorm() <= threshold) return it;
    precondition(r_, z_);
    const double rz_new = r_.dot(z_);
    p_ = z_ + (rz_new / rz) * p_;
    rz = rz_new;
  }
  throw std::runtime_error("CG did not reach the relative tolerance in " + std::to_string(max_iterations_) +
                           " iterations");
}

}  // namespace tb
