// What the real-time time steppers on a body's P1 tets share (Vertex Block Descent,
// vbd_solve.cc; XPBD with neo-Hookean tet constraints, xpbd_tet_solve.cc): the
// positions and velocities of the nodes, their lumped masses, which components a
// tool or the support holds, the external force of the frame, the colour-by-colour
// parallel sweep, and the reactions. Each is an ElasticSolve that advances one
// frame of `time_step` per solve(): the fine FEM (models/fine_fem.h) runs it as a
// dynamic model, tools and loads and reactions included.
//
// Rigid frictionless spheres (takes_spheres): each stepper keeps the body's surface
// nodes out of them in its own iteration (VBD: the linearised gap as a constraint of
// the vertex's 3x3 Newton step; XPBD: a collision projection after each sweep; PD:
// the linearised gaps as constraints of the global step, by multipliers) and marks
// the nodes its last constraint step acted on (touching_). The force a sphere gives
// is read as a tool's: at each marked node, the normal component of the
// implicit-Euler balance m (x - x_n - h v_n) / h^2 + f_int(x) - f (n . r) n, summed
// with the sign turned (the force on the sphere); at a steady state it is the
// contact multiplier of the static equilibrium (docs/equations.md). XPBD, whose
// fixed point is not the law's equilibrium, reports its own contact multipliers
// instead (own_contact_force: what a haptic loop on XPBD renders).
//
// Reactions (what the tissue exerts on a tool): at a held dof c, f_c - f_int,c(x)
// - m_c (x_c - x_n,c - h v_n,c) / h^2, the implicit-Euler balance of the node the
// tool moves (as the fem_dynamic reference measures it; docs/equations.md), from
// the law's own f_int over the tets that touch a held node, once per frame. XPBD
// gives its own f_int there, from its tet multipliers (add_held_internal_force).
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <atomic>
#include <limits>
#include <memory>
#include <stdexcept>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "colouring.h"
#include "elastic_solve.h"
#include "lame_parameters.h"
#include "material_law_visit.h"
#include "mesh_checks.h"
#include "tet_element.h"
#include "thread_team.h"

namespace tb {

/// The settings every stepper here reads.
struct TimeStepping {
  double time_step = 0.01;  ///< s per frame
  int threads = 1;          ///< members of the sweep's thread team (1: the caller alone)
};

/// The parameters time_step and threads, for the models built on these steppers.
std::vector<ParameterSpec> time_stepping_parameters(double default_time_step);
TimeStepping time_stepping(const Parameters& p);
/// The parameter material_law: any law of the table, `default_law` unless given.
ParameterSpec material_law_parameter(const std::string& default_law);

/// Stepper<Law>(body, law, args..., defined_when_inverted) for the law of the table
/// called `law` with the Lame parameters of the body's material: a stepper whose
/// inner loop evaluates the law inlined (material_law_visit.h).
template <template <class> class Stepper, class... Args>
std::unique_ptr<ElasticSolve> make_for_law(const std::string& law, const ElasticBody& body, const Args&... args) {
  const bool defined = find_material_law(law).defined_when_inverted;
  return visit_material_law(law, lame_parameters(body.material()), [&](const auto& l) -> std::unique_ptr<ElasticSolve> {
    return std::make_unique<Stepper<std::decay_t<decltype(l)>>>(body, l, args..., defined);
  });
}

/// F = sum_a x_a g_a^T of a tet whose nodes are at x0..x3 with shape gradients g
/// (column a: node a's), the outer products written out and always inlined (an Eigen
/// 3x4 by 4x3 product was an out-of-line call, a quarter of a VBD sweep; as a call,
/// F went through memory; docs/realtime_nonlinear.md).
template <class X0, class X1, class X2, class X3>
[[gnu::always_inline]] inline Eigen::Matrix3d tet_F(const Eigen::Matrix<double, 3, 4>& g, const X0& x0, const X1& x1,
                                                    const X2& x2, const X3& x3) {
  Eigen::Matrix3d F;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) F(i, j) = x0(i) * g(j, 0) + x1(i) * g(j, 1) + x2(i) * g(j, 2) + x3(i) * g(j, 3);
  return F;
}

