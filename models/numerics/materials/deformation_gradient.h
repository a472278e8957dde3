// What every material law of this folder computes from the deformation gradient
// F: the flattened (9-vector) form of 3x3 tensors, the index convention of the
// 9x9 tangents, and the first and second derivatives of J = det F.
//
// Index convention, used by every tangent here: a 3x3 tensor A is flattened
// column by column, as Eigen stores a Matrix3d, so A_ij sits at i + 3 j; the
// tangent dP/dF is the 9x9 matrix whose entry (i + 3 j, k + 3 l) is dP_ij/dF_kl.
// For a hyperelastic law it is the Hessian of W in flattened F, hence symmetric
// (major symmetry dP_ij/dF_kl = dP_kl/dF_ij).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross
#include <Eigen/LU>        // determinant

namespace tb {

/// A flattened 3x3 tensor: entry (i, j) at i + 3 j.
using Vector9d = Eigen::Matrix<double, 9, 1>;
/// A tangent dP/dF: dP_ij/dF_kl at row i + 3 j, column k + 3 l.
using Matrix9d = Eigen::Matrix<double, 9, 9>;

/// vec(A) (3x3 -> 9), A_ij at i + 3 j.
inline Vector9d flatten(const Eigen::Matrix3d& A) { return Eigen::Map<const Vector9d>(A.data()); }

/// The inverse of flatten (9 -> 3x3).
inline Eigen::Matrix3d unflatten(const Vector9d& a) { return Eigen::Map<const Eigen::Matrix3d>(a.data()); }

/// The cofactor matrix cof F = dJ/dF (3x3), which is J F^-T when F is invertible
/// and is defined (polynomial) for every F: with f0, f1, f2 the columns of F, its
/// columns are f1 x f2, f2 x f0, f0 x f1. Written out and always inlined: Eigen's
/// cross() of two columns, and this function, were out-of-line calls in the VBD
/// sweep, the result passed through memory (docs/realtime_nonlinear.md).
[[gnu::always_inline]] inline Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F) {
  Eigen::Matrix3d C;
  for (int j = 0; j < 3; ++j) {
    const int a = (j + 1) % 3, b = (j + 2) % 3;  // column j is f_a x f_b
    C(0, j) = F(1, a) * F(2, b) - F(2, a) * F(1, b);
    C(1, j) = F(2, a) * F(0, b) - F(0, a) * F(2, b);
    C(2, j) = F(0, a) * F(1, b) - F(1, a) * F(0, b);
  }
  return C;
}

/// The cross-product matrix [v]_x (3x3): [v]_x w = v x w.
inline Eigen::Matrix3d cross_product_matrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d M;
  M << 0, -v(2), v(1), v(2), 0, -v(0), -v(1), v(0), 0;
  return M;
}

/// d^2 J / dF^2 (9x9, the convention above): the derivative of vec(cof F). Block
/// (a, b), rows 3a..3a+2 and columns 3b..3b+2, is d(column a of cof F)/d(column b
/// of F): zero for a = b, and from d(f1 x f2) = df1 x f2 + f1 x df2 (and cyclically)
///   (0,1) = -[f2]x  (0,2) = [f1]x  (1,2) = -[f0]x  (1,0) = [f2]x  (2,0) = -[f1]x  (2,1) = [f0]x,
/// symmetric, the matrix Smith, de Goes and Kim (2018) write for the same Hessian.
inline Matrix9d determinant_hessian(const Eigen::Matrix3d& F) {
  Matrix9d H = Matrix9d::Zero();
  const Eigen::Matrix3d x0 = cross_product_matrix(F.col(0));
  const Eigen::Matrix3d x1 = cross_product_matrix(F.col(1));
  const Eigen::Matrix3d x2 = cross_product_matrix(F.col(2));
  H.block<3, 3>(0, 3) = -x2;
  H.block<3, 3>(0, 6) = x1;
  H.block<3, 3>(3, 6) = -x0;
  H.block<3, 3>(3, 0) = x2;
  H.block<3, 3>(6, 0) = -x1;
  H.block<3, 3>(6, 3) = x0;
  return H;
}

/// A tangent T (9x9) contracted with one node's shape gradient g (3, 1/m):
///   K_ik = sum_{j,l} g_j g_l T(i + 3 j, k + 3 l),
/// the 3x3 diagonal block of a P1 tet's stiffness per unit volume for that node, the
/// per-vertex Hessian of Vertex Block Descent (Chen et al. 2024, eq. 8). With
/// dF = dx g^T of rank one, d^2 J[dF, dF] = 0, so a law's H_J term never reaches it:
/// the laws that have a closed form (node_stiffness) use that; this is the general
/// one, and what the closed forms are tested against.
inline Eigen::Matrix3d contract_tangent(const Matrix9d& T, const Eigen::Vector3d& g) {
  Eigen::Matrix<double, 9, 3> G = Eigen::Matrix<double, 9, 3>::Zero();
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) G(i + 3 * j, i) = g(j);
  return G.transpose() * T * G;
}

/// Throws std::domain_error "<law>: <quantity> is undefined at det F = <J> <= 0 ...":
/// what the laws built on ln J or J^(-2/3) do when asked for a stress or tangent
/// of an inverted (or flat) element.
[[noreturn]] void throw_inverted(const char* law, const char* quantity, double J);

}  // namespace tb
