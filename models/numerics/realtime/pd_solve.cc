#include "pd_solve.h"

#include <Eigen/Cholesky>

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "pd_global_matrix.h"

namespace tb {
namespace {

const char* mode_name(PdMode m) { return m == PdMode::LocalGlobal ? "local_global" : "quasi_newton"; }

const char* weight_name(PdWeight w) {
  switch (w) {
    case PdWeight::Shear: return "shear";
    case PdWeight::Longitudinal: return "longitudinal";
    case PdWeight::Volume: return "volume";
  }
  return "";
}

/// w per unit volume, Pa: 2 mu, 2 mu + lambda or 2 mu + 3 lambda of (E, nu).
double weight_value(PdWeight w, const LameParameters& lame) {
  switch (w) {
    case PdWeight::Shear: return 2 * lame.mu;
    case PdWeight::Longitudinal: return 2 * lame.mu + lame.lambda;
    case PdWeight::Volume: return 2 * lame.mu + 3 * lame.lambda;
  }
  return 0;
}

template <class Law>
class PdSolve : public TetTimeStepper<Law> {
  using Base = TetTimeStepper<Law>;
  using Base::free_;
  using Base::mass_;
  using Base::s_;
  using Base::shapes_;
  using Base::T_;
  using Base::v_;
  using Base::x_;
  using Base::x_n_;

 public:
  PdSolve(const ElasticBody& body, const Law& law, const PdSettings& settings, double weight, bool defined_when_inverted)
      : Base(body, law, settings.stepping, "pd"), o_(settings), weight_(weight), keep_positive_(!defined_when_inverted) {
    const Eigen::Index n = x_.cols(), tets = T_.rows();
    Eigen::VectorXd node_weight(n);
    for (Eigen::Index v = 0; v < n; ++v) node_weight(v) = this->node_weight(v, s_.time_step * s_.time_step);
    global_ = std::make_unique<PdGlobalMatrix>(T_, shapes_, node_weight, free_, weight_);
    around_ = vertex_tets(T_, static_cast<int>(n));
    // One pass over the tets (the local step: stress and energy), then one over the nodes (the gradient).
    passes_.resize(2);
    for (Eigen::Index t = 0; t < tets; ++t) passes_[0].push_back(static_cast<int>(t));
    for (Eigen::Index v = 0; v < n; ++v) passes_[1].push_back(static_cast<int>(tets + v));
    tet_force_ = Eigen::Matrix3Xd::Zero(3, 4 * tets);
    tet_energy_ = Eigen::VectorXd::Zero(tets);
    valid_.assign(static_cast<size_t>(tets), 1);
    for (Eigen::Matrix3Xd* m : {&y_, &gradient_, &trial_gradient_, &trial_, &direction_, &q_})
      *m = Eigen::Matrix3Xd::Zero(3, n);
    s_pairs_.assign(static_cast<size_t>(o_.history), Eigen::Matrix3Xd::Zero(3, n));
    t_pairs_.assign(static_cast<size_t>(o_.history), Eigen::Matrix3Xd::Zero(3, n));
    rho_.assign(static_cast<size_t>(o_.history), 0);
    alpha_.assign(static_cast<size_t>(o_.history), 0);
    // The rounding floor of grad E: a stress of order w |F| (|F| = sqrt 3 at rest)
    // computed to a few 1e-16, times each node's sum of V_t |g_t,a|; 1e-14 stays
    // about tenfold above it (at 1e-13 the small cube settled 1e-10 from Newton, at
    // 1e-14 1e-11, at 1e-15 1e-12; with none, a body at rest drifted 8e-11 m in 100 frames).
    Eigen::VectorXd node_scale = Eigen::VectorXd::Zero(n);
    for (Eigen::Index t = 0; t < tets; ++t)
      for (int a = 0; a < 4; ++a)
        node_scale(T_(t, a)) += shapes_[static_cast<size_t>(t)].volume * shapes_[static_cast<size_t>(t)].gradients.col(a).norm();
    gradient_floor_ = 1e-14 * weight_ * std::sqrt(3.0) * node_scale.norm();
  }

