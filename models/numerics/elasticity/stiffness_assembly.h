// Global stiffness matrix K of linear elasticity on P1 tetrahedra (paper eqs. 1-11):
// deal.II's P1 shape gradients, the element matrices of the linear law
// (numerics/materials/linear_elastic.h). One of the few translation units that
// include deal.II (docs/architecture.md), so the rest sees plain Eigen.
#pragma once

#include <Eigen/SparseCore>

#include "mesh_types.h"

namespace tb {

/// What the element matrices of P1 tets are made of: the gradient of each node's
/// (scalar) shape function, constant on the tet, and the tet's volume, from deal.II's
/// FE_SimplexP<3>(1), MappingFE and QGaussSimplex(1) (exact: B is constant).
/// With them the isotropic element matrix of eq. (9) is, per pair of nodes a, b,
///   K^e_ab = V (lambda g_a g_b^T + mu g_b g_a^T + mu (g_a . g_b) I)   (3 by 3)
struct P1Elements {
  /// #T by 12: columns 3k..3k+2 of row t are the gradient g_k of the shape
  /// function of node T(t, k) (1/m)
  Eigen::Matrix<double, Eigen::Dynamic, 12, Eigen::RowMajor> gradients;
  Eigen::VectorXd volumes;  ///< #T, m^3
};
///   mesh  positively oriented tets
P1Elements p1_elements(const TetMesh& mesh);

/// K (eq. 11), assembled from the element matrices K^e = int B^T D B dx (eq. 9)
/// of p1_elements(mesh).
///   mesh  positively oriented tets
///   returns 3 #V by 3 #V symmetric matrix; dof 3 * node + component
Eigen::SparseMatrix<double> assemble_stiffness(const TetMesh& mesh, double youngs_modulus, double poisson_ratio);

/// Caps the threads deal.II may use (its MultithreadInfo thread limit).
void limit_assembly_threads(unsigned threads);

}  // namespace tb
