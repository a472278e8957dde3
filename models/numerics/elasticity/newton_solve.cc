// The static nonlinear elastic solve: Newton's method on the body's total
// Lagrangian equilibrium f_int(u) = f_ext (dead loads), for any material law of
// numerics/materials (element forces and tangents from the law's P(F) and dP/dF on
// P1 tets, tet_element.h), each Newton system factorised by CHOLMOD (symbolic
// analysis once, numeric factorisation per iteration), with load increments from the
// last converged state (forces and prescribed displacements alike), a backtracking
// line search on the residual, and increments halved when Newton fails (an element
// the law cannot take, an indefinite tangent, no decrease, too many iterations);
// where 12 halvings (newton_max_halvings) still fail (a limit point or a bifurcation
// of the path: the tangent indefinite next to a converged state), the frame is finished by
// pseudo-transient continuation (Kelley and Keyes 1998; below) from the last
// converged state under the frame's whole load, to the equilibrium the body snaps to. The
// one-process nonlinear answer on the paper-sized meshes, beside the distributed
// reference (models/fem_distributed), and the nonlinear coarse FEM of the
// embedded and hybrid models (coarse_solver newton). Not a real-time strategy: a
// frame allocates (CHOLMOD's factorisation).
//
// With a budget of k Newton iterations a frame (newton_max_iterations_per_frame > 0)
// it is the real-time form of that coarse solve: a frame continues from the last
// frame's iterate (warm start, converged or not), takes the whole load and the
// tools' new positions at once (no increments), and stops after k iterations or at
// convergence, accepting the iterate it has; the first iteration carries the held
// values' move as inhomogeneous constraints (the step of predict_interior). Each
// iteration refactorises the tangent (CHOLMOD), and the frame's relative residual
// |R_free| / (the forces in play) is reported, so that a reader sees how far from
// equilibrium the frame's answer is. Under a constant load the frames continue
// Newton's iteration: k frames of budget 1 are one frame of budget k.
//
// Rigid frictionless spheres (any law): the KKT conditions of min Pi(u) subject to
// g_i(u) = |x_i - c| - r >= 0 at the body's surface nodes (Pi the incremental
// potential and f_int its gradient's internal part, inertia included, with a time
// step: below),
//   f_int(u) - f = sum_i lambda_i n_i,  lambda_i >= 0,  g_i >= 0,  lambda_i g_i = 0,
// by a primal-dual active set (Hintermueller, Ito and Kunisch 2002) inside Newton:
// each iteration linearises the gaps of the active nodes at their current positions
// (the normal moves with the node; Wriggers 2006, ch. 5-6) and solves
//   (K - sum_a lambda_a (I - n_a n_a^T) / |x_a - c|) du = -(f_int - f) + N^T lambda,
//   N du = -g_A,
// for (du, lambda) by the Schur complement S = N K~^-1 N^T, K~^-1 applied on the law's
// Cholesky factor with the curvature, a rank-2 term per active node, by the
// Sherman-Morrison-Woodbury identity (low_rank_downdate.h): the factor stays
// supernodal and definite where the curvature makes K~ indefinite; then nodes with
// lambda < 0 leave the set and penetrating ones join. The sphere moves with the load
// increments (docs/equations.md, "Contact with a rigid sphere"). A set entered again
// without the merit halving ends the increment (the update cycles); where increments
// halved 12 times still fail (a fold of the quasi-static path, docs/equations.md) the
// pseudo-transient continuation finishes the frame, as under dead loads.
//
// With a time step h it is the dynamic reference (models/fem_dynamic): implicit
// (backward) Euler with the lumped mass M, each step the minimiser of the
// incremental potential (Kane et al. 2000; Gast et al. 2015; docs/equations.md):
//   M / h^2 (u - u_n - h v_n) + f_int(u) = f,   v_{n+1} = (u - u_n) / h,
// solved by the same Newton iteration with M / h^2 added to the tangent's diagonal,
// a sphere's contact included (the sphere moves through the step's load increments
// as through the static solve's; the last one is the whole step).
#include <Eigen/CholmodSupport>
#include <Eigen/Cholesky>
#include <algorithm>
#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "elastic_solve.h"
#include "lame_parameters.h"
#include "low_rank_downdate.h"
#include "material_laws.h"
#include "progress_notice.h"
#include "tet_element.h"

namespace tb {
namespace {

class NewtonSolve : public ElasticSolve {
 public:
  struct Options {
    std::string law = "neo_hookean";
    double tolerance = 1e-10;  ///< |R_free| <= tolerance * the forces in play, or |du| <= tolerance |u|
    int max_iterations = 50;   ///< per increment, before it is halved
    int load_steps = 1;        ///< increments per solve (halved on failure)
    int max_halvings = 12;     ///< of one frame's increments, before the pseudo-transient continuation
    int max_iterations_per_frame = 0;  ///< > 0: a frame does at most this many iterations from the last iterate
    double time_step = 0;              ///< > 0: implicit Euler with this step, s (else static)
    int blas_threads = 1;              ///< OpenBLAS threads under CHOLMOD's factorisation, during a solve
    double progress_seconds = 60;      ///< a progress line at most this often in a long solve (progress_notice.h)
  };

  NewtonSolve(const ElasticBody& body, const Options& o)
      : body_(body), law_(find_material_law(o.law)), lame_(lame_parameters(body.material())), o_(o) {
    const TetMesh& m = body.mesh();
    shapes_.reserve(static_cast<size_t>(m.T.rows()));
    for (Eigen::Index t = 0; t < m.T.rows(); ++t)
      shapes_.push_back(tet_shape(m.V.row(m.T(t, 0)), m.V.row(m.T(t, 1)), m.V.row(m.T(t, 2)), m.V.row(m.T(t, 3))));
    // The tangent lives on K's pattern (every pair of nodes sharing a tet): where
    // each element entry lands in its values, and where each free entry comes from.
    K_full_ = body.full_stiffness();
    const auto value_index = [&](int row, int col) { return this->value_index(row, col); };
    scatter_.resize(static_cast<size_t>(m.T.rows()) * 144);
    for (Eigen::Index t = 0; t < m.T.rows(); ++t)
      for (int a = 0; a < 12; ++a)
        for (int b = 0; b < 12; ++b)
          scatter_[static_cast<size_t>(t) * 144 + static_cast<size_t>(12 * b + a)] =
              value_index(3 * m.T(t, a / 3) + a % 3, 3 * m.T(t, b / 3) + b % 3);
    K_free_ = body.free_stiffness();
    std::vector<int> free_to_full_dof(static_cast<size_t>(body.free_dofs()));
    for (int d = 0; d < body.dofs(); ++d)
      if (body.free_index(d) >= 0) free_to_full_dof[static_cast<size_t>(body.free_index(d))] = d;
    for (int c = 0; c < K_free_.outerSize(); ++c)
      for (Eigen::SparseMatrix<double>::InnerIterator it(K_free_, c); it; ++it)
        free_from_full_.push_back(value_index(free_to_full_dof[static_cast<size_t>(it.row())],
                                              free_to_full_dof[static_cast<size_t>(it.col())]));
    if (o.time_step > 0) {
      // Row-sum lumping of P1's consistent mass: a quarter of each tet's mass to each node.
      inertia_ = Eigen::VectorXd::Zero(body.dofs());
      for (Eigen::Index t = 0; t < m.T.rows(); ++t)
        for (int a = 0; a < 4; ++a)
          inertia_.segment<3>(3 * m.T(t, a)).array() +=
              body.material().density * shapes_[static_cast<size_t>(t)].volume / 4 / (o.time_step * o.time_step);
      velocity_ = Eigen::VectorXd::Zero(body.dofs());
    }
    // Each dof's diagonal entry: implicit Euler's mass and pseudo-time's scaling V go there.
    rest_diagonal_.resize(body.dofs());
    for (int d = 0; d < body.dofs(); ++d) {
      diagonal_.push_back(value_index(d, d));
      rest_diagonal_(d) = K_full_.valuePtr()[diagonal_.back()];
    }
    // The scale of a gap's violation in the line search's merit: the stiffest free dof (N/m).
    for (int d = 0; d < K_free_.outerSize(); ++d) stiffness_scale_ = std::max(stiffness_scale_, K_free_.coeff(d, d));
    cholesky_.cholmod().print = 0;  // an indefinite tangent is handled (info()), not printed
    ldlt_.cholmod().print = 0;
    cholesky_.analyzePattern(K_free_);
    notice_clock_ = ProgressNoticeClock(
        std::chrono::duration_cast<std::chrono::steady_clock::duration>(std::chrono::duration<double>(o.progress_seconds)));
    u_converged_ = Eigen::VectorXd::Zero(body.dofs());
    f_converged_ = Eigen::VectorXd::Zero(body.free_dofs());
  }