 protected:
  bool takes_springs() const override { return true; }

  void advance() override {
    const double h = s_.time_step, h2 = h * h;
    // The inertial target and the first iterate x_n + h v_n (held components at the
    // frame's end); with springs, the target of each node's inertia and springs
    // (node_target), a held component's staying the tool's (a spring pulls free nodes only).
    this->for_node_ranges([&](Eigen::Index begin, Eigen::Index end, int) {
      for (Eigen::Index v = begin; v < end; ++v) {
        for (int i = 0; i < 3; ++i) {
          const bool moves = free_(i, v) != 0;
          y_(i, v) = moves ? x_n_(i, v) + h * v_(i, v) + h2 * this->f_ext_(i, v) / mass_(v) : this->target_(i, v);
          x_(i, v) = moves ? x_n_(i, v) + h * v_(i, v) : this->target_(i, v);
        }
        if (this->spring_(v) != 0) y_.col(v) = this->node_target(v, y_.col(v), h2);
      }
    });
    iterate(h2);
    this->for_node_ranges([&](Eigen::Index begin, Eigen::Index end, int) {
      for (Eigen::Index v = begin; v < end; ++v)
        for (int i = 0; i < 3; ++i)
          if (free_(i, v) != 0) v_(i, v) = (x_(i, v) - x_n_(i, v)) / h;
    });
  }

  nlohmann::json own_report() const override {
    return {{"solve", o_.mode == PdMode::LocalGlobal ? "projective dynamics, local/global (Bouaziz et al. 2014)"
                                                     : "projective dynamics, L-BFGS (Liu, Bouaziz and Kavan 2017)"},
            {"mode", mode_name(o_.mode)},
            {"material_law", o_.law},
            {"iterations", o_.iterations},
            {"history", o_.history},
            {"tolerance", o_.tolerance},
            {"weight", o_.mode == PdMode::LocalGlobal ? "the law's (2 mu + 3 lambda)" : weight_name(o_.weight)},
            {"weight_Pa", weight_},
            {"factors", global_->factors()},
            {"factor_nonzeros", global_->factor_nonzeros()},
            {"iterations_last_frame", done_},
            {"gradient_reduction_last_frame", reduction_},
            {"line_search_halvings", halvings_},
            {"line_search_failures", failures_},
            {"stages_last_frame", stages_}};
  }

  int last_iterations() const override { return done_; }

 private:
  /// The frame's iterations (per stage where the tools move in stages: each relax()
  /// until `iterations`, the tolerance, the gradient's rounding floor, or a line
  /// search that finds no decrease).
  void iterate(double h2) {
    const bool quasi_newton = o_.mode == PdMode::QuasiNewton;
    stages_ = 1;
    double energy = evaluate(x_, gradient_, h2, quasi_newton);
    if (energy == std::numeric_limits<double>::infinity()) {  // x_n + h v_n inverts a tet: from x_n
      for (Eigen::Index v = 0; v < x_.cols(); ++v)
        for (int i = 0; i < 3; ++i)
          if (free_(i, v) != 0) x_(i, v) = x_n_(i, v);
      energy = evaluate(x_, gradient_, h2, quasi_newton);
      if (energy == std::numeric_limits<double>::infinity()) {  // the tools' move itself: in stages
        stages_ = 0;
        this->move_held_in_stages([&] { relax(h2, evaluate(x_, gradient_, h2, quasi_newton)); }, o_.law, stages_);
        return;
      }
    }
    relax(h2, energy);
  }

