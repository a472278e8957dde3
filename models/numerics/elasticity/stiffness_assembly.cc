#include "stiffness_assembly.h"

#include <deal.II/base/multithread_info.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>

#include <algorithm>
#include <stdexcept>
#include <string>
#include <vector>

#include "linear_elastic.h"

namespace tb {
namespace {

/// The pattern of K, 3x3 blocks per pair of nodes that share a tet, stored column
/// by column as Eigen's compressed column-major format wants it, so that element
/// matrices are added in place (2.5M triplets sorted by setFromTriplets took a
/// quarter of the setup on the paper's cube).
class BlockPattern {
 public:
  explicit BlockPattern(const TetMesh& mesh) : neighbours_(static_cast<size_t>(mesh.V.rows())) {
    for (Eigen::Index t = 0; t < mesh.T.rows(); ++t)
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b < 4; ++b) neighbours_[static_cast<size_t>(mesh.T(t, b))].push_back(mesh.T(t, a));
    first_.resize(neighbours_.size() + 1, 0);
    for (size_t v = 0; v < neighbours_.size(); ++v) {
      auto& n = neighbours_[v];
      std::sort(n.begin(), n.end());
      n.erase(std::unique(n.begin(), n.end()), n.end());
      first_[v + 1] = first_[v] + static_cast<int>(n.size());
    }
    const size_t dofs = 3 * neighbours_.size();
    outer_.resize(dofs + 1);
    inner_.resize(9 * static_cast<size_t>(first_.back()));
    for (size_t v = 0; v < neighbours_.size(); ++v) {
      const auto& n = neighbours_[v];
      for (int c = 0; c < 3; ++c) {
        const size_t col_start = 9 * static_cast<size_t>(first_[v]) + 3 * n.size() * static_cast<size_t>(c);
        outer_[3 * v + static_cast<size_t>(c)] = static_cast<int>(col_start);
        for (size_t k = 0; k < n.size(); ++k)
          for (int r = 0; r < 3; ++r) inner_[col_start + 3 * k + static_cast<size_t>(r)] = 3 * n[k] + r;
      }
    }
    outer_[dofs] = static_cast<int>(inner_.size());
    values_.assign(inner_.size(), 0.0);
  }

  /// Adds k to K(3 row_node + row_component, 3 col_node + col_component).
  void add(int row_node, int row_component, int col_node, int col_component, double k) {
    const auto& n = neighbours_[static_cast<size_t>(col_node)];
    const auto pos = static_cast<size_t>(std::lower_bound(n.begin(), n.end(), row_node) - n.begin());
    values_[static_cast<size_t>(outer_[3 * static_cast<size_t>(col_node) + static_cast<size_t>(col_component)]) +
            3 * pos + static_cast<size_t>(row_component)] += k;
  }

  Eigen::SparseMatrix<double> matrix() const {
    const auto dofs = static_cast<Eigen::Index>(3 * neighbours_.size());
    return Eigen::Map<const Eigen::SparseMatrix<double>>(dofs, dofs, static_cast<Eigen::Index>(values_.size()),
                                                         outer_.data(), inner_.data(), values_.data());
  }

 private:
  std::vector<std::vector<int>> neighbours_;  ///< sorted nodes sharing a tet with each node (itself included)
  std::vector<int> first_;                    ///< prefix sums of the neighbour counts
  std::vector<int> outer_, inner_;
  std::vector<double> values_;
};

}  // namespace

void limit_assembly_threads(unsigned threads) { dealii::MultithreadInfo::set_thread_limit(threads); }

P1Elements p1_elements(const TetMesh& mesh) {
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
  const MappingFE<3> mapping(p1);
  const QGaussSimplex<3> quadrature(1);  // B is constant on a P1 tet: one point is exact
  FEValues<3> fe_values(mapping, p1, quadrature, update_gradients | update_JxW_values);

  P1Elements e;
  e.gradients.resize(mesh.T.rows(), 12);
  e.volumes.resize(mesh.T.rows());
  for (const auto& cell : tria.active_cell_iterators()) {
    fe_values.reinit(cell);
    const auto t = static_cast<Eigen::Index>(cell->index());  // level-0 cells keep their creation order
    e.volumes(t) = fe_values.JxW(0);
    // FE_SimplexP(1) numbers its shape functions by the cell's vertices; place
    // each at its node's position k in the row T(t, :).
    for (unsigned i = 0; i < 4; ++i) {
      const int node = static_cast<int>(cell->vertex_index(i));
      int k = 0;
      while (k < 4 && mesh.T(t, k) != node) ++k;
      if (k == 4)
        throw std::logic_error("p1_elements: deal.II cell " + std::to_string(t) + " is not tet " + std::to_string(t) +
                               " of the mesh");
      const Tensor<1, 3> g = fe_values.shape_grad(i, 0);
      for (int c = 0; c < 3; ++c) e.gradients(t, 3 * k + c) = g[static_cast<unsigned>(c)];
    }
  }
  return e;
}

Eigen::SparseMatrix<double> assemble_stiffness(const TetMesh& mesh, double E, double nu) {
  const P1Elements e = p1_elements(mesh);
  const LinearElastic law(lame_parameters(E, nu));
  BlockPattern K(mesh);
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) {
        const double* ga = &e.gradients(t, 3 * a);
        const double* gb = &e.gradients(t, 3 * b);
        for (int ci = 0; ci < 3; ++ci)
          for (int cj = 0; cj < 3; ++cj)  // (B^T D B)_ab, the linear law's, times the volume
            K.add(mesh.T(t, a), ci, mesh.T(t, b), cj, law.stiffness_entry(ga, gb, ci, cj) * e.volumes(t));
      }
  return K.matrix();
}

}  // namespace tb