  bool linear() const override { return false; }
  bool takes_spheres() const override { return o_.max_iterations_per_frame == 0; }  // a budget has no contact set
  bool takes_springs() const override { return true; }
  const Eigen::VectorXd* internal_force() const override { return &f_int_solution_; }

  void solve(const Eigen::VectorXd& f_free, const std::vector<int>*, Eigen::VectorXd& u) override {
    if (u.size() != body_.dofs()) u = Eigen::VectorXd::Zero(body_.dofs());
    const BlasThreads blas(o_.blas_threads);
    if (o_.max_iterations_per_frame > 0) return budgeted(f_free, u);  // takes no sphere
    // The target: this frame's forces and the prescribed values the caller set in u;
    // the start: the last converged state.
    const Eigen::VectorXd u_target = u, u_start = u_converged_;
    Eigen::VectorXd state = u_start, f(body_.free_dofs());
    iterations_ = increments_ = halvings_ = 0;
    contact_ = spheres_ && spheres_->spheres() > 0;
    if (contact_ && centres_converged_.rows() != spheres_->centres().rows())
      centres_converged_ = spheres_->centres();  // the first frame: the spheres start where they are
    std::vector<ActivePair> active_converged = active_;
    double done = 0, increment = 1.0 / std::max(1, o_.load_steps);
    rescues_ = 0;
    notice_clock_.restart();
    while (done < 1) {
      double target = done + increment;
      if (target > 1 - 1e-12) target = 1;
      load_fraction_ = target;
      f = (1 - target) * f_converged_ + target * f_free;
      if (contact_) centres_now_ = (1 - target) * centres_converged_ + target * spheres_->centres();
      Eigen::VectorXd trial = state;
      set_constrained(u_start, u_target, target, trial);
      predict_interior(state, f, trial);
      if (newton(f, trial)) {
        state = trial;
        done = target;
        ++increments_;
        active_converged = active_;
      } else {
        active_ = active_converged;  // the increment again from the last converged set
        increment /= 2;
        if (++halvings_ > o_.max_halvings) {
          // The increment is down to 2^-max_halvings of the frame and still fails: a
          // fold or a bifurcation of the quasi-static path (located to that fraction of
          // the frame; with fewer halvings the continuation starts sooner, from farther
          // before it: cheaper, but where the load has several equilibria past the fold
          // the start picks one, docs/equations.md, "Crossing a fold sooner, and which
          // equilibrium"). With spheres, a node's
          // contact force reaches 0 where the body without it would be inside the
          // sphere (no equilibrium nearby, docs/equations.md); under dead loads, the
          // tangent turns indefinite next to a converged state (a limit point or a
          // buckling mode). Pseudo-transient continuation from the last converged
          // state under the frame's whole load finds the equilibrium the body snaps
          // to: at the fold itself the unstable mode's stiffness is near zero and the
          // damped flow would leave it as slowly.
          const double failed_at = target;
          const std::string plain_why = why_failed_;  // before the continuation records its own
          const int iterations_before = iterations_;
          if (progress_notices_wanted()) {
            std::ostringstream note;
            note << "newton (" << law_.name << "): no equilibrium at load fraction " << failed_at << " after "
                 << o_.max_halvings << " halvings (" << plain_why
                 << "); a pseudo-transient continuation to the frame's end, up to "
                 << 2 * kPseudoTransientIterations + o_.max_iterations << " iterations";
            progress_notice(note.str());
          }
          rescues_ = 1;
          ++rescues_total_;
          target = load_fraction_ = 1;
          f = f_free;
          if (contact_) centres_now_ = spheres_->centres();
          trial = state;
          set_constrained(u_start, u_target, target, trial);
          // The interior moved with the held values alone: the predictor at the load
          // the state is in equilibrium with (the frame's whole load in its right-hand
          // side would be Newton's full step from the fold, which the continuation is
          // there to damp). Not with spheres: the step would drop the contact forces.
          if (!contact_) predict_interior(state, (1 - done) * f_converged_ + done * f_free, trial);
          if (!continue_pseudo_transiently(f, trial)) {
            active_ = active_converged;  // a caller that goes on starts from the last converged set
            const std::string continuation_why = why_failed_;
            assemble(state, false);  // the last converged state's smallest det F, for the message
            const Eigen::Vector3d where = smallest_det_f_where();
            std::ostringstream msg;
            msg << "newton solve (" << law_.name << "): no equilibrium at load fraction " << failed_at << " after "
                << o_.max_halvings << " halvings of the increment"
                << " and a pseudo-transient continuation from there to the frame's end (the last attempt: "
                << plain_why << "; the continuation: " << continuation_why << "; smallest det F at load fraction "
                << std::setprecision(12) << done << std::setprecision(6) << ": " << smallest_det_f_ << " in the tet at ("
                << where.x() << ", " << where.y() << ", " << where.z() << ") at rest"
                << "); the load may exceed what the mesh and law allow";
            throw std::runtime_error(msg.str());
          }
          if (progress_notices_wanted())
            progress_notice("newton (" + law_.name + "): the continuation reached the frame's equilibrium in " +
                            std::to_string(iterations_ - iterations_before) + " iterations");
          state = trial;
          done = target;
          ++increments_;
        }
      }
    }
    // The internal force the reactions come from, inertia included: assembled around
    // the step's start (u_n, v_n), before they move on to this step's.
    assemble(state, false);
    f_int_solution_ = f_int_;
    smallest_det_f_solution_ = smallest_det_f_;
    smallest_det_f_where_ = smallest_det_f_where();
    if (o_.time_step > 0) velocity_ = (state - u_converged_) / o_.time_step;
    u = state;
    u_converged_ = state;
    f_converged_ = f_free;
    if (spheres_) record_contacts(state);
  }