template <class Law>
class TetTimeStepper : public ElasticSolve {
 public:
  TetTimeStepper(const ElasticBody& body, const Law& law, const TimeStepping& settings, std::string name)
      : body_(body), law_(law), s_(settings), name_(std::move(name)) {
    if (!(s_.time_step > 0)) throw std::invalid_argument(name_ + ": time_step must be positive");
    const TetMesh& m = body.mesh();
    const Eigen::Index n = m.V.rows();
    T_ = m.T;
    X_ = m.V.transpose();
    x_ = X_;
    x_n_ = X_;
    target_ = X_;
    v_ = Eigen::Matrix3Xd::Zero(3, n);
    v_n_held_ = v_;
    f_ext_ = Eigen::Matrix3Xd::Zero(3, n);
    free_ = Eigen::Matrix3Xd::Zero(3, n);
    mass_ = Eigen::VectorXd::Zero(n);
    shapes_.reserve(static_cast<size_t>(T_.rows()));
    for (Eigen::Index t = 0; t < T_.rows(); ++t) {
      shapes_.push_back(tet_shape(m.V.row(T_(t, 0)), m.V.row(T_(t, 1)), m.V.row(T_(t, 2)), m.V.row(T_(t, 3))));
      rest_volume_inverse_.push_back(1 / signed_volume(t, X_));
      // Row-sum lumping of P1's consistent mass: a quarter of the tet's to each node.
      for (int a = 0; a < 4; ++a) mass_(T_(t, a)) += body.material().density * shapes_.back().volume / 4;
    }
    std::vector<char> held(static_cast<size_t>(n), 0);
    for (Eigen::Index v = 0; v < n; ++v) {
      for (int i = 0; i < 3; ++i) {
        const bool is_free = body.free_index(static_cast<int>(3 * v + i)) >= 0;
        free_(i, v) = is_free ? 1 : 0;
        if (!is_free) held[static_cast<size_t>(v)] = 1;
      }
      if (held[static_cast<size_t>(v)]) held_nodes_.push_back(static_cast<int>(v));
    }
    for (Eigen::Index t = 0; t < T_.rows(); ++t)
      for (int a = 0; a < 4; ++a)
        if (held[static_cast<size_t>(T_(t, a))]) {
          held_tets_.push_back(static_cast<int>(t));
          break;
        }
    spring_ = body.spring_stiffness().size() == n ? body.spring_stiffness() : Eigen::VectorXd::Zero(n);
    reaction_force_ = Eigen::VectorXd::Zero(3 * n);
    tet_forces_.resize(held_tets_.size());
    if (s_.threads > 1) {
      team_ = std::make_unique<pbd::ThreadTeam>(s_.threads);
      member_checks_.resize(static_cast<size_t>(team_->size()));
    }
  }

  bool linear() const override { return false; }
  bool takes_spheres() const override { return true; }
  /// The body's springs: a stepper that folds them into its nodes' quadratic term
  /// (node_weight, node_target) says so (VBD, PD); XPBD does not.
  bool takes_springs() const override { return false; }
  /// Exact at the held dofs only (the reactions read no other; tet_time_stepping.h).
  const Eigen::VectorXd* internal_force() const override { return &reaction_force_; }

  /// One frame: the held components go to the values the caller set in u, the free
  /// ones move by advance(); u (3 #V) out.
  void solve(const Eigen::VectorXd& f_free, const std::vector<int>*, Eigen::VectorXd& u) final {
    const Eigen::Index n = X_.cols();
    if (u.size() != 3 * n) u = Eigen::VectorXd::Zero(3 * n);
    for_node_ranges([&](Eigen::Index begin, Eigen::Index end, int) {
      for (Eigen::Index v = begin; v < end; ++v) {
        for (int i = 0; i < 3; ++i) {
          const int free = body_.free_index(static_cast<int>(3 * v + i));
          f_ext_(i, v) = free >= 0 ? f_free(free) : 0;
        }
        x_n_.col(v) = x_.col(v);
        v_n_held_.col(v) = v_.col(v);
        target_.col(v) = X_.col(v) + u.segment<3>(3 * v);  // the held components' values
      }
    });
    if (contact_on()) prepare_contact();
    advance();
    for_node_ranges([&](Eigen::Index begin, Eigen::Index end, int) {
      for (Eigen::Index v = begin; v < end; ++v) {
        for (int i = 0; i < 3; ++i)
          if (free_(i, v) == 0) {
            x_(i, v) = target_(i, v);
            v_(i, v) = (x_(i, v) - x_n_(i, v)) / s_.time_step;
          }
        u.segment<3>(3 * v) = x_.col(v) - X_.col(v);
      }
    });
    measure_reactions();
    if (spheres_) measure_contact();
  }

