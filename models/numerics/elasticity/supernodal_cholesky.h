// Sparse Cholesky factorisation K = P^T L L^T P made once with CHOLMOD
// (supernodal, OpenBLAS), and our own back-substitution over CHOLMOD's supernodes
// (the same BLAS calls as cholmod_solve, bitwise the same result) for two reasons:
//  - a point load has at most 12 nonzeros, and the forward substitution L y = P b
//    only needs the supernodes on their paths to the root of the elimination
//    tree; on the paper's cube that skips 59% of the factor's nonzeros and
//    makes a solve about 35% faster (the full solve reads the whole 22 MB factor
//    twice: memory-bound);
//  - no heap allocation per solve: the workspace is sized in the constructor.
// CHOLMOD picks the fill-reducing ordering itself (AMD, and METIS when AMD's fill
// is high; on the cube METIS gives 2.8M nonzeros in L against AMD's 3.6M).
#pragma once

#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <memory>
#include <vector>

namespace tb {

class SupernodalCholesky {
 public:
  /// Factorises the symmetric positive definite `matrix` (only its lower triangle
  /// is read). Throws std::runtime_error if it is not positive definite.
  explicit SupernodalCholesky(const Eigen::SparseMatrix<double>& matrix);
  ~SupernodalCholesky();
  SupernodalCholesky(const SupernodalCholesky&) = delete;
  SupernodalCholesky& operator=(const SupernodalCholesky&) = delete;

  /// The supernodes a right-hand side with nonzeros only in `rows` needs in the
  /// forward substitution, in elimination order.
  struct SparseRhs {
    std::vector<int> rows;        ///< sorted, unique
    std::vector<int> supernodes;  ///< ascending
  };
  SparseRhs sparse_rhs(const std::vector<int>& rows) const;

  /// x = K^-1 b; x must have the size of b. No heap allocation.
  void solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);
  /// The same for a b that is zero outside rhs.rows (checked: std::logic_error).
  void solve(const Eigen::VectorXd& b, const SparseRhs& rhs, Eigen::VectorXd& x);
  /// X = K^-1 B for many right-hand sides at once (B's columns), X resized to B's
  /// shape: the same supernodal substitutions with dtrsm and dgemm in place of
  /// dtrsv and dgemv, so the factor is read once per call instead of once per
  /// column (a vector solve is memory-bound). Equal to column-by-column solves up
  /// to the BLAS's summation order. Allocates its workspace: a set-up call.
  void solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const;
  /// The same inside a frame: B and X column-major, #rows by k, in caller-kept
  /// storage (X must not overlap B), and the workspace grown to the largest k it has
  /// seen and then reused, so a k seen before allocates nothing.
  struct BlockWorkspace {
    std::vector<double> permuted, gathered;
  };
  void solve(const double* B, double* X, int k, BlockWorkspace& workspace) const;
  int rows() const { return static_cast<int>(w_.size()); }

  /// Nonzeros of the factor L, and CHOLMOD's name of the ordering it chose.
  double factor_nonzeros() const;
  int supernode_count() const { return static_cast<int>(parent_.size()); }
  const char* ordering() const;

 private:
  void forward_supernode(int s);
  void backward_substitution_and_unpermute(Eigen::VectorXd& x);

  struct Cholmod;
  std::unique_ptr<Cholmod> c_;
  std::vector<int> column_supernode_;  ///< supernode of each (permuted) column
  std::vector<int> parent_;            ///< supernodal elimination tree
  std::vector<double> w_, gathered_;   ///< permuted solution; a supernode's off-diagonal rows
};

}  // namespace tb