  int last_iterations() const override { return iterations_; }
  nlohmann::json report() const override {
    nlohmann::json r = {{"solve", o_.time_step > 0 ? "newton, implicit Euler" : "newton"},
                        {"material_law", law_.name},
                        {"newton_tolerance", o_.tolerance},
                        {"blas_threads", o_.blas_threads},
                        {"load_increments_last_solve", increments_},
                        {"newton_max_halvings", o_.max_halvings},
                        {"increment_halvings_last_solve", halvings_},
                        {"newton_iterations_last_solve", iterations_},
                        {"smallest_det_f_last_solve", smallest_det_f_solution_},
                        {"smallest_det_f_tet_at_rest_m",
                         {smallest_det_f_where_.x(), smallest_det_f_where_.y(), smallest_det_f_where_.z()}}};
    r["pseudo_transient_continuations_last_solve"] = rescues_;
    r["pseudo_transient_continuations"] = rescues_total_;
    r["pseudo_time_raised_for_inverting_steps"] = pseudo_time_raised_;
    if (spheres_) r["active_set_cycles_detected"] = active_set_cycles_;
    if (o_.max_iterations_per_frame > 0) {
      r["newton_max_iterations_per_frame"] = o_.max_iterations_per_frame;
      r["relative_residual_last_solve"] = relative_residual_;
      r["converged_last_solve"] = converged_;
      r["largest_relative_residual"] = largest_residual_;
      if (!stopped_.empty()) r["stopped_early_last_solve"] = stopped_;
      r["prescribed_move_left_last_solve_m"] = prescribed_left_;
      // Over the run: a frame in the middle that stopped or left a tool short is
      // otherwise invisible once a later frame recovers.
      r["frames_not_converged"] = frames_not_converged_;
      r["frames_stopped_early"] = frames_stopped_early_;
      r["largest_prescribed_move_left_m"] = largest_prescribed_left_;
      r["inverted_tets_last_solve"] = inverted_tets_;
    }
    if (spheres_)
      r["sphere_contact"] = {{"method", "primal-dual active set on the linearised gaps inside Newton (docs/equations.md)"},
                             {"gap_tolerance_over_radius", kGapTolerance},
                             {"active_nodes_last_solve", active_.size()},
                             {"largest_active_nodes", largest_active_},
                             {"indefinite_tangents", indefinite_factorisations_}};
    return r;
  }

 private:
  /// The non-free dofs of `u` at fraction t between `from` and `to` (the
  /// prescribed values; clamped ones stay 0).
  void set_constrained(const Eigen::VectorXd& from, const Eigen::VectorXd& to, double t, Eigen::VectorXd& u) const {
    for (int d = 0; d < body_.dofs(); ++d)
      if (body_.free_index(d) < 0) u(d) = (1 - t) * from(d) + t * to(d);
  }

  /// One frame of at most max_iterations_per_frame Newton iterations from the last
  /// frame's iterate towards equilibrium under f (and the prescribed values the
  /// caller set in u), each step line-searched as newton() does; the iterate it
  /// reaches is accepted, converged or not. A step that would leave the law
  /// undefined, or (the held values in place) raise |R| at every fraction, ends the
  /// frame early (reported, and counted over the run). A step or residual that is not
  /// finite is an error: nothing to accept.
  void budgeted(const Eigen::VectorXd& f, Eigen::VectorXd& u) {
    const Eigen::VectorXd& u_target = u;
    // u_converged_ is, under a budget, the last frame's accepted iterate (converged or not).
    Eigen::VectorXd& state = last_iterate_;
    state = u_converged_;
    iterations_ = 0;
    increments_ = 1;
    converged_ = false;
    stopped_.clear();
    bool f_int_at_state = false;  // after an accepted step: the line search assembled it there
    for (;;) {
      // The held values' move still to make (zero on free dofs) and the residual here.
      du_p_.setZero(body_.dofs());
      for (int d = 0; d < body_.dofs(); ++d)
        if (body_.free_index(d) < 0) du_p_(d) = u_target(d) - state(d);
      const bool held_in_place = du_p_.lpNorm<Eigen::Infinity>() == 0;
      if (!f_int_at_state && !assemble(state, false))
        throw std::logic_error("newton solve: an accepted iterate the law cannot take");
      residual(f, r_);
      const double r_norm = r_.norm();
      relative_residual_ = relative_to_forces(r_norm, f);
      if (!std::isfinite(relative_residual_))
        throw std::runtime_error("newton solve (" + std::string(law_.name) +
                                 "): the residual is not finite after a budgeted Newton step");
      if (held_in_place && relative_residual_ <= o_.tolerance) {
        converged_ = true;
        break;
      }
      if (iterations_ == o_.max_iterations_per_frame) break;
      ++iterations_;
      assemble(state, true);
      body_.to_free(K_full_ * du_p_, coupling_);
      if (!factorize_tangent()) {
        stopped_ = "tangent not positive definite";
        break;
      }
      du_free_ = cholesky_.solve(-r_ - coupling_);
      if (!du_free_.allFinite())
        throw std::runtime_error("newton solve (" + std::string(law_.name) + "): the Newton step is not finite");
      du_full_ = du_p_;
      body_.to_full(du_free_, du_full_);  // the free entries; the held ones stay du_p
      // Backtracking: the largest step 2^-k (k < 8) that keeps the law defined and,
      // the held values in place, lowers |R| (a step too small to matter is taken
      // as convergence, as newton() does). A full step puts the held values exactly
      // on their targets: state + (target - state) may miss them by an ulp.
      const bool negligible = held_in_place && du_full_.norm() <= o_.tolerance * state.norm();
      bool accepted = false;
      for (double step = 1; step > 1.0 / 256 && !accepted; step /= 2) {
        u_try_ = state + step * du_full_;
        if (step == 1)
          for (int d = 0; d < body_.dofs(); ++d)
            if (body_.free_index(d) < 0) u_try_(d) = u_target(d);
        if (!assemble(u_try_, false)) continue;
        if (held_in_place && !negligible) {
          residual(f, r_);
          accepted = r_.norm() < r_norm;
        } else {
          accepted = true;
        }
      }
      if (!accepted) {
        stopped_ = held_in_place ? "no decrease of the residual along the Newton step"
                                 : "the held values' move leaves the law undefined along the step";
        assemble(state, false);
        break;
      }
      state = u_try_;
      f_int_at_state = true;
      if (negligible) {
        converged_ = true;
        residual(f, r_);
        relative_residual_ = relative_to_forces(r_.norm(), f);
        break;
      }
    }
    // f_int_ is at `state` here.
    prescribed_left_ = du_p_.lpNorm<Eigen::Infinity>();
    if (!converged_) {
      // du_p_ was computed before the frame's last step: recompute what is left.
      prescribed_left_ = 0;
      for (int d = 0; d < body_.dofs(); ++d)
        if (body_.free_index(d) < 0) prescribed_left_ = std::max(prescribed_left_, std::abs(u_target(d) - state(d)));
    }
    largest_residual_ = std::max(largest_residual_, relative_residual_);
    largest_prescribed_left_ = std::max(largest_prescribed_left_, prescribed_left_);
    frames_not_converged_ += converged_ ? 0 : 1;
    frames_stopped_early_ += stopped_.empty() ? 0 : 1;
    u = state;
    u_converged_ = state;
    f_int_solution_ = f_int_;
    smallest_det_f_solution_ = smallest_det_f_;
    smallest_det_f_where_ = smallest_det_f_where();
    f_converged_ = f;
  }

  /// |R| relative to the forces in play: the external ones, or (under prescribed
  /// displacements alone) the internal ones.
  double relative_to_forces(double r_norm, const Eigen::VectorXd& f) const {
    return r_norm / std::max({f.norm(), f_int_.norm(), 1e-300});
  }