  nlohmann::json report() const override {
    nlohmann::json r = own_report();
    r["time_step"] = s_.time_step;
    r["threads"] = s_.threads;
    r["static_residual"] = static_residual();
    return r;
  }

 protected:
  /// Moves x_ over one frame of time_step from x_n_ (positions) and v_ (velocities),
  /// under f_ext_, and updates v_ for the free components. The held components of
  /// target_ are where the tools put them at the frame's end (solve() sets x_ there
  /// afterwards; a stepper may move them there gradually).
  virtual void advance() = 0;
  virtual nlohmann::json own_report() const = 0;

  // --- The nodes' quadratic term: inertia and springs ---
  // Implicit Euler's inertia m / h^2 |x - y|^2 / 2 (y = x_n + h v_n + h^2 f / m, f
  // holding a spring's pull k d) and a spring's k |x - X|^2 / 2 (ElasticBody's
  // springs: a compliant grasp's pads) sum to w |x - y'|^2 / 2 plus a constant, with
  // w = m / h^2 + k and y' = (m / h^2 y + k X) / w: one isotropic quadratic per node.

  /// w = m / h^2 + k of node v, N/m.
  double node_weight(Eigen::Index v, double h2) const { return mass_(v) / h2 + spring_(v); }
  /// y' of node v for its inertial target y.
  Eigen::Vector3d node_target(Eigen::Index v, const Eigen::Vector3d& y, double h2) const {
    if (spring_(v) == 0) return y;
    return (mass_(v) / h2 * y + spring_(v) * X_.col(v)) / node_weight(v, h2);
  }

  // --- Spheres (header comment) ---

  bool contact_on() const { return spheres_ && spheres_->spheres() > 0; }
  /// The surface vertex of body node v, -1 for an interior node (set while contact_on()).
  int surface_vertex(Eigen::Index v) const { return surface_vertex_[static_cast<size_t>(v)]; }
  /// Marks whether the method's last constraint step on node v acted against sphere k.
  void mark_contact(Eigen::Index v, int k, bool on) {
    touching_[static_cast<size_t>(v) * static_cast<size_t>(spheres_->spheres()) + static_cast<size_t>(k)] = on;
  }
  /// Node v's position moved out of sphere k onto its surface along the normal at x
  /// (Mueller et al. 2007, sec. 3.5: C(x) = |x - c| - r >= 0 with stiffness 1), its
  /// held components kept; true if it was inside (and so moved), the move added to
  /// `moved` when given.
  bool project_out_of_sphere(Eigen::Index v, int k, Eigen::Vector3d* moved = nullptr) {
    Eigen::Vector3d n;
    const double g = spheres_->gap(x_.col(v), k, n);
    if (g >= 0) return false;
    const Eigen::Vector3d dx = -g * n.cwiseProduct(free_.col(v));
    x_.col(v) += dx;
    if (moved) *moved += dx;
    return true;
  }
  /// The force sphere k gives marked node v (on the body, N) where a stepper reads it
  /// from its own contact constraint (XPBD: its multipliers); false for the
  /// implicit-Euler balance of the law (header comment).
  virtual bool own_contact_force(Eigen::Index /*v*/, int /*k*/, Eigen::Vector3d& /*force*/) const { return false; }

