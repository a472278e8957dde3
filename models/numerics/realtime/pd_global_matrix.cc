#include "pd_global_matrix.h"

#include <Eigen/SparseCore>
#include <algorithm>
#include <cstddef>
#include <utility>

namespace tb {

PdGlobalMatrix::PdGlobalMatrix(const Tetrahedra& T, const std::vector<TetShape>& shapes,
                               const Eigen::VectorXd& node_weight, const Eigen::Matrix3Xd& free, double weight) {
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
    for (int v : nodes) entries.emplace_back(row[static_cast<size_t>(v)], row[static_cast<size_t>(v)], node_weight(v));
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
    block.slot_of.assign(static_cast<size_t>(n), -1);
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
  ++call_;
  for (Block& block : blocks_) cache_columns(block, nodes);
  // S(a, b) = n_a . (A^-1 N^T)_b at node a = sum_c n_a,c n_b,c [A_c^-1](node a, node b).
  for (int c = 0; c < 3; ++c) {
    if (block_of_[c] < 0) continue;
    const Block& block = blocks_[static_cast<size_t>(block_of_[c])];
    const size_t rows = block.nodes.size();
    for (size_t a = 0; a < m; ++a) {
      const int row = block.row_of[static_cast<size_t>(nodes[a])];
      if (row < 0 || directions[a](c) == 0) continue;
      for (size_t b = 0; b < m; ++b) {
        const int slot = block.slot_of[static_cast<size_t>(nodes[b])];
        if (slot < 0) continue;  // node b not free in this block: its column is zero
        schur(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) +=
            directions[a](c) * directions[b](c) *
            block.columns[static_cast<size_t>(slot) * rows + static_cast<size_t>(row)];
      }
    }
  }
}

void PdGlobalMatrix::cache_columns(Block& block, const std::vector<int>& nodes) {
  const size_t rows = block.nodes.size();
  block.missing.clear();
  for (int v : nodes) {
    if (block.row_of[static_cast<size_t>(v)] < 0) continue;
    const int slot = block.slot_of[static_cast<size_t>(v)];
    if (slot >= 0) {
      block.used_in[static_cast<size_t>(slot)] = call_;
    } else if (slot == -1) {
      block.slot_of[static_cast<size_t>(v)] = -2;  // queued (a node listed twice is solved once)
      block.missing.push_back(v);
    }
  }
  const size_t k = block.missing.size();
  if (k == 0) return;
  if (block.units.size() < rows * k) {
    block.units.resize(rows * k);
    block.solved.resize(rows * k);
  }
  std::fill(block.units.begin(), block.units.begin() + static_cast<std::ptrdiff_t>(rows * k), 0.0);
  for (size_t j = 0; j < k; ++j)
    block.units[j * rows + static_cast<size_t>(block.row_of[static_cast<size_t>(block.missing[j])])] = 1;
  block.cholesky->solve(block.units.data(), block.solved.data(), static_cast<int>(k), block.workspace);
  // Each new column takes a slot this call does not use (its node's column dropped),
  // or a new one: the slots grow to the largest set of nodes one call has needed.
  size_t slot = 0;
  for (size_t j = 0; j < k; ++j) {
    while (slot < block.slot_node.size() && block.used_in[slot] == call_) ++slot;
    if (slot == block.slot_node.size()) {
      block.slot_node.push_back(-1);
      block.used_in.push_back(0);
      block.columns.resize(block.slot_node.size() * rows);
    }
    if (block.slot_node[slot] >= 0) block.slot_of[static_cast<size_t>(block.slot_node[slot])] = -1;
    const int v = block.missing[j];
    std::copy_n(block.solved.begin() + static_cast<std::ptrdiff_t>(j * rows), rows,
                block.columns.begin() + static_cast<std::ptrdiff_t>(slot * rows));
    block.slot_node[slot] = v;
    block.slot_of[static_cast<size_t>(v)] = static_cast<int>(slot);
    block.used_in[slot] = call_;
  }
}

void PdGlobalMatrix::add_constraint_response(const Eigen::VectorXd& mu, Eigen::Matrix3Xd& z) {
  const size_t m = constraint_nodes_.size();
  for (int c = 0; c < 3 && m > 0; ++c) {
    if (block_of_[c] < 0) continue;
    Block& block = blocks_[static_cast<size_t>(block_of_[c])];
    const auto rows = static_cast<Eigen::Index>(block.nodes.size());
    block.x.setZero();
    for (size_t b = 0; b < m; ++b) {
      const int slot = block.slot_of[static_cast<size_t>(constraint_nodes_[b])];
      const double weight = mu(static_cast<Eigen::Index>(b)) * constraint_directions_[b](c);
      if (slot < 0 || weight == 0) continue;
      block.x += weight * Eigen::Map<const Eigen::VectorXd>(block.columns.data() + static_cast<Eigen::Index>(slot) * rows, rows);
    }
    for (Eigen::Index k = 0; k < rows; ++k) z(c, block.nodes[static_cast<size_t>(k)]) += block.x(k);
  }
}

double PdGlobalMatrix::factor_nonzeros() const {
  double sum = 0;
  for (const Block& b : blocks_) sum += b.cholesky->factor_nonzeros();
  return sum;
}

}  // namespace tb
