// Global stiffness matrix K of linear elasticity on P1 tetrahedra (paper eqs. 1-11),
// integrated with deal.II. The only file that includes deal.II, so the rest of the
// project compiles quickly and sees plain Eigen.
#pragma once

#include <Eigen/SparseCore>

#include "mesh_types.h"

namespace tb {

/// K (eq. 11), assembled from element matrices K^e = int B^T D B dx (eq. 9) with
/// deal.II's FE_SimplexP<3>(1)^3, MappingFE and QGaussSimplex.
///   mesh  positively oriented tets
///   returns 3 #V by 3 #V symmetric matrix; dof 3 * node + component
Eigen::SparseMatrix<double> assemble_stiffness(const TetMesh& mesh, double youngs_modulus, double poisson_ratio);

/// Caps the threads deal.II may use (its MultithreadInfo thread limit).
void limit_assembly_threads(unsigned threads);

}  // namespace tb
