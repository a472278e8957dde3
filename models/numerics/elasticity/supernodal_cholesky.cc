#include "supernodal_cholesky.h"

#include <cholmod.h>

#include <Eigen/CholmodSupport>  // viewAsCholmod
#include <algorithm>
#include <stdexcept>

// Reference BLAS interface of OpenBLAS (linked), as CHOLMOD's own solve calls it.
extern "C" {
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a, const int* lda,
            double* x, const int* incx);
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a, const int* lda,
            const double* x, const int* incx, const double* beta, double* y, const int* incy);
void dtrsm_(const char* side, const char* uplo, const char* transa, const char* diag, const int* m, const int* n,
            const double* alpha, const double* a, const int* lda, double* b, const int* ldb);
void dgemm_(const char* transa, const char* transb, const int* m, const int* n, const int* k, const double* alpha,
            const double* a, const int* lda, const double* b, const int* ldb, const double* beta, double* c,
            const int* ldc);
}

namespace tb {

struct SupernodalCholesky::Cholmod {
  cholmod_common common;
  cholmod_factor* L = nullptr;
  Cholmod() { cholmod_start(&common); }
  ~Cholmod() {
    cholmod_free_factor(&L, &common);
    cholmod_finish(&common);
  }
  // The supernodal factor's arrays (CHOLMOD's int version): supernode s holds
  // columns super[s] .. super[s+1]-1, as a dense column-major block of
  // pi[s+1]-pi[s] rows (row indices s[pi[s]] ..., the diagonal block first) at
  // x + px[s].
  const int* super() const { return static_cast<const int*>(L->super); }
  const int* pi() const { return static_cast<const int*>(L->pi); }
  const int* px() const { return static_cast<const int*>(L->px); }
  const int* rows() const { return static_cast<const int*>(L->s); }
  const double* values() const { return static_cast<const double*>(L->x); }
  const int* perm() const { return static_cast<const int*>(L->Perm); }
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
  if (!c_->L->is_super || !c_->L->is_ll || c_->L->xtype != CHOLMOD_REAL)
    throw std::logic_error("SupernodalCholesky: CHOLMOD did not return a real supernodal LL' factor");

