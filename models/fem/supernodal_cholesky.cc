#include "supernodal_cholesky.h"

#include <cholmod.h>

#include <Eigen/CholmodSupport>  // viewAsCholmod
#include <algorithm>
#include <stdexcept>

namespace tb {

struct SupernodalCholesky::Cholmod {
  cholmod_common common;
  cholmod_factor* L = nullptr;
  cholmod_dense* X = nullptr;  // solution, reused by every solve
  cholmod_dense* Y = nullptr;  // workspace of the supernodal solve, reused
  cholmod_dense* E = nullptr;
  Cholmod() { cholmod_start(&common); }
  ~Cholmod() {
    cholmod_free_dense(&X, &common);
    cholmod_free_dense(&Y, &common);
    cholmod_free_dense(&E, &common);
    cholmod_free_factor(&L, &common);
    cholmod_finish(&common);
  }
};

SupernodalCholesky::SupernodalCholesky(const Eigen::SparseMatrix<double>& matrix) : c_(std::make_unique<Cholmod>()) {
  cholmod_common& cm = c_->common;
  cm.supernodal = CHOLMOD_SUPERNODAL;
  // K is only read through this view (CHOLMOD takes non-const pointers).
  Eigen::SparseMatrix<double>& K = const_cast<Eigen::SparseMatrix<double>&>(matrix);
  if (!K.isCompressed()) throw std::logic_error("SupernodalCholesky: the matrix must be compressed");
  cholmod_sparse A = Eigen::viewAsCholmod(K);
  A.stype = -1;  // symmetric, lower triangle stored
  c_->L = cholmod_analyze(&A, &cm);
  if (!c_->L) throw std::runtime_error("CHOLMOD analysis failed (out of memory?)");
  if (!cholmod_factorize(&A, c_->L, &cm) || cm.status == CHOLMOD_NOT_POSDEF)
    throw std::runtime_error("stiffness matrix is not positive definite (CHOLMOD factorisation failed at column " +
                             std::to_string(c_->L->minor) + ")");
  // A first solve sizes X, Y and E; solve() reuses them.
  Eigen::VectorXd b = Eigen::VectorXd::Zero(matrix.rows()), x(matrix.rows());
  solve(b, x);
}

SupernodalCholesky::~SupernodalCholesky() = default;

void SupernodalCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  cholmod_dense B{};  // a header over b's storage, not a copy
  B.nrow = B.d = static_cast<size_t>(b.size());
  B.ncol = 1;
  B.nzmax = B.nrow;
  B.x = const_cast<double*>(b.data());
  B.xtype = CHOLMOD_REAL;
  B.dtype = CHOLMOD_DOUBLE;
  if (!cholmod_solve2(CHOLMOD_A, c_->L, &B, nullptr, &c_->X, nullptr, &c_->Y, &c_->E, &c_->common))
    throw std::runtime_error("CHOLMOD solve failed");
  const auto* xs = static_cast<const double*>(c_->X->x);
  std::copy(xs, xs + b.size(), x.data());
}

double SupernodalCholesky::factor_nonzeros() const { return c_->common.lnz; }

const char* SupernodalCholesky::ordering() const {
  switch (c_->L->ordering) {
    case CHOLMOD_NATURAL: return "natural";
    case CHOLMOD_GIVEN: return "given";
    case CHOLMOD_AMD: return "AMD";
    case CHOLMOD_METIS: return "METIS";
    case CHOLMOD_NESDIS: return "NESDIS";
    case CHOLMOD_COLAMD: return "COLAMD";
    case CHOLMOD_POSTORDERED: return "postordered";
    default: return "unknown";
  }
}

}  // namespace tb