  /// Adds f_int at the held dofs into f (3 #V; other dofs may receive anything, the
  /// reactions read none): the law's, sum over the tets that touch a held node of
  /// V P(F) g_a. A stepper whose fixed point is not the law's equilibrium gives its
  /// own (XPBD: its tet multipliers).
  virtual void add_held_internal_force(Eigen::VectorXd& f) { add_law_internal_force(held_tets_, f); }
  /// Adds the f_int of `tets` under the law at x_, V P(F) g_a at each node a of each,
  /// into f (3 #V): each tet's on the thread team, then summed into f in the list's
  /// order (the same sums whatever the team's size). The law's error for an inverted
  /// tet is thrown from the caller's thread.
  void add_law_internal_force(const std::vector<int>& tets, Eigen::VectorXd& f) {
    if (tet_forces_.size() < tets.size()) tet_forces_.resize(tets.size());
    std::atomic<bool> undefined{false};
    for_ranges(static_cast<Eigen::Index>(tets.size()), [&](Eigen::Index begin, Eigen::Index end, int) {
      try {
        for (Eigen::Index k = begin; k < end; ++k)
          tet_forces_[static_cast<size_t>(k)] = law_internal_force(tets[static_cast<size_t>(k)]);
      } catch (const std::domain_error&) {  // a task must not throw (thread_team.h)
        undefined = true;
      }
    });
    if (undefined)
      for (int t : tets) law_internal_force(t);  // throws the law's error for the first such tet
    for (size_t k = 0; k < tets.size(); ++k)
      for (int a = 0; a < 4; ++a) f.segment<3>(3 * T_(tets[k], a)) += tet_forces_[k].col(a);
  }
  /// Tet t's f_int under the law at x_: column a, V P(F) g_a at its node a.
  Eigen::Matrix<double, 3, 4> law_internal_force(int t) const {
    const Eigen::Matrix3d P = law_.first_piola(deformation_gradient(t, x_));
    const TetShape& shape = shapes_[static_cast<size_t>(t)];
    return shape.volume * (P * shape.gradients);
  }

  /// F of tet t at positions x (3 by #V) (tet_F).
  Eigen::Matrix3d deformation_gradient(Eigen::Index t, const Eigen::Matrix3Xd& x) const {
    return tet_F(shapes_[static_cast<size_t>(t)].gradients, x.col(T_(t, 0)), x.col(T_(t, 1)), x.col(T_(t, 2)),
                 x.col(T_(t, 3)));
  }

  /// Signed volume of tet t with its corners at x (mesh_checks.h).
  double signed_volume(Eigen::Index t, const Eigen::Matrix3Xd& x) const {
    return tet_volume(x.col(T_(t, 0)), x.col(T_(t, 1)), x.col(T_(t, 2)), x.col(T_(t, 3)));
  }

  /// Runs part(begin, end, member) over contiguous ranges that split [0, count)
  /// among the thread team's members (the whole range on the caller without a
  /// team): a frame's per-node and per-tet loops, which on one thread would be a
  /// tenth of a one-sweep VBD frame left serial (docs/realtime_nonlinear.md, "Two
  /// threads and the serial remainder"). part must not throw or allocate.
  template <class Part>
  void for_ranges(Eigen::Index count, Part&& part) {
    if (!team_) {
      part(Eigen::Index{0}, count, 0);
      return;
    }
    const Eigen::Index members = team_->size();
    auto task = [&](int member) {
      const Eigen::Index m = member;
      part(count * m / members, count * (m + 1) / members, member);
    };
    team_->run(task);
  }
  /// for_ranges over the nodes.
  template <class Part>
  void for_node_ranges(Part&& part) {
    for_ranges(X_.cols(), std::forward<Part>(part));
  }

