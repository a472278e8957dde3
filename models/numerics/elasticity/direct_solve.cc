// The direct elastic solve: CHOLMOD factorisation made once (setup), per frame our
// own back-substitution whose forward part visits only the elimination-tree paths
// of the loaded rows (supernodal_cholesky.h). No parameters of its own.
#include <stdexcept>

#include "elastic_solve.h"
#include "supernodal_cholesky.h"

namespace tb {
namespace {

class DirectSolve : public ElasticSolve {
 public:
  explicit DirectSolve(const ElasticBody& body) : body_(body), cholesky_(body.free_stiffness()), x_(body.free_dofs()) {}
  bool factorised() const override { return true; }

  void solve(const Eigen::VectorXd& f_free, const std::vector<int>* nonzero_rows, Eigen::VectorXd& u) override {
    if (!nonzero_rows) {
      cholesky_.solve(f_free, x_);
    } else {
      if (!has_rhs_ || rhs_.rows != *nonzero_rows) {  // a new pattern: its forward-solve path
        rhs_ = cholesky_.sparse_rhs(*nonzero_rows);
        has_rhs_ = true;
      }
      cholesky_.solve(f_free, rhs_, x_);
    }
    body_.to_full(x_, u);
  }

  void solve_columns(const Eigen::MatrixXd& f_free, Eigen::MatrixXd& u_free) override { cholesky_.solve(f_free, u_free); }

  nlohmann::json report() const override {
    return {{"solve", "direct"}, {"factor_nonzeros", cholesky_.factor_nonzeros()}, {"ordering", cholesky_.ordering()}};
  }

 private:
  const ElasticBody& body_;
  SupernodalCholesky cholesky_;
  SupernodalCholesky::SparseRhs rhs_;
  bool has_rhs_ = false;
  Eigen::VectorXd x_;
};

}  // namespace

ElasticSolveInfo direct_solve_info() {
  return {"direct", "CHOLMOD factorisation in setup, back-substitution per frame",
          [](const std::string&) { return std::vector<ParameterSpec>{}; },
          [](const ElasticBody& b, const Parameters&, const std::string&, const ElasticSolveContext&) {
            return std::unique_ptr<ElasticSolve>(new DirectSolve(b));
          }, takes_the_tool, takes_the_tool};
}

std::unique_ptr<ElasticSolve> make_direct_solve(const ElasticBody& body) { return std::make_unique<DirectSolve>(body); }

}  // namespace tb