  /// The iterations from a valid x_ whose E and gradient_ are computed.
  void relax(double h2, double energy) {
    const bool quasi_newton = o_.mode == PdMode::QuasiNewton;
    const bool contact = this->contact_on();
    if (contact) update_contact_set();
    const double first = contact ? contact_residual() : norm(gradient_);
    pairs_ = 0;
    done_ = 0;
    reduction_ = 1;
    for (; done_ < o_.iterations; ++done_) {
      if (contact && done_ > 0) update_contact_set();
      const double g = contact ? contact_residual() : norm(gradient_);
      reduction_ = first > 0 ? g / first : 0;
      if (!(g > std::max(o_.tolerance * first, gradient_floor_)) && !(contact && gap_open())) break;
      if (contact && !pd_contacts_.empty()) {
        pairs_ = 0;  // the L-BFGS pairs of an unconstrained iterate do not hold with the multipliers
        if (!constrained_step(h2, energy)) break;
        continue;
      }
      descent_direction();
      double slope = dot(direction_, gradient_);
      if (quasi_newton && !(slope < 0)) {  // the history spoilt it: A^-1 alone is a descent direction
        pairs_ = 0;
        descent_direction();
        slope = dot(direction_, gradient_);
      }
      double step = 1, trial_energy = 0;
      for (int halving = 0;; ++halving) {
        trial_ = x_ + step * direction_;
        trial_energy = evaluate(trial_, trial_gradient_, h2, quasi_newton);
        if (!quasi_newton ||
            sufficient_decrease(energy, trial_energy, step, slope, [&] { return dot(direction_, trial_gradient_); }))
          break;
        if (halving == kMaxHalvings) {
          ++failures_;
          if (contact) mark_contacts();
          return;
        }
        step /= 2;
        ++halvings_;
      }
      if (quasi_newton && o_.history > 0) remember(step);
      x_.swap(trial_);
      gradient_.swap(trial_gradient_);
      energy = trial_energy;
    }
    if (contact) mark_contacts();
  }

  /// The contact set's nodes with a non-negative multiplier are the sphere's contacts.
  void mark_contacts() {
    for (const PdContact& c : pd_contacts_) this->mark_contact(c.node, c.sphere, c.mu >= 0);
  }

  // --- Spheres: the linearised gaps as constraints of the global step ---

  struct PdContact {
    int node = 0, sphere = 0;
    double mu = 0;  ///< its multiplier, N
  };

  /// The primal-dual update of the contact set at x_: pairs with a tensile
  /// multiplier leave, free surface nodes inside a sphere join.
  void update_contact_set() {
    pd_contacts_.erase(std::remove_if(pd_contacts_.begin(), pd_contacts_.end(), [](const PdContact& c) { return c.mu < 0; }),
                       pd_contacts_.end());
    Eigen::Vector3d n;
    for (int node : this->spheres_->surface_nodes()) {
      if (this->surface_vertex(node) < 0) continue;
      for (int k = 0; k < this->spheres_->spheres(); ++k) {
        if (!(this->spheres_->gap(x_.col(node), k, n) < 0)) continue;
        bool known = false;
        for (const PdContact& c : pd_contacts_) known = known || (c.node == node && c.sphere == k);
        if (!known) pd_contacts_.push_back({node, k, 0});
      }
    }
  }

  /// Whether a node of the contact set is off its sphere by more than 1e-9 r (its
  /// linearised gap not yet closed: the gradient alone does not show it).
  bool gap_open() const {
    Eigen::Vector3d n;
    for (const PdContact& c : pd_contacts_) {
      const double r = this->spheres_->radii()(c.sphere);
      if (std::abs(this->spheres_->gap(x_.col(c.node), c.sphere, n)) > 1e-9 * r) return true;
    }
    return false;
  }

