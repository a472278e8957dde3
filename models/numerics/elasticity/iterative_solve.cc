// The iterative elastic solve: conjugate gradients warm-started from the previous
// frame, preconditioned by incomplete Cholesky or the two-level preconditioner
// (preconditioned_cg.h) whose coarse space is the scenario's coarse tet mesh.
#include <stdexcept>

#include "elastic_solve.h"
#include "point_location.h"
#include "preconditioned_cg.h"

namespace tb {
namespace {

/// P: free dofs by coarse dofs, u_fine = P u_coarse by the P1 (barycentric)
/// interpolation of the coarse tet containing each fine node (the nearest tet,
/// extrapolated, for a node outside the coarse mesh). Coarse dofs that reach no
/// free dof are left out, so that P^T K P is nonsingular.
Eigen::SparseMatrix<double> coarse_prolongation(const ElasticBody& body, const TetMesh& coarse) {
  const TetMesh& fine = body.mesh();
  std::vector<Eigen::Triplet<double>> t;
  for (Eigen::Index v = 0; v < fine.V.rows(); ++v) {
    const TetEmbedding e = locate_point(coarse, fine.V.row(v).transpose());
    for (int c = 0; c < 3; ++c) {
      const int row = body.free_index(static_cast<int>(3 * v + c));
      if (row < 0) continue;
      for (int k = 0; k < 4; ++k)
        if (e.weights(k) != 0) t.emplace_back(row, 3 * coarse.T(e.tet, k) + c, e.weights(k));
    }
  }
  Eigen::SparseMatrix<double> P(body.free_dofs(), 3 * coarse.V.rows());
  P.setFromTriplets(t.begin(), t.end());
  std::vector<int> used_columns;
  for (Eigen::Index c = 0; c < P.cols(); ++c)
    if (P.col(c).nonZeros() > 0) used_columns.push_back(static_cast<int>(c));
  Eigen::SparseMatrix<double> Pu(P.rows(), static_cast<Eigen::Index>(used_columns.size()));
  for (size_t j = 0; j < used_columns.size(); ++j) Pu.col(static_cast<Eigen::Index>(j)) = P.col(used_columns[j]);
  Pu.makeCompressed();
  return Pu;
}

class IterativeSolve : public ElasticSolve {
 public:
  /// preconditioner "ic" or "two_level" (then coarse_space is its coarse mesh).
  IterativeSolve(const ElasticBody& body, const std::string& preconditioner, double tolerance,
                 const TetMesh* coarse_space)
      : body_(body), preconditioner_(preconditioner), tolerance_(tolerance) {
    const int n = body.free_dofs();
    if (preconditioner == "two_level") {
      const Eigen::SparseMatrix<double> P = coarse_prolongation(body, *coarse_space);
      cg_ = std::make_unique<PreconditionedCG>(body.free_stiffness(), tolerance, 10 * n, &P);
    } else {
      cg_ = std::make_unique<PreconditionedCG>(body.free_stiffness(), tolerance, 10 * n);
    }
    x_.setZero(n);
  }

  void solve(const Eigen::VectorXd& f_free, const std::vector<int>*, Eigen::VectorXd& u) override {
    if (u.size() != body_.dofs()) u = Eigen::VectorXd::Zero(body_.dofs());
    body_.to_free(u, x_);
    last_iterations_ = cg_->solve(f_free, x_);
    body_.to_full(x_, u);
  }

  int last_iterations() const override { return last_iterations_; }
  nlohmann::json report() const override {
    return {{"solve", "iterative"}, {"preconditioner", preconditioner_}, {"cg_tolerance", tolerance_}};
  }

 private:
  const ElasticBody& body_;
  std::string preconditioner_;
  double tolerance_;
  std::unique_ptr<PreconditionedCG> cg_;
  Eigen::VectorXd x_;
  int last_iterations_ = 0;
};

}  // namespace

ElasticSolveInfo iterative_solve_info() {
  return {"iterative", "preconditioned CG from the previous frame's solution",
          [](const std::string& prefix) {
            std::vector<ParameterSpec> specs = {ParameterSpec::choice(
                prefix + "preconditioner", {"two_level", "ic"}, "ic",
                "of the iterative solver. two_level: incomplete Cholesky plus a coarse correction on the "
                "scenario's coarse (hybrid) tet mesh; ic: incomplete Cholesky alone")};
            for (ParameterSpec& s : cg_tolerance_parameter(prefix)) specs.push_back(std::move(s));
            return specs;
          },
          [](const ElasticBody& b, const Parameters& p, const std::string& prefix, const ElasticSolveContext& c) {
            const std::string& preconditioner = p.choice(prefix + "preconditioner");
            if (preconditioner == "two_level" && !c.coarse_space)
              throw std::invalid_argument(prefix + "preconditioner two_level needs the scenario's coarse volume mesh; use " +
                                          prefix + "preconditioner ic");
            return std::unique_ptr<ElasticSolve>(
                new IterativeSolve(b, preconditioner, p.number(prefix + "cg_tolerance"), c.coarse_space));
          }, takes_the_tool, takes_the_tool};
}

}  // namespace tb
