// Conjugate gradients on a symmetric positive definite K, warm-started from the
// caller's x, preconditioned by incomplete Cholesky (IC) alone or by a two-level
// additive preconditioner: IC plus a Galerkin coarse-space correction
// P (P^T K P)^-1 P^T, where P interpolates a coarse mesh's nodal displacements to
// the fine dofs (the hybrid's coarse tets; the iteration counts it saves are in
// docs/paper_reproduction.md). Written out rather than with Eigen's ConjugateGradient so
// that a solve touches no heap: every work vector is allocated in the constructor.
#pragma once

#include <Eigen/IterativeLinearSolvers>
#include <Eigen/SparseCore>
#include <algorithm>
#include <memory>
#include <stdexcept>
#include <string>

namespace tb {

/// Work vectors of conjugate_gradients, sized once (no allocation per solve).
struct CgWorkspace {
  explicit CgWorkspace(Eigen::Index n = 0) { resize(n); }
  void resize(Eigen::Index n) {
    for (Eigen::VectorXd* v : {&r, &z, &p, &q}) v->setZero(n);
  }
  Eigen::VectorXd r, z, p, q;
};

/// Preconditioned conjugate gradients on A x = b for any symmetric positive
/// definite operator, the loop every CG in the project runs:
///   apply(p, q)        q = A p
///   precondition(r, z) z = B r, B symmetric positive definite (approximately A^-1)
/// x is the warm start and the result. Stops when |b - A x| <= tolerance |b|, or
/// <= reduction |b - A x_0| (an inexact solve inside an outer iteration; 0: off);
/// returns the iterations (0: x already satisfied the first). Throws
/// std::runtime_error after max_iterations. No allocation when w has the size of b.
template <class Apply, class Precondition>
int conjugate_gradients(Apply&& apply, Precondition&& precondition, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                        double tolerance, int max_iterations, CgWorkspace& w, double reduction = 0);

class SupernodalCholesky;

class PreconditionedCG {
 public:
  ///   matrix              both triangles stored; kept by reference, must outlive this
  ///   relative_tolerance  stop when |b - K x| <= relative_tolerance |b|
  ///   prolongation        #dofs by #coarse dofs; nullptr: IC alone
  /// Throws std::runtime_error if the incomplete factorisation fails.
  PreconditionedCG(const Eigen::SparseMatrix<double>& matrix, double relative_tolerance, int max_iterations,
                   const Eigen::SparseMatrix<double>* prolongation = nullptr);
  ~PreconditionedCG();

  /// Improves x (the warm start) until the tolerance is met; returns the number of
  /// iterations. Throws std::runtime_error if max_iterations is reached first.
  int solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

 private:
  /// z = M^-1 r with M = P^T S^-1 L L^T S^-1 P, Eigen's IncompleteCholesky factor.
  void apply_ic(const Eigen::VectorXd& r, Eigen::VectorXd& z);
  /// z = B r, B the preconditioner (IC, or IC plus the coarse correction).
  void precondition(const Eigen::VectorXd& r, Eigen::VectorXd& z);

  const Eigen::SparseMatrix<double>& K_;
  Eigen::IncompleteCholesky<double, Eigen::Lower, Eigen::AMDOrdering<int>> ic_;
  Eigen::SparseMatrix<double> P_, Pt_;          ///< prolongation and restriction (empty: none)
  std::unique_ptr<SupernodalCholesky> coarse_;  ///< of P^T K P
  double tolerance_;
  int max_iterations_;
  CgWorkspace work_;
  Eigen::VectorXd t_, rc_, uc_;  ///< work vectors of the preconditioner
};

template <class Apply, class Precondition>
int conjugate_gradients(Apply&& apply, Precondition&& precondition, const Eigen::VectorXd& b, Eigen::VectorXd& x,
                        double tolerance, int max_iterations, CgWorkspace& w, double reduction) {
  double threshold = tolerance * tolerance * b.squaredNorm();
  apply(x, w.r);
  w.r = b - w.r;
  if (w.r.squaredNorm() <= threshold) return 0;
  threshold = std::max(threshold, reduction * reduction * w.r.squaredNorm());
  precondition(w.r, w.z);
  w.p = w.z;
  double rz = w.r.dot(w.z);
  for (int it = 1; it <= max_iterations; ++it) {
    apply(w.p, w.q);
    const double alpha = rz / w.p.dot(w.q);
    x += alpha * w.p;
    w.r -= alpha * w.q;
    if (w.r.squaredNorm() <= threshold) return it;
    precondition(w.r, w.z);
    const double rz_new = w.r.dot(w.z);
    w.p = w.z + (rz_new / rz) * w.p;
    rz = rz_new;
  }
  throw std::runtime_error("CG did not reach the relative tolerance in " + std::to_string(max_iterations) +
                           " iterations");
}

}  // namespace tb