  const int n = static_cast<int>(c_->L->n), ns = static_cast<int>(c_->L->nsuper);
  const int *super = c_->super(), *pi = c_->pi(), *rows = c_->rows();
  column_supernode_.resize(static_cast<size_t>(n));
  parent_.assign(static_cast<size_t>(ns), -1);
  size_t max_rows = 0;
  for (int s = 0; s < ns; ++s) {
    for (int k = super[s]; k < super[s + 1]; ++k) column_supernode_[static_cast<size_t>(k)] = s;
    max_rows = std::max(max_rows, static_cast<size_t>(pi[s + 1] - pi[s]));
  }
  for (int s = 0; s < ns; ++s) {
    const int cols = super[s + 1] - super[s];
    // The parent is the supernode of the first row below the diagonal block.
    if (pi[s + 1] - pi[s] > cols)
      parent_[static_cast<size_t>(s)] = column_supernode_[static_cast<size_t>(rows[pi[s] + cols])];
  }
  w_.resize(static_cast<size_t>(n));
  gathered_.resize(max_rows);
}

SupernodalCholesky::~SupernodalCholesky() = default;

SupernodalCholesky::SparseRhs SupernodalCholesky::sparse_rhs(const std::vector<int>& rows) const {
  SparseRhs rhs{rows, {}};
  std::sort(rhs.rows.begin(), rhs.rows.end());
  rhs.rows.erase(std::unique(rhs.rows.begin(), rhs.rows.end()), rhs.rows.end());
  const int n = static_cast<int>(c_->L->n);
  std::vector<int> position(static_cast<size_t>(n));  // permuted position of each original row
  for (int i = 0; i < n; ++i) position[static_cast<size_t>(c_->perm()[i])] = i;
  std::vector<char> needed(parent_.size(), 0);
  for (int r : rows) {
    if (r < 0 || r >= n) throw std::invalid_argument("sparse_rhs: row out of range");
    for (int s = column_supernode_[static_cast<size_t>(position[static_cast<size_t>(r)])];
         s >= 0 && !needed[static_cast<size_t>(s)]; s = parent_[static_cast<size_t>(s)])
      needed[static_cast<size_t>(s)] = 1;
  }
  for (size_t s = 0; s < needed.size(); ++s)
    if (needed[s]) rhs.supernodes.push_back(static_cast<int>(s));
  return rhs;
}

void SupernodalCholesky::forward_supernode(int s) {
  // w1 = L11^-1 w1, then w2 -= L21 w1 scattered to the supernode's rows below.
  const int *super = c_->super(), *pi = c_->pi();
  const int first = super[s], cols = super[s + 1] - first, nrows = pi[s + 1] - pi[s], below = nrows - cols;
  const double* block = c_->values() + c_->px()[s];
  const int one = 1;
  const double alpha = 1, beta = 0;
  dtrsv_("L", "N", "N", &cols, block, &nrows, w_.data() + first, &one);
  if (below == 0) return;
  dgemv_("N", &below, &cols, &alpha, block + cols, &nrows, w_.data() + first, &one, &beta, gathered_.data(), &one);
  const int* below_rows = c_->rows() + pi[s] + cols;
  for (int i = 0; i < below; ++i) w_[static_cast<size_t>(below_rows[i])] -= gathered_[static_cast<size_t>(i)];
}

void SupernodalCholesky::backward_substitution_and_unpermute(Eigen::VectorXd& x) {
  // L^T x = w, supernodes in reverse: w1 -= L21^T w2 (gathered), w1 = L11^-T w1.
  const int *super = c_->super(), *pi = c_->pi();
  const int one = 1;
  const double minus_one = -1, plus_one = 1;
  for (int s = static_cast<int>(parent_.size()) - 1; s >= 0; --s) {
    const int first = super[s], cols = super[s + 1] - first, nrows = pi[s + 1] - pi[s], below = nrows - cols;
    const double* block = c_->values() + c_->px()[s];
    if (below > 0) {
      const int* below_rows = c_->rows() + pi[s] + cols;
      for (int i = 0; i < below; ++i) gathered_[static_cast<size_t>(i)] = w_[static_cast<size_t>(below_rows[i])];
      dgemv_("T", &below, &cols, &minus_one, block + cols, &nrows, gathered_.data(), &one, &plus_one, w_.data() + first,
             &one);
    }
    dtrsv_("L", "T", "N", &cols, block, &nrows, w_.data() + first, &one);
  }
  const int* perm = c_->perm();
  for (size_t i = 0; i < w_.size(); ++i) x(perm[i]) = w_[i];  // x = P^T w
}

void SupernodalCholesky::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  const int* perm = c_->perm();
  for (size_t i = 0; i < w_.size(); ++i) w_[i] = b(perm[i]);  // w = P b
  for (int s = 0; s < static_cast<int>(parent_.size()); ++s) forward_supernode(s);
  backward_substitution_and_unpermute(x);
}

void SupernodalCholesky::solve(const Eigen::VectorXd& b, const SparseRhs& rhs, Eigen::VectorXd& x) {
  // Zero outside rhs.rows (sorted), or the skipped supernodes would be wrong.
  size_t next = 0;
  for (Eigen::Index i = 0; i < b.size(); ++i) {
    if (next < rhs.rows.size() && rhs.rows[next] == i) {
      ++next;
      continue;
    }
    if (b(i) != 0) throw std::logic_error("SupernodalCholesky::solve: b has nonzeros outside its sparse pattern");
  }
  const int* perm = c_->perm();
  for (size_t i = 0; i < w_.size(); ++i) w_[i] = b(perm[i]);
  for (int s : rhs.supernodes) forward_supernode(s);  // the other supernodes see zeros only
  backward_substitution_and_unpermute(x);
}

void SupernodalCholesky::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd& X) const {
  if (B.rows() != rows()) throw std::invalid_argument("SupernodalCholesky::solve: right-hand sides of the wrong length");
  X.resize(B.rows(), B.cols());
  BlockWorkspace workspace;
  solve(B.data(), X.data(), static_cast<int>(B.cols()), workspace);
}

