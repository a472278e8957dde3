#include "stiffness_assembly.h"

#include <deal.II/base/multithread_info.h>
#include <deal.II/base/quadrature_lib.h>
#include <deal.II/fe/fe_simplex_p.h>
#include <deal.II/fe/fe_system.h>
#include <deal.II/fe/fe_values.h>
#include <deal.II/fe/mapping_fe.h>
#include <deal.II/grid/tria.h>

#include <algorithm>
#include <tuple>
#include <vector>

#include "elasticity_cell.h"

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
  const Lame lame(E, nu);

  const unsigned n = fe.n_dofs_per_cell();  // 12
  // FE_SimplexP(1) numbers its shape functions by the cell's vertices.
  std::vector<unsigned> component(n), vertex(n);
  for (unsigned i = 0; i < n; ++i) std::tie(component[i], vertex[i]) = fe.system_to_component_index(i);
  BlockPattern K(mesh);
  std::vector<int> node(n);
  FullMatrix<double> Ke;
  std::vector<Tensor<1, 3>> grad;
  for (const auto& cell : tria.active_cell_iterators()) {
    fe_values.reinit(cell);
    for (unsigned i = 0; i < n; ++i) node[i] = static_cast<int>(cell->vertex_index(vertex[i]));
    linear_elastic_cell_matrix(fe_values, component, lame, Ke, grad);  // eq. (9), shared with the distributed FEM
    for (unsigned i = 0; i < n; ++i)
      for (unsigned j = 0; j < n; ++j)
        K.add(node[i], static_cast<int>(component[i]), node[j], static_cast<int>(component[j]), Ke(i, j));
  }
  return K.matrix();
}

}  // namespace tb