  /// Where the increment moves prescribed dofs (a plate, a grasp), the free dofs of
  /// `trial` are moved with them by one linearised step from the converged `state`:
  /// K_ff du_f = -(f_int_f(state) - f) - K_fp du_p, the first Newton step of the
  /// increment with the held values' increment as inhomogeneous constraints (the
  /// predictor of deal.II's step-44, Pelteret and McBride 2012; docs/equations.md).
  /// Without it the held nodes move alone and crush the layer of cells beside them,
  /// which halves the increments until they are a fraction of a cell. Kept only if
  /// the law stays defined there; Newton then starts from it.
  void predict_interior(const Eigen::VectorXd& state, const Eigen::VectorXd& f, Eigen::VectorXd& trial) {
    const Eigen::VectorXd du_p = trial - state;  // nonzero on prescribed dofs only
    if (du_p.lpNorm<Eigen::Infinity>() == 0) return;
    if (!assemble(state, true)) return;
    Eigen::VectorXd r, coupling;
    residual(f, r);
    body_.to_free(K_full_ * du_p, coupling);
    if (!factorize_tangent()) return;
    const Eigen::VectorXd du_free = cholesky_.solve(-r - coupling);
    Eigen::VectorXd du_full = Eigen::VectorXd::Zero(body_.dofs());
    body_.to_full(du_free, du_full);
    Eigen::VectorXd predicted = trial + du_full;
    if (assemble(predicted, false)) trial = std::move(predicted);
  }

  /// Factorises the free block of the tangent last assembled; false where it is not
  /// positive definite.
  bool factorize_tangent() {
    copy_free_tangent();
    cholesky_.factorize(K_free_);
    return cholesky_.info() == Eigen::Success;
  }

  /// K_free_: the free block of the tangent last assembled (K_full_).
  void copy_free_tangent() {
    for (size_t k = 0; k < free_from_full_.size(); ++k) K_free_.valuePtr()[k] = K_full_.valuePtr()[free_from_full_[k]];
  }

  /// f_int (3 #V) and, with `tangent`, the tangent's values on K's pattern at u.
  /// False where the law is undefined (det F <= 0 for a law not defined there).
  bool assemble(const Eigen::VectorXd& u, bool tangent) {
    const TetMesh& m = body_.mesh();
    f_int_.setZero(body_.dofs());
    inverted_tets_ = 0;
    smallest_det_f_ = std::numeric_limits<double>::infinity();
    smallest_det_f_tet_ = -1;
    if (tangent) std::fill(K_full_.valuePtr(), K_full_.valuePtr() + K_full_.nonZeros(), 0.0);
    for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
      const TetShape& s = shapes_[static_cast<size_t>(t)];
      Eigen::Matrix<double, 3, 4> x;
      for (int a = 0; a < 4; ++a) x.col(a) = m.V.row(m.T(t, a)).transpose() + u.segment<3>(3 * m.T(t, a));
      const Eigen::Matrix3d F = tet_deformation_gradient(s, x);
      const double J = F.determinant();
      if (J < smallest_det_f_) smallest_det_f_ = J, smallest_det_f_tet_ = static_cast<int>(t);
      if (!(J > 0)) {
        if (!law_.defined_when_inverted) return false;
        ++inverted_tets_;
      }
      const Eigen::Matrix<double, 9, 12> G = tet_gradient_operator(s);
      const Eigen::Matrix<double, 12, 1> fe = s.volume * (G.transpose() * flatten(law_.first_piola(F, lame_)));
      for (int a = 0; a < 4; ++a) f_int_.segment<3>(3 * m.T(t, a)) += fe.segment<3>(3 * a);
      if (!tangent) continue;
      const Eigen::Matrix<double, 12, 12> Ke = s.volume * (G.transpose() * (law_.tangent(F, lame_) * G));
      const int* at = &scatter_[static_cast<size_t>(t) * 144];
      for (int k = 0; k < 144; ++k) K_full_.valuePtr()[at[k]] += Ke.data()[k];
    }
    // The body's springs (a compliant grasp's pads): k u and k I; their pull k d is in f.
    const Eigen::VectorXd& springs = body_.spring_stiffness();
    for (Eigen::Index v = 0; v < springs.size(); ++v) {
      if (springs(v) == 0) continue;
      f_int_.segment<3>(3 * v) += springs(v) * u.segment<3>(3 * v);
      if (tangent)
        for (int c = 0; c < 3; ++c) K_full_.valuePtr()[diagonal_[static_cast<size_t>(3 * v + c)]] += springs(v);
    }
    if (o_.time_step > 0) {  // the inertia of implicit Euler, around the last step's state
      f_int_.array() += inertia_.array() * (u - u_converged_ - o_.time_step * velocity_).array();
      if (tangent)
        for (size_t d = 0; d < diagonal_.size(); ++d)
          K_full_.valuePtr()[diagonal_[d]] += inertia_(static_cast<Eigen::Index>(d));
    }
    return true;
  }

  /// R_free = f_int_free - f, from f_int_.
  void residual(const Eigen::VectorXd& f, Eigen::VectorXd& r) const {
    body_.to_free(f_int_, r);
    r -= f;
  }

