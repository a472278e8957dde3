// The elastic solve strategies. Each is a small class over an ElasticBody:
//  - direct: CHOLMOD factorisation made once (setup), per frame our own
//    back-substitution whose forward part visits only the load's elimination-tree
//    paths (supernodal_cholesky.h);
//  - iterative: conjugate gradients warm-started from the previous frame,
//    preconditioned by incomplete Cholesky or the two-level preconditioner
//    (preconditioned_cg.h);
//  - corotational: stiffness warping (Mueller and Gross 2004,
//    corotational_elements.h), CG on the rotated stiffness K_R warm-started from
//    the previous frame and preconditioned by the linear K's factorisation.
#include "elastic_solve.h"

#include <algorithm>
#include <stdexcept>

#include "corotational_elements.h"
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

/// Corotational linear FEM (Mueller and Gross 2004, corotational_elements.h): the equilibrium
/// sum_e R_e K_e (R_e^T x_e - X_e) = f, with R_e the polar rotation of tet e at u,
/// solved by the (relaxed) fixed-point iteration of stiffness warping
///   R^k = R(u^k),  v = K_R(R^k)^-1 (f + c(R^k)),  u^{k+1} = u^k + w^k (v - u^k)
/// (corotational_elements.h). w^0 = corotational_relaxation; in "converged" the
/// later w^k adapt by Aitken's rule (undamped, w = 1, the iteration oscillates
/// without settling at 1 N on the paper's cube: a static solve has no mass
/// term to damp it, unlike Mueller and Gross's implicit time step). Each linear solve is
/// CG warm-started from u^k and preconditioned by the factorised linear K (the
/// CHOLMOD factor `direct` uses, full back-substitution): K_R = K when every
/// R_e = I. One CG iteration costs one matrix-free K_R product (a loop over the
/// tets) and one back-substitution with K's factor; one update, a 3x3 SVD per tet.
/// "converged" repeats until, right after an update, the warm start already
/// satisfies K_R u = f + c to cg_tolerance (CG takes 0 iterations): the
/// corotational force balance then holds to that tolerance. "per_frame" makes one
/// update and one solve per call, as interactive simulators do (the rotations lag
/// one frame; a static load converges over the frames).
class CorotationalSolve : public ElasticSolve {
 public:
  CorotationalSolve(const ElasticBody& body, const ElasticSolveOptions& o)
      : body_(body),
        elements_(body.mesh(), body.material().youngs_modulus, body.material().poisson_ratio),
        cholesky_(body.free_stiffness()),
        tolerance_(o.cg_tolerance),
        converge_(o.corotational_update == "converged"),
        max_updates_(o.corotational_max_updates),
        relaxation_(o.corotational_relaxation),
        work_(body.free_dofs()) {
    if (o.corotational_update != "converged" && o.corotational_update != "per_frame")
      throw std::invalid_argument("corotational update '" + o.corotational_update +
                                  "' is neither converged nor per_frame");
    if (max_updates_ < 1) throw std::invalid_argument("corotational_max_updates must be at least 1");
    if (!(relaxation_ > 0 && relaxation_ <= 1))
      throw std::invalid_argument("corotational_relaxation must be in (0, 1]");
    const int n = body.free_dofs();
    for (Eigen::VectorXd* v : {&f_, &b_, &x_, &x_previous_, &step_, &step_previous_, &step_change_}) v->setZero(n);
    for (Eigen::VectorXd* v : {&p_full_, &y_full_}) v->setZero(body.dofs());
  }

  void solve(const LoadStencil& load, const Eigen::Vector3d& force, Eigen::VectorXd& u) override {
    if (u.size() != body_.dofs()) u = Eigen::VectorXd::Zero(body_.dofs());
    body_.load_vector(load, force, f_);
    body_.to_free(u, x_);
    const auto apply = [this](const Eigen::VectorXd& p, Eigen::VectorXd& q) {
      body_.to_full(p, p_full_);  // clamped dofs stay 0
      elements_.apply_stiffness(p_full_, y_full_);
      body_.to_free(y_full_, q);
    };
    const auto precondition = [this](const Eigen::VectorXd& r, Eigen::VectorXd& z) { cholesky_.solve(r, z); };
    last_iterations_ = 0;
    double w = relaxation_;
    for (int update = 1;; ++update) {
      elements_.update_rotations(u);
      body_.to_free(elements_.offset(), b_);
      b_ += f_;
      x_previous_ = x_;
      // In "converged", an inexact solve: CG reduces this update's residual by
      // kForcing only (the next update changes the system anyway), down to
      // cg_tolerance. At 1 N on the paper's cube, 17.6 CG iterations per frame
      // (mean over the ramp) instead of 56.4 solving each update to cg_tolerance
      // (0.1: 23.4), for 14 updates instead of 11.
      constexpr double kForcing = 0.3;
      const int iterations = conjugate_gradients(apply, precondition, b_, x_, tolerance_, 10 * body_.free_dofs(), work_,
                                                 converge_ ? kForcing : 0.0);
      last_iterations_ += iterations;
      // d^k = v - u^k, the fixed-point step; in "converged", w^k by Aitken's
      // delta-squared rule (Irons and Tuck 1969) from d^{k-1} and d^k, kept in [0.01, 1].
      step_ = x_ - x_previous_;
      if (converge_ && update > 1) {
        step_change_ = step_ - step_previous_;
        const double change2 = step_change_.squaredNorm();
        if (change2 > 0) w = std::clamp(-w * step_previous_.dot(step_change_) / change2, 0.01, 1.0);
      }
      step_previous_ = step_;
      x_ = x_previous_ + w * step_;
      body_.to_full(x_, u);
      last_updates_ = update;
      max_updates_seen_ = std::max(max_updates_seen_, update);
      max_inverted_ = std::max(max_inverted_, elements_.inverted_elements());
      max_svd_fallbacks_ = std::max(max_svd_fallbacks_, elements_.svd_fallbacks());
      if (!converge_ || iterations == 0) break;
      if (update == max_updates_)
        throw std::runtime_error("corotational solve: the rotations still change the solution after " +
                                 std::to_string(max_updates_) +
                                 " updates (corotational_max_updates); the load may be too large for this mesh");
    }
  }

