#include "pd_global_matrix.h"

#include <Eigen/SparseCore>
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

double PdGlobalMatrix::factor_nonzeros() const {
  double sum = 0;
  for (const Block& b : blocks_) sum += b.cholesky->factor_nonzeros();
  return sum;
}

}  // namespace tb
