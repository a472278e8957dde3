// The elastic solve strategies. Each is a small class over an ElasticBody:
//  - direct: CHOLMOD factorisation made once (setup), per frame our own
//    back-substitution whose forward part visits only the load's elimination-tree
//    paths (supernodal_cholesky.h);
//  - iterative: conjugate gradients warm-started from the previous frame,
//    preconditioned by incomplete Cholesky or the two-level preconditioner
//    (preconditioned_cg.h).
#include "elastic_solve.h"

#include <stdexcept>

#include "point_location.h"
#include "preconditioned_cg.h"
#include "supernodal_cholesky.h"

namespace tb {
namespace {

class DirectSolve : public ElasticSolve {
 public:
  explicit DirectSolve(const ElasticBody& body)
      : body_(body), cholesky_(body.free_stiffness()), f_(body.free_dofs()), x_(body.free_dofs()) {}

  void solve(const LoadStencil& load, const Eigen::Vector3d& force, Eigen::VectorXd& u) override {
    if (!has_rhs_ || rhs_nodes_ != load.nodes) {  // a new load tet: its forward-solve path
      rhs_ = cholesky_.sparse_rhs(body_.loaded_free_dofs(load));
      rhs_nodes_ = load.nodes;
      has_rhs_ = true;
    }
    body_.load_vector(load, force, f_);
    cholesky_.solve(f_, rhs_, x_);
    body_.to_full(x_, u);
  }

  nlohmann::json report() const override {
    return {{"solve", "direct"}, {"factor_nonzeros", cholesky_.factor_nonzeros()}, {"ordering", cholesky_.ordering()}};
  }

  /// The factorisation, for strategies and models built on it (precomputed responses).
  SupernodalCholesky& cholesky() { return cholesky_; }

 private:
  const ElasticBody& body_;
  SupernodalCholesky cholesky_;
  SupernodalCholesky::SparseRhs rhs_;
  Eigen::Vector4i rhs_nodes_ = Eigen::Vector4i::Zero();
  bool has_rhs_ = false;
  Eigen::VectorXd f_, x_;
};

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
  IterativeSolve(const ElasticBody& body, const ElasticSolveOptions& o)
      : body_(body), preconditioner_(o.preconditioner), tolerance_(o.cg_tolerance) {
    const int n = body.free_dofs();
    if (o.preconditioner == "two_level") {
      if (!o.coarse_space) throw std::invalid_argument("preconditioner two_level needs a coarse mesh; none was given");
      const Eigen::SparseMatrix<double> P = coarse_prolongation(body, *o.coarse_space);
      cg_ = std::make_unique<PreconditionedCG>(body.free_stiffness(), o.cg_tolerance, 10 * n, &P);
    } else {
      cg_ = std::make_unique<PreconditionedCG>(body.free_stiffness(), o.cg_tolerance, 10 * n);
    }
    f_.setZero(n);
    x_.setZero(n);
  }

  void solve(const LoadStencil& load, const Eigen::Vector3d& force, Eigen::VectorXd& u) override {
    if (u.size() != body_.dofs()) u = Eigen::VectorXd::Zero(body_.dofs());
    body_.load_vector(load, force, f_);
    body_.to_free(u, x_);
    last_iterations_ = cg_->solve(f_, x_);
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
  Eigen::VectorXd f_, x_;
  int last_iterations_ = 0;
};

}  // namespace

const std::vector<ElasticSolveInfo>& elastic_solves() {
  static const std::vector<ElasticSolveInfo> list = {
      {"direct", "CHOLMOD factorisation in setup, back-substitution per frame",
       [](const ElasticBody& b, const ElasticSolveOptions&) { return std::make_unique<DirectSolve>(b); }},
      {"iterative", "preconditioned CG from the previous frame's solution",
       [](const ElasticBody& b, const ElasticSolveOptions& o) { return std::make_unique<IterativeSolve>(b, o); }},
  };
  return list;
}

std::unique_ptr<ElasticSolve> make_elastic_solve(const std::string& name, const ElasticBody& body,
                                                 const ElasticSolveOptions& options) {
  for (const auto& s : elastic_solves())
    if (s.name == name) return s.create(body, options);
  std::string known;
  for (const auto& s : elastic_solves()) known += (known.empty() ? "" : ", ") + s.name;
  throw std::invalid_argument("unknown elastic solve '" + name + "' (known: " + known + ")");
}

std::vector<ParameterSpec> elastic_solve_parameters(const std::string& prefix, const std::string& default_solver,
                                                    const std::string& default_preconditioner) {
  std::vector<std::string> names;
  std::string described;
  for (const auto& s : elastic_solves()) {
    names.push_back(s.name);
    described += (described.empty() ? "" : "; ") + s.name + ": " + s.description;
  }
  using P = ParameterSpec;
  return {P::choice(prefix + "solver", names, default_solver, described),
          P::choice(prefix + "preconditioner", {"two_level", "ic"}, default_preconditioner,
                    "of the iterative solver. two_level: incomplete Cholesky plus a coarse correction on the "
                    "scenario's coarse (hybrid) tet mesh; ic: incomplete Cholesky alone"),
          P::number(prefix + "cg_tolerance", 1e-8, 1e-14, 1e-2, "relative residual tolerance of the iterative solver")};
}

std::unique_ptr<ElasticSolve> make_elastic_solve(const ElasticBody& body, const Parameters& p,
                                                 const std::string& prefix, const TetMesh* coarse_space) {
  ElasticSolveOptions o;
  o.cg_tolerance = p.number(prefix + "cg_tolerance");
  o.preconditioner = p.choice(prefix + "preconditioner");
  o.coarse_space = coarse_space;
  const std::string solver = p.choice(prefix + "solver");
  if (solver == "iterative" && o.preconditioner == "two_level" && !coarse_space)
    throw std::invalid_argument(prefix + "preconditioner two_level needs the scenario's coarse volume mesh; use " +
                                prefix + "preconditioner ic");
  return make_elastic_solve(solver, body, o);
}

}  // namespace tb