  /// Newton from `u` (its constrained dofs already set) at external force f; true
  /// with u the equilibrium when converged. With spheres (contact_), the KKT
  /// conditions at centres_now_ with the active set active_ (header comment).
  bool newton(const Eigen::VectorXd& f, Eigen::VectorXd& u) {
    if (!assemble(u, true)) return failed("the start (the held values moved, the interior predicted) inverts a tet");
    Eigen::VectorXd r, du_free, du_full, u_try;
    residual(f, r);
    // The scale of the forces in play: the external ones, or (under prescribed
    // displacements alone) the internal ones the first state carries, or the contact's.
    const double scale0 = std::max({f.norm(), f_int_.norm(), 1e-300});
    const bool pseudo_transient = ptc_shift_ > 0;
    const int max_iterations = pseudo_transient ? kPseudoTransientIterations : o_.max_iterations;
    sets_seen_.clear();
    if (contact_) update_active_set(u);  // the nodes the sphere's move put inside join at once
    double merit = contact_ ? contact_terms(u, r) : r.norm();
    // A set entered again without the merit having halved since: the primal-dual update
    // cycles (set_cycles). Plain Newton gives the increment up (it is halved);
    // pseudo-transient continuation damps harder.
    const auto cycles = [&]() {
      if (!set_cycles(merit)) return false;
      ++active_set_cycles_;
      if (!pseudo_transient) return true;
      ptc_shift_ = std::max(10 * ptc_shift_, 1.0);
      sets_seen_.clear();
      return false;
    };
    for (int it = 0;; ++it) {
      const double r_norm = contact_ ? residual_c_.norm() : r.norm();
      const double scale = contact_ ? std::max(scale0, contact_free_.norm()) : scale0;
      if (r_norm <= std::max(o_.tolerance, ptc_tolerance_) * scale) {
        if (!contact_ || contact_settled(u)) return true;
        // In equilibrium with this set, but a node is inside or pulls: the set anew
        // (a step would be round-off the line search cannot decrease).
        if (update_active_set(u)) {
          merit = contact_terms(u, r);
          if (it == max_iterations) return failed("no convergence in the iterations allowed");
          if (cycles()) return failed("the contact's active set cycles");
          continue;
        }
      }
      if (it == max_iterations) return failed("no convergence in the iterations allowed");
      if (notice_clock_.due()) notice_iteration(r_norm / scale);
      ++iterations_;
      // The contact's curvature: in the tangent itself where pseudo-time's shift must
      // make the whole of it definite; otherwise a low-rank downdate of the law's
      // factor (prepare_curvature), which keeps that factor supernodal and positive
      // definite where the curvature makes the tangent indefinite (a node pressed hard
      // on the sphere's pole: lambda / |x - c| above its tangential stiffness).
      if (contact_ && pseudo_transient) add_contact_curvature(u);
      indefinite_ = false;
      curvature_.clear();
      if (pseudo_transient) {
        if (!factorize_shifted_tangent()) return failed("the pseudo-time-shifted tangent is not positive definite");
      } else if (!factorize_tangent()) {
        // The law's tangent itself is not positive definite (an element compressed
        // past its stability): with contact, the tangent and curvature by LDL^T, no
        // pivoting, which keeps Newton's quadratic rate.
        if (!contact_ || active_.empty())
          return failed("the tangent is not positive definite (an element compressed or sheared past its stability)");
        add_contact_curvature(u);
        copy_free_tangent();
        if (!ldlt_analysed_) ldlt_.analyzePattern(K_free_);
        ldlt_analysed_ = true;
        ldlt_.factorize(K_free_);
        if (ldlt_.info() != Eigen::Success) return failed("the indefinite tangent's LDL^T failed");
        indefinite_ = true;
        ++indefinite_factorisations_;
      } else if (contact_) {
        prepare_curvature(u);
      }
      du_free = solve_tangent(Eigen::VectorXd(-r));
      if (contact_ && !active_.empty()) solve_multipliers(du_free);
      du_full = Eigen::VectorXd::Zero(body_.dofs());
      body_.to_full(du_free, du_full);
      // Converged also when the step no longer moves u: near rest a law's stress is
      // a difference of terms of the size of mu (neo-Hookean: mu (F - F^-T)), which
      // leaves |R| a round-off floor that a small load's tolerance can sit below.
      // With spheres, a body at rest under no load (a sphere not yet touching) has |R|
      // and |u| at round-off: |u| counts at least the smallest radius.
      // (Not while pseudo-time damps the step: a small step there is not convergence.)
      const double u_scale = contact_ ? std::max(u.norm(), spheres_->radii().minCoeff()) : u.norm();
      if (ptc_shift_ == 0 && du_full.norm() <= o_.tolerance * u_scale) {
        u += du_full;
        if (!contact_) return true;
        for (size_t a = 0; a < active_.size(); ++a) active_[a].lambda = lambda_new_(static_cast<Eigen::Index>(a));
        if (contact_settled(u)) return true;
        const bool changed = update_active_set(u);
        if (!assemble(u, true)) return failed("a converged step inverts a tet");
        residual(f, r);
        merit = contact_terms(u, r);
        if (changed && cycles()) return failed("the contact's active set cycles");
        continue;
      }
      // Backtracking: the largest step 2^-k (k < 8) that keeps the law defined and
      // lowers |R| (with spheres, the merit |R(u, lambda)| + k_max |g_A(u)|, lambda
      // moved with the step). Pseudo-transient continuation takes its damped step
      // whole where the law stays defined (Kelley and Keyes 1998 use no line search):
      // crossing a snap, the merit must rise before it falls.
      bool accepted = false, every_step_inverts = true;
      double step = 1;
      for (; step > 1.0 / 256 && !accepted; step /= 2) {
        u_try = u + step * du_full;
        if (!assemble(u_try, true)) continue;
        every_step_inverts = false;
        residual(f, r);
        if (contact_) {
          for (size_t a = 0; a < active_.size(); ++a)
            trial_lambda_[a] = active_[a].lambda + step * (lambda_new_(static_cast<Eigen::Index>(a)) - active_[a].lambda);
          const double m = contact_terms(u_try, r, &trial_lambda_);
          // or already at the converged level (round-off)
          accepted = pseudo_transient || m < merit || m <= o_.tolerance * scale;
          if (accepted) merit = m;
        } else {
          accepted = pseudo_transient || r.norm() < r_norm;
          if (accepted) merit = r.norm();
        }
        if (accepted) break;
      }
      if (!accepted && pseudo_transient && every_step_inverts && ptc_shift_ < kPseudoTimeLargest) {
        // Even 1/256 of pseudo-time's step leaves the law undefined: the step is still
        // too much Newton's (near a fold its soft mode's part is huge). Damp harder and
        // take the iteration again from the same u, as Levenberg-Marquardt raises its
        // damping after a rejected step (Nocedal and Wright 2006, section 10.3): the
        // next ladder starts at 4x the shift that failed.
        ptc_shift_ = std::max(16 * ptc_shift_, kPseudoTimeStart);
        ++pseudo_time_raised_;
        if (!assemble(u, true)) return failed("an accepted iterate inverts a tet");
        residual(f, r);
        if (contact_) merit = contact_terms(u, r);
        continue;
      }
      if (!accepted)
        return failed(every_step_inverts ? "every step of the line search inverts a tet"
                                         : "the line search finds no step that lowers the residual");
      u = u_try;
      if (contact_) {
        for (size_t a = 0; a < active_.size(); ++a) active_[a].lambda = trial_lambda_[a];
        if (update_active_set(u)) {
          merit = contact_terms(u, r);  // the set changed: its merit anew
          if (cycles()) return failed("the contact's active set cycles");
        }
      }
    }
  }

  /// A progress line in a long solve, before an iteration: how many the frame has
  /// done, where its load is, how far the iterate is from equilibrium.
  void notice_iteration(double relative_residual) const {
    std::ostringstream note;
    note << "newton (" << law_.name << "): " << iterations_ << " iterations done in this frame, "
         << (ptc_shift_ > 0 ? "in the pseudo-transient continuation" : "at load fraction ");
    if (ptc_shift_ == 0) note << load_fraction_;
    note << ", relative residual " << std::setprecision(3) << relative_residual << ", smallest det F "
         << smallest_det_f_;
    progress_notice(note.str());
  }

  /// The rest centroid of the tet with the smallest det F at the last state assembled.
  Eigen::Vector3d smallest_det_f_where() const {
    if (smallest_det_f_tet_ < 0) return Eigen::Vector3d::Zero();
    const TetMesh& m = body_.mesh();
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int a = 0; a < 4; ++a) c += m.V.row(m.T(smallest_det_f_tet_, a)).transpose() / 4;
    return c;
  }

  /// Records why the last Newton attempt failed (the solve's error names the last
  /// one) and returns false.
  bool failed(const char* why) {
    why_failed_ = why;
    return false;
  }

  // --- Pseudo-transient continuation (Kelley and Keyes 1998) ---
  //
  // Past a fold of the quasi-static path Newton has no nearby equilibrium to converge
  // to, and where the tangent is indefinite it is drawn to the saddle the fold leaves
  // behind. Pseudo-transient continuation (Kelley and Keyes 1998, SIAM J. Numer. Anal.
  // 35, eq. 1.3) damps each Newton step by a pseudo-time term,
  //   (K~ + V / delta) du = -R,   V = the rest stiffness's diagonal,
  // a gradient flow of the energy while 1 / delta is large, Newton's step as it
  // vanishes. Here 1 / delta is the smallest on a ladder (factors of 4 from a quarter
  // of the last one, from 0) for which K~ + V / delta is positive definite (Nocedal
  // and Wright 2006, Algorithm 3.3, Cholesky with an added multiple of the identity):
  // each step is then a descent direction of the energy on the free dofs, so the
  // iteration leaves the saddle for a minimum, the contact's Schur complement is
  // positive definite and the primal-dual set update does not cycle on it; where the
  // tangent is positive definite it is Newton's step. Converged means the static KKT
  // conditions, as Newton's: the pseudo-time term only shapes the path.

  /// Pseudo-time's factor at the start (the ladder's first rung is a quarter of it:
  /// V / 4 added to the tangent's diagonal); the
  /// smallest nonzero factor tried.
  static constexpr double kPseudoTimeStart = 1, kPseudoTimeSmallest = 1e-6;
  /// The largest factor a step that inverts a tet raises it to (a step of about
  /// -R / (1e6 V): a gradient-flow step far below a cell's size).
  static constexpr double kPseudoTimeLargest = 1e6;
  /// The relative KKT residual at which pseudo-time hands over to plain Newton.
  static constexpr double kPseudoTimeLoose = 1e-6;
  /// Iterations a pseudo-transient continuation may take.
  static constexpr int kPseudoTransientIterations = 400;

