// Solving with a factorised symmetric matrix minus a low-rank term, K - U U^T, on
// K's factor alone: the Sherman-Morrison-Woodbury identity (Golub and Van Loan 2013,
// Matrix Computations, 4th ed., eq. 2.1.4),
//   (K - U U^T)^-1 = K^-1 + W C^-1 W^T,   W = K^-1 U,   C = I - U^T W (the capacitance),
// so with X = K^-1 B, (K - U U^T)^-1 B = X + W C^-1 U^T X.
// The Newton solve's contact uses it for the gap's curvature, a rank-2 term per node
// in contact (newton_solve.cc): K's sparse Cholesky factor stays supernodal and
// positive definite while K - U U^T may be indefinite. With K positive definite,
// K - U U^T has as many negative eigenvalues as C (Haynsworth's inertia additivity on
// the block matrix [K U; U^T I]), which is how `negative_eigenvalues` knows.
#pragma once

#include <Eigen/Dense>
#include <algorithm>
#include <utility>

namespace tb {

class LowRankDowndate {
 public:
  /// Prepares the solve with K - U U^T from U (n x k) and W = K^-1 U. False when C is
  /// singular to round-off (K - U U^T is then singular): smallest |eigenvalue| of C
  /// below 1e-12 times its largest or 1.
  bool prepare(Eigen::MatrixXd U, Eigen::MatrixXd W) {
    U_ = std::move(U);
    W_ = std::move(W);
    const Eigen::Index k = U_.cols();
    negative_ = 0;
    if (k == 0) return true;
    Eigen::MatrixXd C = Eigen::MatrixXd::Identity(k, k) - U_.transpose() * W_;
    C = 0.5 * (C + C.transpose());  // symmetric to round-off; exactly so for the eigensolver
    eigen_.compute(C);
    const Eigen::VectorXd& e = eigen_.eigenvalues();
    const double largest = std::max(1.0, e.cwiseAbs().maxCoeff());
    if (!(e.cwiseAbs().minCoeff() > 1e-12 * largest)) return false;
    negative_ = static_cast<int>((e.array() < 0).count());
    return true;
  }

  /// No term: apply() leaves K^-1 B as it is.
  void clear() {
    U_.resize(0, 0);
    W_.resize(0, 0);
    negative_ = 0;
  }

  /// X = K^-1 B in, (K - U U^T)^-1 B out (one column or many).
  template <class Matrix>
  void apply(Matrix& X) const {
    if (W_.cols() == 0) return;
    const Eigen::MatrixXd& Q = eigen_.eigenvectors();
    const Eigen::MatrixXd coefficients = Q * (eigen_.eigenvalues().cwiseInverse().asDiagonal() *
                                              (Q.transpose() * (U_.transpose() * X)));
    X += W_ * coefficients;
  }

  /// The rank of the term (k); 0 when there is none.
  Eigen::Index rank() const { return W_.cols(); }
  /// How many negative eigenvalues K - U U^T has, given K positive definite.
  int negative_eigenvalues() const { return negative_; }

 private:
  Eigen::MatrixXd U_, W_;
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen_;
  int negative_ = 0;
};

}  // namespace tb
