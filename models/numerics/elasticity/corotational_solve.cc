// The corotational elastic solve (stiffness warping, Mueller and Gross 2004): the
// element rotations and the rotated stiffness are corotational_elements.h; this
// file holds the strategy's fixed-point iteration and its own parameters.
#include <algorithm>
#include <stdexcept>

#include "corotational_elements.h"
#include "elastic_solve.h"
#include "preconditioned_cg.h"
#include "supernodal_cholesky.h"

namespace tb {

namespace {

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
/// Prescribed displacements (grasps, plates) are Dirichlet values on the rotated
/// system: with the held dofs u_p set in u by the caller, each update solves
/// K_R,ff u_f = f_f + c_f - K_R,fp u_p, and the reactions are f - f_int at the held
/// dofs with f_int = K_R u - c, the corotational elastic force (internal_force()).
class CorotationalSolve : public ElasticSolve {
 public:
  /// The options of this strategy alone (its parameters, corotational_solve_info).
  struct Options {
    double cg_tolerance = 1e-8;
    /// "converged" (rotation updates and solves until the rotations no longer
    /// change the solution, at most max_updates) or "per_frame" (one update and
    /// one linearised solve per call)
    std::string update = "converged";
    int max_updates = 1000;
    double relaxation = 0.5;  ///< the fraction of each update's solve step taken, in (0, 1]
  };

  CorotationalSolve(const ElasticBody& body, const Options& o)
      : body_(body),
        elements_(body.mesh(), body.material().youngs_modulus, body.material().poisson_ratio),
        cholesky_(body.free_stiffness()),
        tolerance_(o.cg_tolerance),
        converge_(o.update == "converged"),
        max_updates_(o.max_updates),
        relaxation_(o.relaxation),
        work_(body.free_dofs()) {
    if (o.update != "converged" && o.update != "per_frame")
      throw std::invalid_argument("corotational update '" + o.update + "' is neither converged nor per_frame");
    if (max_updates_ < 1) throw std::invalid_argument("corotational_max_updates must be at least 1");
    if (!(relaxation_ > 0 && relaxation_ <= 1))
      throw std::invalid_argument("corotational_relaxation must be in (0, 1]");
    const int n = body.free_dofs();
    for (Eigen::VectorXd* v : {&b_, &x_, &x_previous_, &step_, &step_previous_, &step_change_}) v->setZero(n);
    for (Eigen::VectorXd* v : {&p_full_, &y_full_, &held_, &f_int_}) v->setZero(body.dofs());
  }

  /// The rotated stiffness is not K: the caller sets the held values in u and passes
  /// the external force alone (ElasticFrame), and reactions use internal_force().
  bool linear() const override { return false; }
  const Eigen::VectorXd* internal_force() const override { return &f_int_; }

  void solve(const Eigen::VectorXd& f_free, const std::vector<int>*, Eigen::VectorXd& u) override {
    if (u.size() != body_.dofs()) u = Eigen::VectorXd::Zero(body_.dofs());
    body_.to_free(u, x_);
    // u with its free dofs zeroed: the held values alone, lifted into b each update.
    held_ = u;
    for (int d = 0; d < body_.dofs(); ++d)
      if (body_.free_index(d) >= 0) held_(d) = 0;
    const bool lift = held_.lpNorm<Eigen::Infinity>() > 0;
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
      b_ += f_free;
      if (lift) {  // - K_R,fp u_p
        elements_.apply_stiffness(held_, y_full_);
        body_.to_free(y_full_, lift_);
        b_ -= lift_;
      }
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
      // When the rule gives w <= 0 (the step grew along the previous one) w restarts
      // at corotational_relaxation: clamping it to 0.01 there instead stalled the
      // iteration for tens of updates at a time (the cube's 1 N disc push, frame 8:
      // 1000 updates without converging; with the restart 242).
      step_ = x_ - x_previous_;
      if (converge_ && update > 1) {
        step_change_ = step_ - step_previous_;
        const double change2 = step_change_.squaredNorm();
        if (change2 > 0) {
          const double aitken = -w * step_previous_.dot(step_change_) / change2;
          w = aitken > 0 ? std::clamp(aitken, 0.01, 1.0) : relaxation_;
        }
      }
      step_previous_ = step_;
      x_ = x_previous_ + w * step_;
      body_.to_full(x_, u);
      last_updates_ = update;
      max_updates_seen_ = std::max(max_updates_seen_, update);
      max_inverted_ = std::max(max_inverted_, elements_.inverted_elements());
      max_svd_fallbacks_ = std::max(max_svd_fallbacks_, elements_.svd_fallbacks());
      if (!converge_ || iterations == 0) {
        elements_.elastic_force(u, f_int_);  // at the rotations of this update (converged: of u, to cg_tolerance)
        break;
      }
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
  Eigen::VectorXd b_, x_, x_previous_;                  ///< free dofs: right-hand side f + c, solution, u^k
  Eigen::VectorXd p_full_, y_full_;                     ///< 3 #V: K_R's argument and product
  Eigen::VectorXd held_, f_int_;                        ///< 3 #V: the held values alone; K_R u - c
  Eigen::VectorXd lift_;                                ///< free dofs: K_R,fp u_p
  int last_iterations_ = 0, last_updates_ = 0, max_updates_seen_ = 0, max_inverted_ = 0, max_svd_fallbacks_ = 0;
};

}  // namespace

ElasticSolveInfo corotational_solve_info() {
  return {"corotational",
          "corotational linear FEM (Mueller and Gross 2004, element rotations by polar decomposition): CG on the "
          "rotated stiffness from the previous frame, preconditioned by the linear K's factorisation",
          [](const std::string& prefix) {
            using P = ParameterSpec;
            std::vector<ParameterSpec> specs = cg_tolerance_parameter(prefix);
            for (ParameterSpec& s : std::vector<ParameterSpec>{
      P::choice(prefix + "corotational_update", {"converged", "per_frame"}, "converged",
                "of the corotational solver. converged: element rotations re-estimated and the system re-solved "
                "until the rotations no longer change the solution (the corotational equilibrium to "
                "cg_tolerance; an error after corotational_max_updates); per_frame: one rotation update and one "
                "linearised solve per frame, as interactive simulators do"),
      P::whole_number(prefix + "corotational_max_updates", 1000, 1, 100000,
                      "of the corotational solver, update converged: rotation updates allowed per frame"),
      P::number(prefix + "corotational_relaxation", 0.5, 0.01, 1,
                "of the corotational solver: u^{k+1} = u^k + w (K_R^-1 (f + c) - u^k) after each rotation update, "
                "w = this in per_frame, and in converged for the first update (then adapted by Aitken's rule, and "
                "back to this value whenever the rule gives w <= 0). "
                "1 is Mueller and Gross's undamped stiffness warping, which oscillates without settling at 1 N "
                "on the paper's cube (a static solve has no mass term)")})
              specs.push_back(std::move(s));
            return specs;
          },
          [](const ElasticBody& b, const Parameters& p, const std::string& prefix, const ElasticSolveContext&) {
            CorotationalSolve::Options o;
            o.cg_tolerance = p.number(prefix + "cg_tolerance");
            o.update = p.choice(prefix + "corotational_update");
            o.max_updates = p.integer(prefix + "corotational_max_updates");
            o.relaxation = p.number(prefix + "corotational_relaxation");
            return std::unique_ptr<ElasticSolve>(new CorotationalSolve(b, o));
          },
          [](const Parameters&, const std::string&) { return std::string("has no contact"); },
          [](const Parameters&, const std::string&) { return std::string("has no springs for its pads"); }};
}

}  // namespace tb