  /// Whether every tet has det F > 0 at x (3 by #V); with `first_bad` the first that
  /// does not. det F = det(D_s) / det(D_m) (F = D_s D_m^-1, the edge matrices at x and
  /// at rest), the ratio of the signed volumes: a third of the cost of forming F. On the thread team each member
  /// checks a contiguous range of the tets (a VBD frame of one sweep spent a tenth of
  /// its time here on one thread); the first bad tet is the lowest-numbered one
  /// whatever the team's size.
  bool all_positive(const Eigen::Matrix3Xd& x, Eigen::Index* first_bad = nullptr, double* bad_J = nullptr) {
    const Eigen::Index tets = T_.rows();
    // J is written once, at the first bad tet: a member's slot of member_checks_
    // shares a cache line with the other's, and a store per tet would bounce it.
    const auto first_not_positive = [&](Eigen::Index begin, Eigen::Index end, double& J_bad) {
      for (Eigen::Index t = begin; t < end; ++t) {
        const double J = signed_volume(t, x) * rest_volume_inverse_[static_cast<size_t>(t)];
        if (!(J > 0)) {
          J_bad = J;
          return t;
        }
      }
      return end;
    };
    Eigen::Index bad = tets;
    double J = 0;
    if (!team_) {
      bad = first_not_positive(0, tets, J);
    } else {
      for_ranges(tets, [&](Eigen::Index begin, Eigen::Index end, int member) {
        MemberCheck& c = member_checks_[static_cast<size_t>(member)];
        c.bad = first_not_positive(begin, end, c.J);
        if (c.bad == end) c.bad = tets;
      });
      for (const MemberCheck& c : member_checks_)
        if (c.bad < bad) {
          bad = c.bad;
          J = c.J;
        }
    }
    if (bad == tets) return true;
    if (first_bad) *first_bad = bad;
    if (bad_J) *bad_J = J;
    return false;
  }

  /// Where the tools' move this frame would invert a tet beside a held node (a
  /// grasp lifted by more than the cells around it are tall), under a law undefined
  /// there (`law`): the held components advance from x_n_ towards target_ by the
  /// largest fraction of what is left that keeps every tet positive (halved until it
  /// does), relax() moving the free ones after each stage, until they reach target_.
  /// The free components start where x_ has them. Counts the stages in `stages`;
  /// throws std::runtime_error (one line, the stepper's name first) when a stage
  /// would be below 1/4096 of the move or past 64 stages.
  template <class Relax>
  void move_held_in_stages(Relax&& relax, const std::string& law, int& stages) {
    const Eigen::Index n = x_.cols();
    auto hold_at = [&](double fraction) {
      for (Eigen::Index v = 0; v < n; ++v)
        for (int i = 0; i < 3; ++i)
          if (free_(i, v) == 0) x_(i, v) = x_n_(i, v) + fraction * (target_(i, v) - x_n_(i, v));
    };
    double reached = 0;
    while (reached < 1) {
      double step = 1 - reached;
      hold_at(reached + step);
      Eigen::Index t = -1;
      double J = 0;
      while (!all_positive(x_, &t, &J)) {
        step /= 2;
        if (step < 1.0 / 4096 || stages >= 64) {
          std::ostringstream msg;
          msg << name_ << ": this frame's tool positions invert tet " << t << " (det F = " << J
              << ") beside a held node even in " << stages << " stages, where the " << law
              << " law is undefined; ramp the tool over more frames or use a law defined there (stable_neo_hookean)";
          throw std::runtime_error(msg.str());
        }
        hold_at(reached + step);
      }
      reached = step >= 1 - reached ? 1 : reached + step;
      relax();
      ++stages;
    }
  }

  /// Where each member of the thread team starts in each class of a sweep: member m
  /// runs items [shares[c][m], shares[c][m + 1]) of class c (members + 1 bounds a class).
  using Shares = std::vector<std::vector<size_t>>;

  /// Shares of about equal cost, cost(item) >= 0 (a VBD vertex costs its tets, from
  /// 4 to 60 on TetGen's meshes, so equal counts leave one member waiting at the
  /// barrier): member m's share ends at the first item where the class's running
  /// cost reaches m + 1 members' part.
  template <class Cost>
  Shares shares_by_cost(const Colouring& classes, Cost&& cost) const {
    const size_t members = team_ ? static_cast<size_t>(team_->size()) : 1;
    Shares shares;
    for (const std::vector<int>& c : classes) {
      std::vector<double> running(c.size() + 1, 0);
      for (size_t k = 0; k < c.size(); ++k) running[k + 1] = running[k] + cost(c[k]);
      std::vector<size_t> bounds(members + 1, c.size());
      bounds[0] = 0;
      for (size_t m = 1; m < members; ++m) {
        const double part = running.back() * static_cast<double>(m) / static_cast<double>(members);
        bounds[m] = static_cast<size_t>(std::lower_bound(running.begin(), running.end(), part) - running.begin());
      }
      shares.push_back(std::move(bounds));
    }
    return shares;
  }