  /// Newton from u at f by pseudo-transient continuation down to kPseudoTimeLoose
  /// (relative KKT residual), then plain Newton from there (quadratic near the
  /// minimum found), or, if that fails, pseudo-time down to Newton's tolerance.
  bool continue_pseudo_transiently(const Eigen::VectorXd& f, Eigen::VectorXd& u) {
    // Plain Newton again after it, whichever way it ends (a throw included).
    struct PlainNewtonAfter {
      NewtonSolve& solve;
      ~PlainNewtonAfter() { solve.ptc_shift_ = solve.ptc_tolerance_ = 0; }
    } plain_after{*this};
    ptc_shift_ = kPseudoTimeStart;
    ptc_tolerance_ = kPseudoTimeLoose;
    bool converged = newton(f, u);
    ptc_shift_ = 0;
    ptc_tolerance_ = 0;
    if (!converged) return false;
    const std::vector<ActivePair> set = active_;
    Eigen::VectorXd polished = u;
    if (newton(f, polished)) {
      u = polished;
      return true;
    }
    active_ = set;
    ptc_shift_ = kPseudoTimeSmallest;
    converged = newton(f, u);
    ptc_shift_ = 0;
    return converged;
  }

  /// Factorises the tangent last assembled plus 1 / delta V, 1 / delta the smallest
  /// on the ladder (from ptc_shift_ / 4) that makes it positive definite; ptc_shift_
  /// becomes it. False if none up to 1e6 does.
  bool factorize_shifted_tangent() {
    double added = 0;
    double shift = ptc_shift_ / 4 < kPseudoTimeSmallest ? 0 : ptc_shift_ / 4;
    for (;;) {
      for (size_t d = 0; d < diagonal_.size(); ++d)
        K_full_.valuePtr()[diagonal_[d]] += (shift - added) * rest_diagonal_(static_cast<Eigen::Index>(d));
      added = shift;
      if (factorize_tangent()) break;
      shift = std::max(4 * shift, kPseudoTimeSmallest);
      if (shift > 1e6) return false;
    }
    ptc_shift_ = std::max(shift, kPseudoTimeSmallest);  // the next ladder starts from a quarter of it (or 0)
    return true;
  }

  /// Whether the active set, just changed, was entered before in this Newton solve
  /// with a merit not more than twice the present one: the primal-dual update cycles
  /// (it has no descent to show for the round; Hintermueller, Ito and Kunisch 2002
  /// prove it monotone only for an M-matrix, and the contact's curvature can make the
  /// Schur complement indefinite). Records the set otherwise.
  bool set_cycles(double merit) {
    set_key_.clear();
    for (const ActivePair& p : active_) set_key_.emplace_back(p.vertex, p.sphere);
    std::sort(set_key_.begin(), set_key_.end());
    for (auto& [key, seen_merit] : sets_seen_)
      if (key == set_key_) {
        if (merit > 0.5 * seen_merit) return true;
        seen_merit = merit;
        return false;
      }
    sets_seen_.emplace_back(set_key_, merit);
    return false;
  }

  // --- Rigid spheres (header comment) ---

  /// A node in contact with a sphere and its multiplier (the normal force, N).
  struct ActivePair {
    int vertex = 0, sphere = 0;
    double lambda = 0;
    bool operator==(const ActivePair& o) const { return vertex == o.vertex && sphere == o.sphere; }
  };
  /// Gaps below -kGapTolerance r are penetrations; an active node is on its sphere within kGapTolerance r.
  static constexpr double kGapTolerance = 1e-9;

  int node_of(int vertex) const { return spheres_->surface_nodes()[static_cast<size_t>(vertex)]; }
  Eigen::Vector3d position(const Eigen::VectorXd& u, int node) const {
    return body_.mesh().V.row(node).transpose() + u.segment<3>(3 * node);
  }
  bool free_node(int node) const {
    return body_.free_index(3 * node) >= 0 || body_.free_index(3 * node + 1) >= 0 || body_.free_index(3 * node + 2) >= 0;
  }

  /// At u, with r = f_int - f on the free dofs: each active pair's gap and normal,
  /// the contact force N^T lambda on the free dofs (contact_free_), the residual
  /// R = r - N^T lambda (residual_c_) and the merit |R| + k_max |g_A|; lambda the
  /// active pairs' own, or `lambda` (one per pair).
  double contact_terms(const Eigen::VectorXd& u, const Eigen::VectorXd& r, const std::vector<double>* lambda = nullptr) {
    const size_t m = active_.size();
    normal_.resize(m);
    gap_.resize(static_cast<Eigen::Index>(m));
    contact_free_.setZero(body_.free_dofs());
    for (size_t a = 0; a < m; ++a) {
      const ActivePair& p = active_[a];
      const int node = node_of(p.vertex);
      gap_(static_cast<Eigen::Index>(a)) = sphere_gap(position(u, node), centres_now_.row(p.sphere).transpose(),
                                                      spheres_->radii()(p.sphere), normal_[a]);
      const double l = lambda ? (*lambda)[a] : p.lambda;
      for (int c = 0; c < 3; ++c) {
        const int free = body_.free_index(3 * node + c);
        if (free >= 0) contact_free_(free) += l * normal_[a](c);
      }
    }
    residual_c_ = r - contact_free_;
    return residual_c_.norm() + stiffness_scale_ * gap_.norm();
  }

  /// Calls visit(node, n_a, lambda_a / |x_a - c|) for each active pair pressed on its
  /// sphere (lambda_a > 0) at u: the gap's curvature there is that factor times
  /// (I - n_a n_a^T) (the normal turns as the node slides).
  template <class Visit>
  void for_each_curvature(const Eigen::VectorXd& u, Visit visit) const {
    for (size_t a = 0; a < active_.size(); ++a) {
      const ActivePair& p = active_[a];
      if (!(p.lambda > 0)) continue;
      const int node = node_of(p.vertex);
      const double distance = (position(u, node) - centres_now_.row(p.sphere).transpose()).norm();
      if (distance > 0) visit(node, normal_[a], p.lambda / distance);
    }
  }