  /// |grad E| with, at each node of the contact set, the part along the outward
  /// normal that a non-negative multiplier balances removed (KKT: grad E = N^T mu).
  double contact_residual() {
    q_ = gradient_;
    Eigen::Vector3d n;
    for (const PdContact& c : pd_contacts_) {
      this->spheres_->gap(x_.col(c.node), c.sphere, n);
      n = n.cwiseProduct(free_.col(c.node));
      const double along = q_.col(c.node).dot(n);
      if (along > 0 && n.squaredNorm() > 0) q_.col(c.node) -= along / n.squaredNorm() * n;
    }
    return norm(q_);
  }

  /// One global step with the contact set's gaps linearised at x_ as constraints:
  ///   A d = -grad E + N^T mu,  N d = -g,
  /// solved by the Schur complement S = N A^-1 N^T (A^-1 N^T by one
  /// multi-right-hand-side solve per distinct factor of A: pd_global_matrix.h),
  /// then x += a d, a halved from 1 while a tet is not positive under a law
  /// undefined there and, in the quasi-Newton mode, until the Lagrangian decreases
  /// (below). A fixed point (d = 0) has g = 0 and grad E = N^T mu: the KKT
  /// conditions of the step's minimiser with the spheres. False (x_, the energy and
  /// the set's multipliers left as they were, so the frame's iterations end with the
  /// gaps the last accepted step left) if no a down to 2^-30 qualifies or S's
  /// multipliers are not finite.
  bool constrained_step(double h2, double& energy) {
    const size_t m = pd_contacts_.size();
    global_->solve(gradient_, direction_);
    direction_ = -direction_;
    // The Schur system's storage is kept: a frame whose contact set has the size of
    // the last one's allocates nothing (Eigen reallocates only on a change of size).
    const auto M = static_cast<Eigen::Index>(m);
    contact_nodes_.resize(m);
    normals_.resize(m);
    schur_rhs_.resize(M);
    schur_mu_.resize(M);
    for (size_t a = 0; a < m; ++a) {
      const PdContact& c = pd_contacts_[a];
      const double g = this->spheres_->gap(x_.col(c.node), c.sphere, normals_[a]);
      normals_[a] = normals_[a].cwiseProduct(free_.col(c.node));
      contact_nodes_[a] = c.node;
      schur_rhs_(static_cast<Eigen::Index>(a)) = -g - normals_[a].dot(direction_.col(c.node));
    }
    global_->node_constraints(contact_nodes_, normals_, schur_);
    schur_factor_.compute(schur_);
    schur_mu_ = schur_factor_.solve(schur_rhs_);
    // S is positive semi-definite (A is positive definite); a non-finite multiplier
    // (a rounding failure of the factorisation) ends the frame's iterations as a
    // failed line search does, with the last accepted step.
    if (schur_factor_.info() != Eigen::Success || !schur_mu_.allFinite()) {
      ++failures_;
      return false;
    }
    const Eigen::VectorXd& mu = schur_mu_;
    global_->add_constraint_response(mu, direction_);
    // The step is halved until it decreases the Lagrangian L = E - mu . g (mu fixed
    // at this step's multipliers) by Armijo's condition: d = -A^-1 grad L is a
    // descent direction of L, and A is only an approximation of E's Hessian. Taking
    // d whole (as before) overshot where the neo-Hookean Hessian outgrows A (a 50 ms
    // step under the sphere: the contact set went from 1 to 13 nodes frame to frame,
    // half the press inside the sphere at a frame's end); halved, it holds the 9
    // nodes the static FEM finds (tests/models/contact/sphere_contact_test.cc).
    // Local-global (a PD law) takes d whole: there A majorises the energy's Hessian
    // (Bouaziz et al. 2014), and relax() computes no energy to search with.
    const auto lagrangian = [&](const Eigen::Matrix3Xd& x, double e) {
      Eigen::Vector3d n;
      for (size_t a = 0; a < m; ++a)
        e -= mu(static_cast<Eigen::Index>(a)) * this->spheres_->gap(x.col(pd_contacts_[a].node), pd_contacts_[a].sphere, n);
      return e;
    };
    const auto lagrangian_slope = [&](const Eigen::Matrix3Xd& x, const Eigen::Matrix3Xd& gradient) {
      double slope = dot(direction_, gradient);
      Eigen::Vector3d n;
      for (size_t a = 0; a < m; ++a) {
        this->spheres_->gap(x.col(pd_contacts_[a].node), pd_contacts_[a].sphere, n);
        slope -= mu(static_cast<Eigen::Index>(a)) * n.dot(direction_.col(pd_contacts_[a].node));
      }
      return slope;
    };
    const bool search = o_.mode == PdMode::QuasiNewton;
    const double merit = search ? lagrangian(x_, energy) : 0, slope = search ? lagrangian_slope(x_, gradient_) : 0;
    double step = 1, trial_energy = 0;
    for (int halving = 0;; ++halving) {
      trial_ = x_ + step * direction_;
      trial_energy = evaluate(trial_, trial_gradient_, h2, true);
      if (std::isfinite(trial_energy) &&
          (!search || !(slope < 0) ||  // !(slope < 0): rounding at a fixed point
           sufficient_decrease(merit, lagrangian(trial_, trial_energy), step, slope,
                               [&] { return lagrangian_slope(trial_, trial_gradient_); })))
        break;
      if (halving == kMaxHalvings) {
        ++failures_;
        return false;
      }
      step /= 2;
      ++halvings_;
    }
    x_.swap(trial_);
    gradient_.swap(trial_gradient_);
    energy = trial_energy;
    for (size_t a = 0; a < m; ++a) pd_contacts_[a].mu = mu(static_cast<Eigen::Index>(a));
    return true;
  }