  /// Runs item(k) for every k of every class, class by class; the items of a class
  /// are shared out over the thread team in contiguous ranges (equal counts, or
  /// `shares` from shares_by_cost), a barrier between classes. The result does not
  /// depend on the team's size or the shares (items of a class touch disjoint
  /// data). No heap allocation.
  template <class Item>
  void sweep(const Colouring& classes, Item& item, const Shares* shares = nullptr) {
    if (!team_) {
      for (const std::vector<int>& c : classes)
        for (int k : c) item(k);
      return;
    }
    const int members = team_->size();
    auto task = [&](int member) {
      for (size_t i = 0; i < classes.size(); ++i) {
        const std::vector<int>& c = classes[i];
        const size_t m = static_cast<size_t>(member);
        const size_t begin = shares ? (*shares)[i][m] : c.size() * m / static_cast<size_t>(members);
        const size_t end = shares ? (*shares)[i][m + 1] : c.size() * (m + 1) / static_cast<size_t>(members);
        for (size_t k = begin; k < end; ++k) item(c[k]);
        team_->barrier();
      }
    };
    team_->run(task);
  }

  const ElasticBody& body_;
  Law law_;
  TimeStepping s_;
  std::string name_;
  Tetrahedra T_;
  std::vector<TetShape> shapes_;
  Eigen::Matrix3Xd X_;       ///< rest positions, column per node
  Eigen::Matrix3Xd x_, v_;   ///< positions and velocities
  Eigen::Matrix3Xd x_n_;     ///< positions at the frame's start
  Eigen::Matrix3Xd target_;  ///< the held components' positions at the frame's end
  Eigen::Matrix3Xd f_ext_;   ///< the frame's external nodal force on the free components, N
  Eigen::Matrix3Xd free_;    ///< 1 where a component moves freely, 0 where a tool or the support holds it
  Eigen::VectorXd mass_;     ///< lumped nodal mass, kg
  Eigen::VectorXd spring_;   ///< the body's springs' stiffness per node, N/m (0 where none)

 private:
  /// The frame's contact bookkeeping: each node's surface vertex (once), no node touching.
  void prepare_contact() {
    const Eigen::Index n = X_.cols();
    if (surface_vertex_.empty()) {
      surface_vertex_.assign(static_cast<size_t>(n), -1);
      const std::vector<int>& nodes = spheres_->surface_nodes();
      for (size_t v = 0; v < nodes.size(); ++v)
        if (free_.col(nodes[v]).sum() > 0) surface_vertex_[static_cast<size_t>(nodes[v])] = static_cast<int>(v);
      around_contact_ = vertex_tets(T_, static_cast<int>(n));
    }
    touching_.assign(static_cast<size_t>(n) * static_cast<size_t>(spheres_->spheres()), 0);
  }

  /// Each marked node's contact force, the normal part of its implicit-Euler balance
  /// (header comment), into spheres_ (forces, contact vertices, penetration).
  void measure_contact() {
    contacts_.clear();
    const int S = spheres_->spheres();
    const double h = s_.time_step;
    for (size_t i = 0; i < touching_.size() && S > 0; ++i) {
      if (!touching_[i]) continue;
      const Eigen::Index v = static_cast<Eigen::Index>(i / static_cast<size_t>(S));
      const int k = static_cast<int>(i % static_cast<size_t>(S));
      Eigen::Vector3d r;
      if (!own_contact_force(v, k, r)) {
        r = mass_(v) * (x_.col(v) - x_n_.col(v) - h * v_n_held_.col(v)) / (h * h) - f_ext_.col(v) +
            spring_(v) * (x_.col(v) - X_.col(v));
        for (int j = around_contact_.offset[static_cast<size_t>(v)]; j < around_contact_.offset[static_cast<size_t>(v) + 1];
             ++j) {
          const auto [t, a] = around_contact_.around[static_cast<size_t>(j)];
          const TetShape& shape = shapes_[static_cast<size_t>(t)];
          r += shape.volume * (law_.first_piola(deformation_gradient(t, x_)) * shape.gradients.col(a));
        }
      }
      r = r.cwiseProduct(free_.col(v));  // a held component's share goes to its tool
      Eigen::Vector3d normal;
      spheres_->gap(x_.col(v), k, normal);
      contacts_.push_back({static_cast<int>(v), surface_vertex(v), k, normal.dot(r) * normal});
    }
    spheres_->record(contacts_, x_);
  }