  /// Subtracts the gap's curvature from each pressed node's diagonal block of the
  /// tangent last assembled, which makes the iteration Newton's on the KKT system.
  void add_contact_curvature(const Eigen::VectorXd& u) {
    for_each_curvature(u, [&](int node, const Eigen::Vector3d& n, double factor) {
      const Eigen::Matrix3d H = factor * (Eigen::Matrix3d::Identity() - n * n.transpose());
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) K_full_.valuePtr()[value_index(3 * node + i, 3 * node + j)] -= H(i, j);
    });
  }

  /// The curvature's downdate for this iteration (after the law's tangent, without
  /// it, was factorised): lambda_a (I - n_a n_a^T) / |x_a - c| = U_a U_a^T with U_a's two
  /// columns sqrt(lambda_a / |x_a - c|) times an orthonormal basis of the tangent plane,
  /// on the free dofs. Where K~ is singular, the step goes without the curvature (a
  /// quasi-Newton step).
  void prepare_curvature(const Eigen::VectorXd& u) {
    curvature_columns_.setZero(body_.free_dofs(), 2 * static_cast<Eigen::Index>(active_.size()));
    Eigen::Index k = 0;
    for_each_curvature(u, [&](int node, const Eigen::Vector3d& n, double factor) {
      Eigen::Index axis = 0;
      n.cwiseAbs().minCoeff(&axis);  // the axis least along n: its cross product with n is far from 0
      const Eigen::Vector3d t1 = n.cross(Eigen::Vector3d::Unit(axis)).normalized(), t2 = n.cross(t1);
      const double scale = std::sqrt(factor);
      for (const Eigen::Vector3d& t : {t1, t2}) {
        for (int c = 0; c < 3; ++c) {
          const int free = body_.free_index(3 * node + c);
          if (free >= 0) curvature_columns_(free, k) = scale * t(c);
        }
        ++k;
      }
    });
    if (k == 0) return;  // no node pressed yet (a joining node's lambda is 0)
    curvature_columns_.conservativeResize(Eigen::NoChange, k);
    Eigen::MatrixXd W = cholesky_.solve(curvature_columns_);
    if (!curvature_.prepare(curvature_columns_, std::move(W))) {
      curvature_.clear();
      return;
    }
    if (curvature_.negative_eigenvalues() > 0) ++indefinite_factorisations_;
  }

  /// K~^-1 B for this iteration's tangent: its LDL^T factor, or the law's Cholesky
  /// factor with the curvature's downdate (none under pseudo-time, whose shifted
  /// tangent holds it).
  template <class Matrix>
  Matrix solve_tangent(const Matrix& B) const {
    if (indefinite_) return ldlt_.solve(B);
    Matrix X = cholesky_.solve(B);
    curvature_.apply(X);
    return X;
  }

  /// du_free in: K~^-1 (-r); out: with the active gaps' linearised constraints,
  /// du0 + Y lambda_new, Y = K~^-1 N^T, S lambda_new = -g - N du0, S = N Y.
  void solve_multipliers(Eigen::VectorXd& du_free) {
    const Eigen::Index m = static_cast<Eigen::Index>(active_.size());
    Nt_.setZero(body_.free_dofs(), m);
    for (Eigen::Index a = 0; a < m; ++a) {
      const int node = node_of(active_[static_cast<size_t>(a)].vertex);
      for (int c = 0; c < 3; ++c) {
        const int free = body_.free_index(3 * node + c);
        if (free >= 0) Nt_(free, a) = normal_[static_cast<size_t>(a)](c);
      }
    }
    Y_ = solve_tangent(Nt_);
    const Eigen::MatrixXd S = Nt_.transpose() * Y_;
    lambda_new_ = S.ldlt().solve(-gap_ - Nt_.transpose() * du_free);
    du_free += Y_ * lambda_new_;
    trial_lambda_.resize(active_.size());
  }

  /// Whether u satisfies the contact's KKT conditions to kGapTolerance: every active
  /// multiplier non-negative and its node on the sphere, no free surface node inside.
  bool contact_settled(const Eigen::VectorXd& u) const {
    Eigen::Vector3d n;
    for (const ActivePair& p : active_) {
      if (p.lambda < 0) return false;
      const double g = sphere_gap(position(u, node_of(p.vertex)), centres_now_.row(p.sphere).transpose(),
                                  spheres_->radii()(p.sphere), n);
      if (std::abs(g) > kGapTolerance * spheres_->radii()(p.sphere)) return false;
    }
    return deepest_outside_set(u) <= 0;
  }

  /// Calls visit(vertex, sphere, gap, radius) for every free surface node inside a
  /// sphere by more than kGapTolerance r and not in the active set with it.
  template <class Visit>
  void for_each_penetration_outside_set(const Eigen::VectorXd& u, Visit visit) const {
    Eigen::Vector3d n;
    const int vertices = static_cast<int>(spheres_->surface_nodes().size());
    for (int k = 0; k < spheres_->spheres(); ++k) {
      const double r = spheres_->radii()(k);
      for (int v = 0; v < vertices; ++v) {
        const int node = node_of(v);
        if (!free_node(node)) continue;
        const double g = sphere_gap(position(u, node), centres_now_.row(k).transpose(), r, n);
        if (g >= -kGapTolerance * r) continue;
        if (std::find(active_.begin(), active_.end(), ActivePair{v, k, 0}) != active_.end()) continue;
        visit(v, k, g, r);
      }
    }
  }

  /// How deep (in units of kGapTolerance r) the deepest free surface node outside the set is inside a sphere.
  double deepest_outside_set(const Eigen::VectorXd& u) const {
    double worst = 0;
    for_each_penetration_outside_set(
        u, [&](int, int, double g, double r) { worst = std::max(worst, -g / (kGapTolerance * r)); });
    return worst > 1 ? worst : 0;
  }

  /// The primal-dual update of the set at u: pairs whose multiplier is tensile leave,
  /// free surface nodes inside a sphere join (lambda 0). True if it changed.
  bool update_active_set(const Eigen::VectorXd& u) {
    const size_t before = active_.size();
    active_.erase(std::remove_if(active_.begin(), active_.end(), [](const ActivePair& p) { return p.lambda < 0; }),
                  active_.end());
    bool changed = active_.size() != before;
    // Collected first: the visit searches active_, which must not grow under it.
    joining_.clear();
    for_each_penetration_outside_set(u, [&](int v, int k, double, double) { joining_.push_back({v, k, 0}); });
    active_.insert(active_.end(), joining_.begin(), joining_.end());
    return changed || !joining_.empty();
  }

  /// After a solve: each active pair's force lambda n on the body, into spheres_.
  void record_contacts(const Eigen::VectorXd& u) {
    contacts_.clear();
    Eigen::Vector3d n;
    for (const ActivePair& p : active_) {
      if (!contact_) break;
      const int node = node_of(p.vertex);
      sphere_gap(position(u, node), spheres_->centres().row(p.sphere).transpose(), spheres_->radii()(p.sphere), n);
      contacts_.push_back({node, p.vertex, p.sphere, p.lambda * n});
    }
    if (contact_) centres_converged_ = spheres_->centres();
    largest_active_ = std::max(largest_active_, static_cast<int>(active_.size()));
    positions_ = body_.mesh().V.transpose() + Eigen::Map<const Eigen::Matrix3Xd>(u.data(), 3, body_.mesh().V.rows());
    spheres_->record(contacts_, positions_);
  }

  /// Where the entry (row, col) of K's pattern is in K_full_'s values.
  int value_index(int row, int col) const {
    const int* begin = K_full_.innerIndexPtr() + K_full_.outerIndexPtr()[col];
    const int* end = K_full_.innerIndexPtr() + K_full_.outerIndexPtr()[col + 1];
    const int* at = std::lower_bound(begin, end, row);
    if (at == end || *at != row) throw std::logic_error("newton solve: an element entry outside K's pattern");
    return static_cast<int>(at - K_full_.innerIndexPtr());
  }

  const ElasticBody& body_;
  const MaterialLawInfo& law_;
  LameParameters lame_;
  Options o_;
  std::vector<TetShape> shapes_;
  std::vector<int> scatter_;         ///< per tet, its 12 x 12 entries' places in K_full_'s values (column-major)
  std::vector<int> free_from_full_;  ///< per value of K_free_, its place in K_full_'s values
  Eigen::SparseMatrix<double> K_full_, K_free_;
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholesky_;
  /// The contact's tangent where the law's own is not positive definite.
  Eigen::CholmodSimplicialLDLT<Eigen::SparseMatrix<double>, Eigen::Lower> ldlt_;
  bool ldlt_analysed_ = false;
  bool indefinite_ = false;  ///< whether this iteration's tangent was factorised by ldlt_
  long indefinite_factorisations_ = 0;  ///< iterations whose tangent, the curvature included, was indefinite
  LowRankDowndate curvature_;           ///< the contact's curvature on cholesky_'s factor (prepare_curvature)
  Eigen::MatrixXd curvature_columns_;
  Eigen::VectorXd f_int_, f_int_solution_, u_converged_, f_converged_;
  Eigen::VectorXd inertia_;    ///< implicit Euler: the lumped mass over h^2, per dof
  Eigen::VectorXd velocity_;   ///< implicit Euler: v_n
  std::vector<int> diagonal_;  ///< each dof's diagonal entry in K_full_'s values
  Eigen::VectorXd rest_diagonal_;  ///< pseudo-time's V: the rest stiffness's diagonal (N/m), per dof
  double ptc_shift_ = 0;           ///< pseudo-transient continuation's 1 / delta (0: plain Newton)
  double ptc_tolerance_ = 0;       ///< > 0: the relative KKT residual pseudo-time stops at
  int rescues_ = 0;                ///< pseudo-transient continuations in the last solve (0 or 1)
  long rescues_total_ = 0, active_set_cycles_ = 0;
  std::vector<std::pair<std::vector<std::pair<int, int>>, double>> sets_seen_;  ///< (set, merit) this Newton solve
  std::vector<std::pair<int, int>> set_key_;
  int iterations_ = 0, increments_ = 0, halvings_ = 0;
  int pseudo_time_raised_ = 0;  ///< over the run: continuation steps redone damped harder, every fraction inverting
  double load_fraction_ = 0;  ///< the frame's load fraction the increment in progress aims at
  ProgressNoticeClock notice_clock_{std::chrono::seconds(60)};  ///< paces the progress lines (Options)
  // A budgeted frame's state, what it reports, and its work vectors (sized at the first frame).
  double relative_residual_ = 0, largest_residual_ = 0, prescribed_left_ = 0, largest_prescribed_left_ = 0;
  bool converged_ = false;
  std::string stopped_;
  long frames_not_converged_ = 0, frames_stopped_early_ = 0;
  int inverted_tets_ = 0;  ///< tets with det F <= 0 at the last state assembled (laws defined there)
  double smallest_det_f_ = 1;           ///< the smallest det F at the last state assembled
  double smallest_det_f_solution_ = 1;  ///< ... at the last solve's answer (reported)
  int smallest_det_f_tet_ = -1;         ///< the tet where smallest_det_f_ is
  Eigen::Vector3d smallest_det_f_where_ = Eigen::Vector3d::Zero();  ///< its rest centroid at the last answer
  std::string why_failed_;              ///< why the last Newton attempt failed (failed())
  Eigen::VectorXd last_iterate_, du_p_, r_, coupling_, du_free_, du_full_, u_try_;
  // Spheres: whether this solve has any, the active set (kept from frame to frame),
  // the centres at the last converged state and at the current increment, and work.
  bool contact_ = false;
  std::vector<ActivePair> active_;
  std::vector<ActivePair> joining_;  ///< update_active_set's pairs to add (kept: no allocation per update)
  Eigen::MatrixX3d centres_converged_, centres_now_;
  std::vector<Eigen::Vector3d> normal_;
  Eigen::VectorXd gap_, contact_free_, residual_c_, lambda_new_;
  std::vector<double> trial_lambda_;
  Eigen::MatrixXd Nt_, Y_;
  double stiffness_scale_ = 0;
  int largest_active_ = 0;
  std::vector<NodeContact> contacts_;
  Eigen::Matrix3Xd positions_;
};

}  // namespace

