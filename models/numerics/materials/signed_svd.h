// The singular value decomposition of a deformation gradient with rotations on both
// sides (Irving, Teran and Fedkiw 2004, "Invertible finite elements for robust
// simulation of large deformation", section 5): F = U diag(sigma) V^T with
// det U = det V = +1, sigma_1 >= sigma_2 >= |sigma_3|, and sigma_3 < 0 exactly when
// det F < 0 (an inverted element keeps its rotation; the reflection goes into the
// smallest stretch). Then R = U V^T is the rotation nearest to F in the Frobenius
// norm for every F, inverted included (the Procrustes problem over SO(3)), and
// F = R S with S = V diag(sigma) V^T symmetric: the polar decomposition when
// det F > 0.
//
// Computed with Eigen's two-sided Jacobi SVD of the 3x3 matrix (Givens rotations to
// machine precision, deterministic, no iteration limit reached on rank-deficient or
// flat F), then the signs fixed: a reflection in U or V is moved into sigma_3.
#pragma once

#include <Eigen/Core>
#include <Eigen/SVD>

namespace tb {

struct SignedSvd {
  Eigen::Matrix3d U, V;  ///< rotations
  Eigen::Vector3d sigma;  ///< sigma_1 >= sigma_2 >= |sigma_3|; sigma_3 < 0 iff det F < 0
};

/// F = U diag(sigma) V^T (3x3), as above.
inline SignedSvd signed_svd(const Eigen::Matrix3d& F) {
  const Eigen::JacobiSVD<Eigen::Matrix3d> svd(F, Eigen::ComputeFullU | Eigen::ComputeFullV);
  SignedSvd r{svd.matrixU(), svd.matrixV(), svd.singularValues()};
  if (r.U.determinant() < 0) {
    r.U.col(2) = -r.U.col(2);
    r.sigma(2) = -r.sigma(2);
  }
  if (r.V.determinant() < 0) {
    r.V.col(2) = -r.V.col(2);
    r.sigma(2) = -r.sigma(2);
  }
  return r;
}

}  // namespace tb