  static constexpr int kMaxHalvings = 30;

  /// Armijo's condition on a merit function phi (E for the unconstrained steps, the
  /// Lagrangian for the contact-constrained ones): phi(x + a d) <= phi(x) + c a s0,
  /// c = 1e-4, s0 = `slope` its slope along d at x. Near the minimiser the decrease is
  /// below phi's rounding (phi sums terms far larger than their change): there, the
  /// decrease is measured by the slopes instead, a (s0 + s1) / 2 (exact for a
  /// quadratic; Hager and Zhang 2005's approximate Wolfe condition), s1 = trial_slope()
  /// the slope at the trial point.
  template <class TrialSlope>
  static bool sufficient_decrease(double energy, double trial_energy, double step, double slope,
                                  const TrialSlope& trial_slope) {
    constexpr double c = 1e-4;
    if (!std::isfinite(trial_energy)) return false;  // a tet not positive under a law undefined there
    if (trial_energy <= energy + c * step * slope) return true;
    const double noise = 1e-13 * std::max(std::abs(energy), std::abs(trial_energy));
    if (!(std::abs(trial_energy - energy) <= noise)) return false;
    return trial_slope() <= (2 * c - 1) * slope;
  }

  /// direction_ = -H grad E, H the L-BFGS inverse Hessian over the stored pairs with
  /// A^-1 as its start (the two-loop recursion, Nocedal and Wright 2006, Algorithm 7.4).
  void descent_direction() {
    q_ = gradient_;
    const int m = o_.history;
    for (int k = 0; k < pairs_; ++k) {  // newest first
      const size_t i = static_cast<size_t>((newest_ - k + m) % m);
      alpha_[i] = rho_[i] * dot(s_pairs_[i], q_);
      q_ -= alpha_[i] * t_pairs_[i];
    }
    global_->solve(q_, direction_);
    for (int k = pairs_ - 1; k >= 0; --k) {  // oldest first
      const size_t i = static_cast<size_t>((newest_ - k + m) % m);
      const double beta = rho_[i] * dot(t_pairs_[i], direction_);
      direction_ += (alpha_[i] - beta) * s_pairs_[i];
    }
    direction_ = -direction_;
  }