ElasticSolveInfo newton_solve_info() {
  return {
      "newton",
      "static nonlinear FEM: Newton on f_int(u) = f for the material law of material_law, CHOLMOD on the "
      "tangent, load increments from the last converged state (a reference solve, not real time)",
      [](const std::string& prefix) {
        std::vector<std::string> laws;
        for (const MaterialLawInfo& l : material_laws()) laws.push_back(l.name);
        using P = ParameterSpec;
        std::vector<ParameterSpec> specs{
            P::choice(prefix + "material_law", laws, "neo_hookean",
                      "of the newton solver: the material law (numerics/materials), with the Lame parameters of "
                      "the scenario's E and nu"),
            P::number(
                prefix + "newton_tolerance", 1e-10, 1e-15, 1e-3,
                "of the newton solver: converged when |R| <= this times the norm of the forces in play, or a Newton "
                "step moves u by at most this times |u|"),
            P::whole_number(prefix + "newton_load_steps", 1, 1, 10000,
                            "of the newton solver: load increments per frame from the last converged state "
                            "(each halved when Newton fails)"),
            P::whole_number(prefix + "newton_max_halvings", 12, 0, 30,
                            "of the newton solver: halvings of a failing load increment before a pseudo-transient "
                            "continuation from the last converged state finishes the frame (12 locates a fold to "
                            "2^-12 of the frame; fewer start the continuation sooner, from farther before the fold)"),
            P::whole_number(prefix + "newton_max_iterations_per_frame", 0, 0, 1000,
                            "of the newton solver: 0, each frame to convergence; k > 0, a frame does at most k "
                            "Newton iterations from the last frame's iterate and accepts where it gets (its "
                            "residual reported), the whole load at once")};
        // A reference's own settings: not for a coarse solve inside a real-time frame,
        // whose timing stays single-threaded and which never runs a minute.
        if (prefix.empty()) {
          specs.push_back(P::whole_number("newton_blas_threads", 1, 1, 64,
                                          "of the newton solver: OpenBLAS threads under CHOLMOD's factorisation "
                                          "during its solve (a reference on a large mesh, where the factorisation is "
                                          "most of an iteration; the answer changes by round-off); 1 for a budgeted "
                                          "frame"));
          specs.push_back(P::number("newton_progress_seconds", 60, 0, 1e6,
                                    "of the newton solver: a progress line on stderr at most this often in a "
                                    "long solve (its iterations, load fraction, relative residual, smallest det F)"));
        }
        return specs;
      },
      [](const ElasticBody& b, const Parameters& p, const std::string& prefix, const ElasticSolveContext&) {
        NewtonSolve::Options o;
        o.law = p.choice(prefix + "material_law");
        o.tolerance = p.number(prefix + "newton_tolerance");
        o.load_steps = p.integer(prefix + "newton_load_steps");
        o.max_halvings = p.integer(prefix + "newton_max_halvings");
        o.max_iterations_per_frame = p.integer(prefix + "newton_max_iterations_per_frame");
        if (prefix.empty()) {
          o.blas_threads = p.integer("newton_blas_threads");
          o.progress_seconds = p.number("newton_progress_seconds");
        }
        if (o.max_iterations_per_frame > 0 && o.blas_threads > 1)
          throw std::invalid_argument("newton_blas_threads " + std::to_string(o.blas_threads) +
                                      ": a budgeted frame (newton_max_iterations_per_frame " +
                                      std::to_string(o.max_iterations_per_frame) +
                                      ") is timed as a real-time model's, on one thread");
        if (o.max_iterations_per_frame > 0 && o.load_steps > 1)
          throw std::invalid_argument(prefix + "newton_max_iterations_per_frame " +
                                      std::to_string(o.max_iterations_per_frame) +
                                      ": a budgeted frame takes the whole load at once, so " + prefix +
                                      "newton_load_steps must be 1, not " + std::to_string(o.load_steps));
        return std::unique_ptr<ElasticSolve>(new NewtonSolve(b, o));
      },
      [](const Parameters& p, const std::string& prefix) {
        const int budget = p.integer(prefix + "newton_max_iterations_per_frame");
        return budget == 0 ? std::string()
                           : "has no contact set in a budgeted frame (" + prefix + "newton_max_iterations_per_frame " +
                                 std::to_string(budget) + "; 0, to convergence, has)";
      },
      takes_the_tool};
}

std::unique_ptr<ElasticSolve> make_implicit_euler_solve(const ElasticBody& body, const std::string& law,
                                                        double tolerance, double time_step) {
  if (!(time_step > 0)) throw std::invalid_argument("implicit Euler: time_step must be positive");
  NewtonSolve::Options o;
  o.law = law;
  o.tolerance = tolerance;
  o.time_step = time_step;
  return std::make_unique<NewtonSolve>(body, o);
}

}  // namespace tb