  int last_iterations() const override { return last_iterations_; }
  nlohmann::json report() const override {
    return {{"solve", "corotational"},
            {"update", converge_ ? "converged" : "per_frame"},
            {"cg_tolerance", tolerance_},
            {"relaxation", relaxation_},
            {"preconditioner", "linear K factorisation"},
            {"factor_nonzeros", cholesky_.factor_nonzeros()},
            {"ordering", cholesky_.ordering()},
            {"rotation_updates_last_solve", last_updates_},
            {"rotation_updates_max", max_updates_seen_},
            {"inverted_elements_max", max_inverted_},
            {"svd_rotations_max", max_svd_fallbacks_}};
  }

 private:
  const ElasticBody& body_;
  CorotationalElements elements_;
  SupernodalCholesky cholesky_;
  double tolerance_;
  bool converge_;
  int max_updates_;
  double relaxation_;
  CgWorkspace work_;
  Eigen::VectorXd step_, step_previous_, step_change_;  ///< free dofs: d^k, d^{k-1}, their difference
  Eigen::VectorXd f_, b_, x_, x_previous_;              ///< free dofs: load, right-hand side f + c, solution, u^k
  Eigen::VectorXd p_full_, y_full_;                     ///< 3 #V: K_R's argument and product
  int last_iterations_ = 0, last_updates_ = 0, max_updates_seen_ = 0, max_inverted_ = 0, max_svd_fallbacks_ = 0;
};

}  // namespace

const std::vector<ElasticSolveInfo>& elastic_solves() {
  static const std::vector<ElasticSolveInfo> list = {
      {"direct", "CHOLMOD factorisation in setup, back-substitution per frame",
       [](const ElasticBody& b, const ElasticSolveOptions&) { return std::make_unique<DirectSolve>(b); }},
      {"iterative", "preconditioned CG from the previous frame's solution",
       [](const ElasticBody& b, const ElasticSolveOptions& o) { return std::make_unique<IterativeSolve>(b, o); }},
      {"corotational",
       "corotational linear FEM (Mueller and Gross 2004, element rotations by polar decomposition): CG on the "
       "rotated stiffness from the previous frame, preconditioned by the linear K's factorisation",
       [](const ElasticBody& b, const ElasticSolveOptions& o) { return std::make_unique<CorotationalSolve>(b, o); }},
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
  return {
      P::choice(prefix + "solver", names, default_solver, described),
      P::choice(prefix + "preconditioner", {"two_level", "ic"}, default_preconditioner,
                "of the iterative solver. two_level: incomplete Cholesky plus a coarse correction on the "
                "scenario's coarse (hybrid) tet mesh; ic: incomplete Cholesky alone"),
      P::number(prefix + "cg_tolerance", 1e-8, 1e-14, 1e-2,
                "relative residual tolerance of the iterative and corotational solvers"),
      P::choice(prefix + "corotational_update", {"converged", "per_frame"}, "converged",
                "of the corotational solver. converged: element rotations re-estimated and the system re-solved "
                "until the rotations no longer change the solution (the corotational equilibrium to "
                "cg_tolerance; an error after corotational_max_updates); per_frame: one rotation update and one "
                "linearised solve per frame, as interactive simulators do"),
      P::whole_number(prefix + "corotational_max_updates", 1000, 1, 100000,
                      "of the corotational solver, update converged: rotation updates allowed per frame (at 1 N push "
                      "on the paper's cube, where 12 tets invert, one frame took 579)"),
      P::number(prefix + "corotational_relaxation", 0.5, 0.01, 1,
                "of the corotational solver: u^{k+1} = u^k + w (K_R^-1 (f + c) - u^k) after each rotation update, "
                "w = this in per_frame, and in converged for the first update (then adapted by Aitken's rule). "
                "1 is Mueller and Gross's undamped stiffness warping, which oscillates without settling at 1 N "
                "on the paper's cube (a static solve has no mass term)")};
}

std::unique_ptr<ElasticSolve> make_elastic_solve(const ElasticBody& body, const Parameters& p,
                                                 const std::string& prefix, const TetMesh* coarse_space) {
  ElasticSolveOptions o;
  o.cg_tolerance = p.number(prefix + "cg_tolerance");
  o.preconditioner = p.choice(prefix + "preconditioner");
  o.coarse_space = coarse_space;
  o.corotational_update = p.choice(prefix + "corotational_update");
  o.corotational_max_updates = p.integer(prefix + "corotational_max_updates");
  o.corotational_relaxation = p.number(prefix + "corotational_relaxation");
  const std::string solver = p.choice(prefix + "solver");
  if (solver == "iterative" && o.preconditioner == "two_level" && !coarse_space)
    throw std::invalid_argument(prefix + "preconditioner two_level needs the scenario's coarse volume mesh; use " +
                                prefix + "preconditioner ic");
  return make_elastic_solve(solver, body, o);
}

}  // namespace tb