  /// Stores s = step d and t = grad E(x + s) - grad E(x) unless s . t <= 0 (the
  /// curvature condition, without which the update is not positive definite).
  void remember(double step) {
    const int m = o_.history;
    const size_t i = static_cast<size_t>((newest_ + 1) % m);
    s_pairs_[i] = step * direction_;
    t_pairs_[i] = trial_gradient_ - gradient_;
    const double st = dot(s_pairs_[i], t_pairs_[i]);
    if (!(st > 0)) return;
    rho_[i] = 1 / st;
    newest_ = static_cast<int>(i);
    pairs_ = std::min(pairs_ + 1, m);
  }

  /// E(x) (when `with_energy`; +infinity if a tet is not positive under a law
  /// undefined there) and grad E(x) into `gradient` (3 by #V, zero where held):
  /// the tets' stresses, then each node's sum, on the thread team.
  double evaluate(const Eigen::Matrix3Xd& x, Eigen::Matrix3Xd& gradient, double h2, bool with_energy) {
    const Eigen::Index tets = T_.rows();
    auto item = [&](int k) {
      if (k < tets) {
        local_step(k, x, with_energy);
        return;
      }
      const int v = static_cast<int>(k - tets);
      Eigen::Vector3d g = this->node_weight(v, h2) * (x.col(v) - y_.col(v));
      for (int j = around_.offset[static_cast<size_t>(v)]; j < around_.offset[static_cast<size_t>(v) + 1]; ++j) {
        const auto [t, a] = around_.around[static_cast<size_t>(j)];
        g += tet_force_.col(4 * t + a);
      }
      gradient.col(v) = g.cwiseProduct(free_.col(v));
    };
    this->sweep(passes_, item);
    if (!with_energy) return 0;
    double energy = 0;
    for (Eigen::Index t = 0; t < tets; ++t) {
      if (!valid_[static_cast<size_t>(t)]) return std::numeric_limits<double>::infinity();
      energy += tet_energy_(t);
    }
    for (Eigen::Index v = 0; v < x.cols(); ++v) energy += this->node_weight(v, h2) / 2 * (x.col(v) - y_.col(v)).squaredNorm();
    return energy;
  }

  /// Tet t at x: V W(F) and its nodal forces V P(F) g_a (the local step).
  void local_step(Eigen::Index t, const Eigen::Matrix3Xd& x, bool with_energy) {
    const Eigen::Matrix3d F = this->deformation_gradient(t, x);
    const size_t k = static_cast<size_t>(t);
    valid_[k] = !keep_positive_ || F.determinant() > 0;
    if (!valid_[k]) return;  // E is +infinity: the line search rejects x
    const TetShape& shape = shapes_[k];
    if (with_energy) tet_energy_(t) = shape.volume * this->law_.energy(F);
    tet_force_.template middleCols<4>(4 * t) = (shape.volume * this->law_.first_piola(F)) * shape.gradients;
  }

  static double dot(const Eigen::Matrix3Xd& a, const Eigen::Matrix3Xd& b) { return a.cwiseProduct(b).sum(); }
  static double norm(const Eigen::Matrix3Xd& a) { return std::sqrt(dot(a, a)); }