  void measure_reactions() {
    reaction_force_.setZero();
    const double h = s_.time_step;
    add_held_internal_force(reaction_force_);
    // The held nodes' inertia: the tool accelerates the mass it holds.
    for (int v : held_nodes_)
      for (int i = 0; i < 3; ++i)
        if (free_(i, v) == 0)
          reaction_force_(3 * v + i) += mass_(v) * (x_(i, v) - x_n_(i, v) - h * v_n_held_(i, v)) / (h * h);
  }

  /// |f_ext + f_contact - f_int(x)| over the free components (f_contact: the spheres'
  /// forces of the last frame), relative to the larger of |f_ext| and |f_int|: 0 at a
  /// static equilibrium, what a settled state is measured by.
  double static_residual() const {
    Eigen::Matrix3Xd r = -f_ext_;
    for (Eigen::Index v = 0; v < r.cols(); ++v)
      if (spring_(v) != 0) r.col(v) += spring_(v) * (x_.col(v) - X_.col(v));  // the pads' k u (f_ext holds k d)
    try {
      for (Eigen::Index t = 0; t < T_.rows(); ++t) {
        const Eigen::Matrix3d P = law_.first_piola(deformation_gradient(t, x_));
        const TetShape& shape = shapes_[static_cast<size_t>(t)];
        for (int a = 0; a < 4; ++a) r.col(T_(t, a)) += shape.volume * (P * shape.gradients.col(a));
      }
    } catch (const std::domain_error&) {
      return std::numeric_limits<double>::infinity();  // an inverted tet under a law undefined there
    }
    const double scale = std::max({f_ext_.norm(), (r + f_ext_).cwiseProduct(free_).norm(), 1e-300});
    // A sphere's forces on the body are external forces too: at a static equilibrium
    // in contact f_int balances f_ext plus them.
    for (const NodeContact& c : contacts_) r.col(c.node) -= c.force;
    return r.cwiseProduct(free_).norm() / scale;
  }

  std::unique_ptr<pbd::ThreadTeam> team_;
  struct MemberCheck {
    Eigen::Index bad = 0;  ///< the member's first tet with det F <= 0, or the tet count
    double J = 0;          ///< its det F
  };
  std::vector<MemberCheck> member_checks_;  ///< all_positive's per-member results
  std::vector<double> rest_volume_inverse_;  ///< per tet, 1 / its signed rest volume (all_positive)
  std::vector<int> surface_vertex_;     ///< per node, its surface vertex or -1 (contact only)
  std::vector<char> touching_;          ///< per (node, sphere): the last constraint step acted on it
  VertexTets around_contact_;           ///< the tets around each node (the contact forces' f_int)
  std::vector<NodeContact> contacts_;
  std::vector<int> held_tets_;      ///< tets with a held node (the reactions' f_int)
  std::vector<int> held_nodes_;     ///< nodes with a held component
  std::vector<Eigen::Matrix<double, 3, 4>> tet_forces_;  ///< add_law_internal_force's per-tet forces
  Eigen::Matrix3Xd v_n_held_;       ///< velocities at the frame's start (the held nodes' inertia)
  Eigen::VectorXd reaction_force_;  ///< f_int + inertia at the held dofs (3 #V, zero elsewhere)
};

}  // namespace tb
