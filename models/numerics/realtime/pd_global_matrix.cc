#include "pd_global_matrix.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cstddef>
#include <utility>

namespace tb {

PdGlobalMatrix::PdGlobalMatrix(const Tetrahedra& T, const std::vector<TetShape>& shapes, const Eigen::VectorXd& mass,
                               const Eigen::Matrix3Xd& free, double h, double weight) {
  const Eigen::Index n = free.cols();
  for (int c = 0; c < 3; ++c) {
    std::vector<int> nodes;
    for (Eigen::Index v = 0; v < n; ++v)
      if (free(c, v) != 0) nodes.push_back(static_cast<int>(v));
    if (nodes.empty()) continue;
    for (size_t b = 0; b < blocks_.size(); ++b)
      if (blocks_[b].nodes == nodes) block_of_[c] = static_cast<int>(b);
    if (block_of_[c] >= 0) continue;
    std::vector<int> row(static_cast<size_t>(n), -1);
    for (size_t k = 0; k < nodes.size(); ++k) row[static_cast<size_t>(nodes[k])] = static_cast<int>(k);
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(nodes.size() + 10 * static_cast<size_t>(T.rows()));
    for (int v : nodes) entries.emplace_back(row[static_cast<size_t>(v)], row[static_cast<size_t>(v)], mass(v) / (h * h));
    for (Eigen::Index t = 0; t < T.rows(); ++t) {
      const TetShape& s = shapes[static_cast<size_t>(t)];
      for (int a = 0; a < 4; ++a)
        for (int b = 0; b <= a; ++b) {  // the lower triangle: CHOLMOD reads no other
          int i = row[static_cast<size_t>(T(t, a))], j = row[static_cast<size_t>(T(t, b))];
          if (i < 0 || j < 0) continue;
          if (i < j) std::swap(i, j);
          entries.emplace_back(i, j, weight * s.volume * s.gradients.col(a).dot(s.gradients.col(b)));
        }
    }
    Eigen::SparseMatrix<double> A(static_cast<Eigen::Index>(nodes.size()), static_cast<Eigen::Index>(nodes.size()));
    A.setFromTriplets(entries.begin(), entries.end());
    A.makeCompressed();
    Block block;
    block.nodes = std::move(nodes);
    block.row_of = std::move(row);
    block.cholesky = std::make_unique<SupernodalCholesky>(A);
    block.b = Eigen::VectorXd::Zero(A.rows());
    block.x = Eigen::VectorXd::Zero(A.rows());
    block_of_[c] = static_cast<int>(blocks_.size());
    blocks_.push_back(std::move(block));
  }
}

PdGlobalMatrix::~PdGlobalMatrix() = default;

void PdGlobalMatrix::solve(const Eigen::Matrix3Xd& q, Eigen::Matrix3Xd& z) {
  z.setZero();
  for (int c = 0; c < 3; ++c) {
    if (block_of_[c] < 0) continue;
    Block& block = blocks_[static_cast<size_t>(block_of_[c])];
    for (size_t k = 0; k < block.nodes.size(); ++k) block.b(static_cast<Eigen::Index>(k)) = q(c, block.nodes[k]);
    block.cholesky->solve(block.b, block.x);
    for (size_t k = 0; k < block.nodes.size(); ++k) z(c, block.nodes[k]) = block.x(static_cast<Eigen::Index>(k));
  }
}

void PdGlobalMatrix::node_constraints(const std::vector<int>& nodes, const std::vector<Eigen::Vector3d>& directions,
                                      Eigen::MatrixXd& schur) {
  const size_t m = nodes.size();
  constraint_nodes_.assign(nodes.begin(), nodes.end());
  constraint_directions_.assign(directions.begin(), directions.end());
  const auto M = static_cast<Eigen::Index>(m);
  schur.resize(M, M);
  schur.setZero();
  if (m == 0) return;
  for (Block& block : blocks_) {
    const size_t rows = block.nodes.size();
    if (block.units.size() < rows * m) {
      block.units.resize(rows * m);
      block.responses.resize(rows * m);
    }
    std::fill(block.units.begin(), block.units.begin() + static_cast<std::ptrdiff_t>(rows * m), 0.0);
    for (size_t a = 0; a < m; ++a) {
      const int row = block.row_of[static_cast<size_t>(nodes[a])];
      if (row >= 0) block.units[a * rows + static_cast<size_t>(row)] = 1;
    }
    block.cholesky->solve(block.units.data(), block.responses.data(), static_cast<int>(m), block.workspace);
  }
  // S(a, b) = n_a . (A^-1 N^T)_b at node a = sum_c n_a,c n_b,c [A_c^-1](node a, node b).
  for (int c = 0; c < 3; ++c) {
    if (block_of_[c] < 0) continue;
    const Block& block = blocks_[static_cast<size_t>(block_of_[c])];
    const size_t rows = block.nodes.size();
    for (size_t a = 0; a < m; ++a) {
      const int row = block.row_of[static_cast<size_t>(nodes[a])];
      if (row < 0 || directions[a](c) == 0) continue;
      for (size_t b = 0; b < m; ++b)
        schur(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) +=
            directions[a](c) * directions[b](c) * block.responses[b * rows + static_cast<size_t>(row)];
    }
  }
}

void PdGlobalMatrix::add_constraint_response(const Eigen::VectorXd& mu, Eigen::Matrix3Xd& z) {
  const auto m = static_cast<Eigen::Index>(constraint_nodes_.size());
  if (m == 0) return;
  if (weights_.size() < m) weights_.resize(m);  // grown, never shrunk
  for (int c = 0; c < 3; ++c) {
    if (block_of_[c] < 0) continue;
    Block& block = blocks_[static_cast<size_t>(block_of_[c])];
    const auto rows = static_cast<Eigen::Index>(block.nodes.size());
    for (Eigen::Index a = 0; a < m; ++a) weights_(a) = mu(a) * constraint_directions_[static_cast<size_t>(a)](c);
    block.x.noalias() = Eigen::Map<const Eigen::MatrixXd>(block.responses.data(), rows, m) * weights_.head(m);
    for (Eigen::Index k = 0; k < rows; ++k) z(c, block.nodes[static_cast<size_t>(k)]) += block.x(k);
  }
}

double PdGlobalMatrix::factor_nonzeros() const {
  double sum = 0;
  for (const Block& b : blocks_) sum += b.cholesky->factor_nonzeros();
  return sum;
}

}  // namespace tb