  PdSettings o_;
  double weight_;
  double gradient_floor_ = 0;  ///< |grad E| at or below this is rounding: the frame stops there
  bool keep_positive_;
  std::unique_ptr<PdGlobalMatrix> global_;
  VertexTets around_;
  Colouring passes_;
  Eigen::Matrix3Xd tet_force_;  ///< column 4 t + a: V_t P(F_t) g_t,a, tet t's force on its node a
  Eigen::VectorXd tet_energy_;  ///< V_t W(F_t)
  std::vector<char> valid_;     ///< whether tet t's F was positive (laws undefined at det F <= 0)
  Eigen::Matrix3Xd y_, gradient_, trial_gradient_, trial_, direction_, q_;
  std::vector<Eigen::Matrix3Xd> s_pairs_, t_pairs_;  ///< L-BFGS pairs (ring of `history`)
  std::vector<PdContact> pd_contacts_;            ///< the contact set, kept from frame to frame
  std::vector<int> contact_nodes_;                ///< the contact set's nodes, in its order
  std::vector<Eigen::Vector3d> normals_;          ///< their outward normals, zero where held
  Eigen::MatrixXd schur_;                         ///< S = N A^-1 N^T of the contact set
  Eigen::LDLT<Eigen::MatrixXd> schur_factor_;
  Eigen::VectorXd schur_rhs_, schur_mu_;          ///< S's right-hand side; the multipliers mu
  std::vector<double> rho_, alpha_;
  int pairs_ = 0, newest_ = -1;
  int done_ = 0;
  int stages_ = 1;  ///< the frame's relaxations (more than one where the tools moved in stages)
  double reduction_ = 1;
  long halvings_ = 0, failures_ = 0;
};

}  // namespace

std::vector<ParameterSpec> pd_parameters() {
  using P = ParameterSpec;
  const PdSettings d;
  std::vector<ParameterSpec> specs = time_stepping_parameters(d.stepping.time_step);
  specs.push_back(P::choice("solve", {"local_global", "quasi_newton"}, mode_name(d.mode),
                            "local_global: Bouaziz et al. 2014's local projections and global solve (law arap_volume); "
                            "quasi_newton: L-BFGS with A^-1 as the initial inverse Hessian and a line search on the "
                            "incremental potential (Liu, Bouaziz and Kavan 2017), any law"));
  specs.push_back(material_law_parameter(d.law));
  specs.push_back(P::whole_number("iterations", d.iterations, 1, 100000,
                                  "global solves per frame, at most (each after its local step)"));
  specs.push_back(P::whole_number("history", d.history, 0, 100, "L-BFGS pairs kept (quasi_newton; 0: A^-1 alone)"));
  specs.push_back(P::number("tolerance", d.tolerance, 0, 1,
                            "a frame stops when |grad E| falls below this times its value at the frame's first iterate"));
  specs.push_back(P::choice("weight", {"shear", "longitudinal", "volume"}, weight_name(d.weight),
                            "A's weight per unit volume (quasi_newton): 2 mu, 2 mu + lambda or 2 mu + 3 lambda; "
                            "local_global takes its law's, 2 mu + 3 lambda"));
  return specs;
}

PdSettings pd_settings(const Parameters& p) {
  PdSettings s;
  s.stepping = time_stepping(p);
  s.mode = p.choice("solve") == "local_global" ? PdMode::LocalGlobal : PdMode::QuasiNewton;
  s.law = p.choice("material_law");
  s.iterations = p.integer("iterations");
  s.history = p.integer("history");
  s.tolerance = p.number("tolerance");
  const std::string& w = p.choice("weight");
  s.weight = w == "shear" ? PdWeight::Shear : w == "longitudinal" ? PdWeight::Longitudinal : PdWeight::Volume;
  return s;
}

std::unique_ptr<ElasticSolve> make_pd_solve(const ElasticBody& body, const PdSettings& settings) {
  if (settings.iterations < 1) throw std::invalid_argument("pd: iterations must be at least 1");
  if (settings.history < 0) throw std::invalid_argument("pd: history must be at least 0");
  if (!(settings.tolerance >= 0)) throw std::invalid_argument("pd: tolerance must be at least 0");
  if (settings.mode == PdMode::LocalGlobal && settings.law != "arap_volume")
    throw std::invalid_argument("pd: solve local_global minimises the arap_volume law only (its energy is PD's), not " +
                                settings.law + "; set material_law arap_volume, or solve quasi_newton");
  const PdWeight weight = settings.mode == PdMode::LocalGlobal ? PdWeight::Volume : settings.weight;
  return make_for_law<PdSolve>(settings.law, body, settings, weight_value(weight, lame_parameters(body.material())));
}

}  // namespace tb
