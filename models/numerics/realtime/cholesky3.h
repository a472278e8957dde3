// The Cholesky factor of a symmetric 3x3 matrix written out, for the per-vertex
// Newton step of Vertex Block Descent (vbd_solve.cc), which factors one per vertex
// visit. Eigen's LLT<Matrix3d> runs its general loop for a fixed size; written out,
// the factor and its two triangular solves are straight-line code with one
// reciprocal per pivot. It fails where a pivot is not positive (the matrix is not
// positive definite), as Eigen's LLT does, and also where a pivot is NaN (which
// Eigen's passes on into a NaN solution); it reads the lower triangle only. Both are
// always inlined: called from VBD's AVX2 kernels (target attributes), GCC kept them
// out of line, a call per vertex visit (perf: 5 % of a frame).
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace tb {

class Cholesky3 {
 public:
  [[gnu::always_inline]] explicit Cholesky3(const Eigen::Matrix3d& A) {
    const double d0 = A(0, 0);
    if (!(d0 > 0)) return;
    r0_ = 1 / std::sqrt(d0);
    l10_ = A(1, 0) * r0_;
    l20_ = A(2, 0) * r0_;
    const double d1 = A(1, 1) - l10_ * l10_;
    if (!(d1 > 0)) return;
    r1_ = 1 / std::sqrt(d1);
    l21_ = (A(2, 1) - l20_ * l10_) * r1_;
    const double d2 = A(2, 2) - l20_ * l20_ - l21_ * l21_;
    if (!(d2 > 0)) return;
    r2_ = 1 / std::sqrt(d2);
    ok_ = true;
  }

  /// Whether A was positive definite (the factor exists).
  bool ok() const { return ok_; }

  /// A^-1 b, by L y = b then L^T x = y (L's diagonal stored as reciprocals).
  [[gnu::always_inline]] Eigen::Vector3d solve(const Eigen::Vector3d& b) const {
    const double y0 = b(0) * r0_;
    const double y1 = (b(1) - l10_ * y0) * r1_;
    const double y2 = (b(2) - l20_ * y0 - l21_ * y1) * r2_;
    const double x2 = y2 * r2_;
    const double x1 = (y1 - l21_ * x2) * r1_;
    const double x0 = (y0 - l10_ * x1 - l20_ * x2) * r0_;
    return {x0, x1, x2};
  }

 private:
  double r0_ = 0, r1_ = 0, r2_ = 0;  ///< 1 / L(i, i)
  double l10_ = 0, l20_ = 0, l21_ = 0;
  bool ok_ = false;
};

}  // namespace tb
