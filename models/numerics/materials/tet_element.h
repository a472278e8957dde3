// A linear (P1) tetrahedron under any material law of this folder: its shape
// gradients and volume, the deformation gradient, the nodal internal forces and
// the element stiffness, each written once for every law (total Lagrangian).
//
// With g_a = grad N_a (constant on the tet), V its rest volume and G the 9 by 12
// matrix that maps the nodal displacements to vec(grad u), G(i + 3 j, 3 a + i) = g_a,j:
//   F = sum_a x_a g_a^T,   f_int = V G^T vec(P(F)),   K_e = V G^T C(F) G,
// C = dP/dF the law's 9x9 tangent. Node by node, K_e's 3x3 block (a, b) is
//   V sum_{j,l} C_{ijkl} g_a,j g_b,l   (row i, column k),
// and with linear_elastic.h's C it is the B^T D B of the serial stiffness.
// Dofs are numbered 3 a + i (node a, component i), as assemble_stiffness numbers them.
#pragma once

#include <Eigen/Core>

#include "deformation_gradient.h"

namespace tb {

/// The constant shape-function gradients and the volume of a P1 tet at rest.
struct TetShape {
  Eigen::Matrix<double, 3, 4> gradients;  ///< 3 by 4: column a is grad N_a of node a, 1/m
  double volume = 0;                      ///< rest volume, m^3
};

/// Shape gradients and volume from the rest positions of nodes 0..3 (each 3, m).
/// Throws std::invalid_argument unless the positions are finite and the tet is
/// positively oriented, det[X1 - X0, X2 - X0, X3 - X0] > 0.
TetShape tet_shape(const Eigen::Vector3d& X0, const Eigen::Vector3d& X1, const Eigen::Vector3d& X2,
                   const Eigen::Vector3d& X3);

/// F = sum_a x_a g_a^T (3x3) for current positions x (3 by 4, column a: node a, m).
inline Eigen::Matrix3d tet_deformation_gradient(const TetShape& shape, const Eigen::Matrix<double, 3, 4>& x) {
  return x * shape.gradients.transpose();
}

/// G (9 by 12): G(i + 3 j, 3 a + i) = g_a,j, so vec(F - I) = G u for nodal displacements u (12).
Eigen::Matrix<double, 9, 12> tet_gradient_operator(const TetShape& shape);

/// Internal nodal forces (12, N; dof 3 a + i): d(V W(F))/dx = V G^T vec(P(F)).
/// Law: any of this folder's laws (first_piola(F)). F: 3x3.
template <class Law>
Eigen::Matrix<double, 12, 1> tet_internal_force(const TetShape& shape, const Law& law, const Eigen::Matrix3d& F) {
  return shape.volume * (tet_gradient_operator(shape).transpose() * flatten(law.first_piola(F)));
}

/// Element stiffness K_e = V G^T C(F) G (12 by 12, N/m; dof 3 a + i): the
/// derivative of tet_internal_force in the nodal positions. Law: any of this
/// folder's laws (tangent(F)). F: 3x3, the identity for the stiffness at rest.
template <class Law>
Eigen::Matrix<double, 12, 12> tet_stiffness(const TetShape& shape, const Law& law, const Eigen::Matrix3d& F) {
  const Eigen::Matrix<double, 9, 12> G = tet_gradient_operator(shape);
  return shape.volume * (G.transpose() * (law.tangent(F) * G));
}

/// The stiffness at rest (F = I) of the tet with rest positions X0..X3 (each 3, m;
/// positively oriented, see tet_shape): for linear_elastic.h's law, the serial
/// assembly's element matrix B^T D B V.
template <class Law>
Eigen::Matrix<double, 12, 12> tet_stiffness(const Eigen::Vector3d& X0, const Eigen::Vector3d& X1,
                                            const Eigen::Vector3d& X2, const Eigen::Vector3d& X3, const Law& law) {
  return tet_stiffness(tet_shape(X0, X1, X2, X3), law, Eigen::Matrix3d::Identity());
}

}  // namespace tb