void SupernodalCholesky::solve(const double* B, double* X, int k, BlockWorkspace& workspace) const {
  const int n = static_cast<int>(c_->L->n);
  if (k <= 0) return;
  const size_t nk = static_cast<size_t>(n) * static_cast<size_t>(k), gk = gathered_.size() * static_cast<size_t>(k);
  // Grown, never shrunk: std::vector keeps its capacity, so a k seen before allocates nothing.
  if (workspace.permuted.size() < nk) workspace.permuted.resize(nk);
  if (workspace.gathered.size() < gk) workspace.gathered.resize(gk);
  Eigen::Map<Eigen::MatrixXd> W(workspace.permuted.data(), n, k);  // P B, then the solution in the permuted order
  Eigen::Map<Eigen::MatrixXd> G(workspace.gathered.data(), static_cast<Eigen::Index>(gathered_.size()), k);
  const int *super = c_->super(), *pi = c_->pi(), *perm = c_->perm();
  for (int j = 0; j < k; ++j)  // column by column: the matrices are column-major
    for (int i = 0; i < n; ++i) W(i, j) = B[static_cast<size_t>(j) * n + static_cast<size_t>(perm[i])];
  const int ldw = n, ldg = static_cast<int>(G.rows());
  const double one = 1, zero = 0, minus_one = -1;
  const int ns = static_cast<int>(parent_.size());
  for (int s = 0; s < ns; ++s) {  // L W = P B: W1 = L11^-1 W1, W2 -= L21 W1
    const int first = super[s], cols = super[s + 1] - first, nrows = pi[s + 1] - pi[s], below = nrows - cols;
    const double* block = c_->values() + c_->px()[s];
    dtrsm_("L", "L", "N", "N", &cols, &k, &one, block, &nrows, W.data() + first, &ldw);
    if (below == 0) continue;
    dgemm_("N", "N", &below, &k, &cols, &one, block + cols, &nrows, W.data() + first, &ldw, &zero, G.data(), &ldg);
    const int* below_rows = c_->rows() + pi[s] + cols;
    for (int j = 0; j < k; ++j)
      for (int i = 0; i < below; ++i) W(below_rows[i], j) -= G(i, j);
  }
  for (int s = ns - 1; s >= 0; --s) {  // L^T W = W: W1 -= L21^T W2, W1 = L11^-T W1
    const int first = super[s], cols = super[s + 1] - first, nrows = pi[s + 1] - pi[s], below = nrows - cols;
    const double* block = c_->values() + c_->px()[s];
    if (below > 0) {
      const int* below_rows = c_->rows() + pi[s] + cols;
      for (int j = 0; j < k; ++j)
        for (int i = 0; i < below; ++i) G(i, j) = W(below_rows[i], j);
      dgemm_("T", "N", &cols, &k, &below, &minus_one, block + cols, &nrows, G.data(), &ldg, &one, W.data() + first,
             &ldw);
    }
    dtrsm_("L", "L", "T", "N", &cols, &k, &one, block, &nrows, W.data() + first, &ldw);
  }
  for (int j = 0; j < k; ++j)  // X = P^T W
    for (int i = 0; i < n; ++i) X[static_cast<size_t>(j) * n + static_cast<size_t>(perm[i])] = W(i, j);
}

double SupernodalCholesky::factor_nonzeros() const { return c_->common.lnz; }

const char* SupernodalCholesky::ordering() const {
  switch (c_->L->ordering) {
    case CHOLMOD_NATURAL:
      return "natural";
    case CHOLMOD_GIVEN:
      return "given";
    case CHOLMOD_AMD:
      return "AMD";
    case CHOLMOD_METIS:
      return "METIS";
    case CHOLMOD_NESDIS:
      return "NESDIS";
    case CHOLMOD_COLAMD:
      return "COLAMD";
    case CHOLMOD_POSTORDERED:
      return "postordered";
    default:
      return "unknown";
  }
}

}  // namespace tb
