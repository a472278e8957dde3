#include "stiffness_assembly.h"

#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>

#include <vector>

namespace tb {

Eigen::SparseMatrix<double> assemble_stiffness(const TetMesh& mesh, double E, double nu) {
  using namespace dealii;
  std::vector<Point<3>> vertices;
  vertices.reserve(static_cast<size_t>(mesh.V.rows()));
  for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) vertices.emplace_back(mesh.V(v, 0), mesh.V(v, 1), mesh.V(v, 2));
  std::vector<CellData<3>> cells(static_cast<size_t>(mesh.T.rows()), CellData<3>(4));
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t)
    for (unsigned k = 0; k < 4; ++k) cells[static_cast<size_t>(t)].vertices[k] = static_cast<unsigned>(mesh.T(t, k));
  Triangulation<3> tria;
  tria.create_triangulation(vertices, cells, SubCellData());

  const FE_SimplexP<3> p1(1);
  const FESystem<3> fe(p1, 3);
  const MappingFE<3> mapping(p1);
  const QGaussSimplex<3> quadrature(1);  // B is constant on a P1 tet: one point is exact
  FEValues<3> fe_values(mapping, fe, quadrature, update_gradients | update_JxW_values);

  // Lame parameters of the elasticity matrix D (eq. 9).
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu));
  const double mu = E / (2 * (1 + nu));

  const unsigned n = fe.n_dofs_per_cell();  // 12
  std::vector<Eigen::Triplet<double>> triplets;
  triplets.reserve(static_cast<size_t>(mesh.T.rows()) * n * n);
  std::vector<int> global(n);
  for (const auto& cell : tria.active_cell_iterators()) {
    fe_values.reinit(cell);
    for (unsigned i = 0; i < n; ++i) {
      // FE_SimplexP(1) numbers its shape functions by the cell's vertices.
      const auto [component, vertex] = fe.system_to_component_index(i);
      global[i] = 3 * static_cast<int>(cell->vertex_index(vertex)) + static_cast<int>(component);
    }
    for (unsigned q = 0; q < quadrature.size(); ++q)
      for (unsigned i = 0; i < n; ++i) {
        const unsigned ci = fe.system_to_component_index(i).first;
        const Tensor<1, 3> gi = fe_values.shape_grad(i, q);
        for (unsigned j = 0; j < n; ++j) {
          const unsigned cj = fe.system_to_component_index(j).first;
          const Tensor<1, 3> gj = fe_values.shape_grad(j, q);
          // (B^T D B)_ij for isotropic D, as in deal.II step-8.
          double k = gi[ci] * gj[cj] * lambda + gi[cj] * gj[ci] * mu;
          if (ci == cj) k += gi * gj * mu;
          triplets.emplace_back(global[i], global[j], k * fe_values.JxW(q));
        }
      }
  }
  Eigen::SparseMatrix<double> K(3 * mesh.V.rows(), 3 * mesh.V.rows());
  K.setFromTriplets(triplets.begin(), triplets.end());
  return K;
}

}  // namespace tb
