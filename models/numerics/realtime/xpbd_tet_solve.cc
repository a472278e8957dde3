#include "xpbd_tet_solve.h"

#include <array>
#include <cmath>
#include <stdexcept>

#include "lame_parameters.h"
#include "xpbd_neo_hookean.h"

namespace tb {
namespace {

/// One tet as the sweep reads it. Stored contiguously in sweep order (colour by
/// colour, a colour's tets in increasing index), so that a sweep streams through
/// them instead of reading each tet's shape, nodes and compliances from wherever the
/// colouring scattered the tet (as the VBD sweep's visits, vbd_solve.cc).
struct TetInSweep {
  Eigen::Matrix<double, 3, 4> g;  ///< shape gradients, column a: node a's, 1/m
  std::array<int, 4> nodes{};
  double compliance_d = 0, compliance_h = 0;  ///< 1 / (mu V), 1 / (lambda V)
};

class XpbdTetSolve : public TetTimeStepper<XpbdNeoHookean> {
  using Base = TetTimeStepper<XpbdNeoHookean>;

 public:
  XpbdTetSolve(const ElasticBody& body, const XpbdTetSettings& settings)
      : Base(body, XpbdNeoHookean(lame_parameters(body.material())), settings.stepping, "xpbd_neo"), o_(settings) {
    if (o_.substeps < 1 || o_.iterations < 1) throw std::invalid_argument("xpbd_neo: substeps and iterations must be at least 1");
    if (!(o_.damping >= 0)) throw std::invalid_argument("xpbd_neo: damping must be non-negative");
    const Eigen::Index n = x_.cols();
    inverse_mass_ = Eigen::Matrix3Xd::Zero(3, n);
    std::vector<char> moving(static_cast<size_t>(n), 0);
    for (Eigen::Index v = 0; v < n; ++v) {
      inverse_mass_.col(v) = free_.col(v) / mass_(v);
      moving[static_cast<size_t>(v)] = free_.col(v).sum() > 0;
    }
    // The colours as sweep positions, the tets' data in that order.
    std::vector<int> tet_at_position;
    for (const std::vector<int>& c : colour_tets(T_, static_cast<int>(n), moving)) {
      std::vector<int> positions;
      for (int t : c) {
        positions.push_back(static_cast<int>(tets_.size()));
        const TetShape& shape = shapes_[static_cast<size_t>(t)];
        TetInSweep tet;
        tet.g = shape.gradients;
        for (int a = 0; a < 4; ++a) tet.nodes[static_cast<size_t>(a)] = T_(t, a);
        tet.compliance_d = 1 / (law_.mu * shape.volume);
        tet.compliance_h = 1 / (law_.lambda * shape.volume);
        tets_.push_back(tet);
        tet_at_position.push_back(t);
      }
      colours_.push_back(std::move(positions));
    }
    // The tets that touch a held node: those with a free component keep their
    // projections' push on the held nodes (held_push_); those held entirely are never
    // projected, and give the law's force (add_held_internal_force).
    held_slot_.assign(tets_.size(), -1);
    for (size_t p = 0; p < tets_.size(); ++p) {
      int held_nodes = 0;
      bool free_component = false;
      for (int node : tets_[p].nodes) {
        held_nodes += free_.col(node).minCoeff() == 0;
        free_component = free_component || free_.col(node).maxCoeff() > 0;
      }
      if (held_nodes == 0) continue;
      if (free_component) {
        held_slot_[p] = static_cast<int>(slot_position_.size());
        slot_position_.push_back(static_cast<int>(p));
      } else {
        held_entirely_.push_back(tet_at_position[p]);
      }
    }
    held_push_.assign(slot_position_.size(), Eigen::Matrix<double, 3, 4>::Zero());
    lambda_d_ = Eigen::VectorXd::Zero(T_.rows());
    lambda_h_ = Eigen::VectorXd::Zero(T_.rows());
    x_sub_ = x_;
  }

 protected:
  void advance() override {
    const int n_sub = o_.substeps;
    const double h = s_.time_step / n_sub;
    const double keep = 1 / (1 + o_.damping * h);
    auto project = [this, h](int p) { project_tet(p, h); };
    if (contact_on())  // allocates only when it grows (the first frame with contact, or more spheres)
      contact_impulse_.resize(spheres_->surface_nodes().size() * static_cast<size_t>(spheres_->spheres()));
    for (int s = 1; s <= n_sub; ++s) {
      const double along = static_cast<double>(s) / n_sub;
      this->for_node_ranges([&](Eigen::Index begin, Eigen::Index end, int) {
        for (Eigen::Index v = begin; v < end; ++v) {
          x_sub_.col(v) = x_.col(v);
          for (int i = 0; i < 3; ++i) {
            if (free_(i, v) != 0) {
              v_(i, v) += h * f_ext_(i, v) / mass_(v);
              x_(i, v) += h * v_(i, v);
            } else {
              x_(i, v) = x_n_(i, v) + along * (target_(i, v) - x_n_(i, v));
            }
          }
        }
      });
      lambda_d_.setZero();
      lambda_h_.setZero();
      std::fill(held_push_.begin(), held_push_.end(), Eigen::Matrix<double, 3, 4>::Zero());
      if (contact_on()) std::fill(contact_impulse_.begin(), contact_impulse_.end(), Eigen::Vector3d::Zero());
      for (int k = 0; k < o_.iterations; ++k) {
        sweep(colours_, project);
        if (contact_on()) project_spheres();
      }
      if (contact_on()) mark_pushed_nodes();
      this->for_node_ranges([&](Eigen::Index begin, Eigen::Index end, int) {
        for (Eigen::Index v = begin; v < end; ++v)
          for (int i = 0; i < 3; ++i)
            if (free_(i, v) != 0) v_(i, v) = keep * (x_(i, v) - x_sub_(i, v)) / h;
      });
    }
  }

  nlohmann::json own_report() const override {
    return {{"solve", "XPBD, neo-Hookean tet constraints (Macklin and Mueller 2021)"},
            {"material_law", "xpbd_neo_hookean"},
            {"substeps", o_.substeps},
            {"iterations", o_.iterations},
            {"damping_per_s", o_.damping},
            {"sphere_force", "its contact multipliers: lambda / h_sub^2 over the last sub-step's projections"},
            {"reactions", "its tet multipliers at the held nodes: the sum of grad C dlambda / h_sub^2 over the last "
                          "sub-step's projections, and the held nodes' inertia over the frame"},
            {"tet_colours", colours_.size()}};
  }

  int last_iterations() const override { return o_.substeps * o_.iterations; }

 private:
  /// The collision constraints (Mueller et al. 2007, sec. 3.5; Macklin et al. 2016
  /// treat contacts as constraints of the same solve): after each sweep of the tets,
  /// every free surface node inside a sphere moves to its surface along the normal.
  /// Each projection is a multiplier step of the stiff constraint, d lambda = m |dx|
  /// along the normal (w = 1/m: the sphere does not move), accumulated over the
  /// sub-step's iterations as the tets' multipliers are: m dx summed per node.
  void project_spheres() {
    const int S = spheres_->spheres();
    for (int node : spheres_->surface_nodes()) {
      const int vertex = surface_vertex(node);
      if (vertex < 0) continue;
      for (int k = 0; k < S; ++k) {
        Eigen::Vector3d moved = Eigen::Vector3d::Zero();
        if (project_out_of_sphere(node, k, &moved)) contact_impulse_[impulse_index(vertex, k)] += mass_(node) * moved;
      }
    }
  }

  /// A node is in contact (marked) when a projection of the sub-step moved it.
  void mark_pushed_nodes() {
    const int S = spheres_->spheres();
    for (int node : spheres_->surface_nodes()) {
      const int vertex = surface_vertex(node);
      if (vertex < 0) continue;
      for (int k = 0; k < S; ++k) mark_contact(node, k, contact_impulse_[impulse_index(vertex, k)].squaredNorm() > 0);
    }
  }

  /// The last sub-step's contact multipliers as a force, lambda / h_sub^2 along the
  /// constraint's gradient (Macklin, Mueller and Chentanez 2016, eq. 17): the sum of
  /// the node's m dx over the sub-step's iterations, over h_sub^2.
  bool own_contact_force(Eigen::Index v, int k, Eigen::Vector3d& force) const override {
    const double h = s_.time_step / o_.substeps;
    if (surface_vertex(v) < 0) return false;  // not a surface node: never marked (mark_pushed_nodes)
    force = contact_impulse_[impulse_index(surface_vertex(v), k)] / (h * h);
    return true;
  }

  /// The held nodes' f_int from the tet multipliers of the last sub-step: a
  /// projection pushes node a by grad_a C dlambda / m, the force grad_a C dlambda /
  /// h_sub^2 (Macklin, Mueller and Chentanez 2016, eq. 17), which the tissue takes
  /// from a held node as it would a free one's move; f_int is its negative. The
  /// law's balance at XPBD's positions is not XPBD's equilibrium: near
  /// incompressibility lambda' (det F - alpha) there is far from what the projections
  /// apply (docs/realtime_nonlinear.md). A tet held entirely is never projected: the
  /// law's V P g_a, which its multipliers would reach.
  void add_held_internal_force(Eigen::VectorXd& f) override {
    const double h = s_.time_step / o_.substeps;
    for (size_t slot = 0; slot < slot_position_.size(); ++slot) {
      const TetInSweep& tet = tets_[static_cast<size_t>(slot_position_[slot])];
      for (int a = 0; a < 4; ++a) f.segment<3>(3 * tet.nodes[static_cast<size_t>(a)]) -= held_push_[slot].col(a) / (h * h);
    }
    add_law_internal_force(held_entirely_, f);
  }

  /// Where contact_impulse_ holds surface vertex `vertex`'s sum for sphere k.
  size_t impulse_index(int vertex, int k) const {
    return static_cast<size_t>(vertex) * static_cast<size_t>(spheres_->spheres()) + static_cast<size_t>(k);
  }

  /// Tet t's two constraints projected together: the XPBD update of the pair, one
  /// 2x2 system (S + diag(alpha~)) dlambda = -(C + alpha~ lambda), S_ij = sum_a
  /// w_a grad_a C_i . grad_a C_j. Projected one after the other instead, each sees
  /// the other's large rest-state correction (C_D = sqrt 3 at rest, balanced by C_H),
  /// and with lambda reset each sub-step the fixed point left the cube of
  /// tests/models/realtime 30 % from the law's equilibrium; together, their rest
  /// corrections cancel exactly (docs/realtime_nonlinear.md). p: the tet's sweep position.
  void project_tet(int p, double h) {
    const TetInSweep& tet = tets_[static_cast<size_t>(p)];
    const double h2 = h * h;
    const Eigen::Matrix3d F = tet_F(tet.g, x_.col(tet.nodes[0]), x_.col(tet.nodes[1]), x_.col(tet.nodes[2]), x_.col(tet.nodes[3]));
    const double norm = F.norm();
    if (!(norm > 1e-12)) return;
    const Eigen::Matrix<double, 3, 4> grad_d = (F / norm) * tet.g;
    const Eigen::Matrix<double, 3, 4> grad_h = cofactor(F) * tet.g;
    const double alpha_d = tet.compliance_d / h2, alpha_h = tet.compliance_h / h2;
    Eigen::Matrix2d A = Eigen::Matrix2d::Zero();
    for (int a = 0; a < 4; ++a) {
      const Eigen::Vector3d w = inverse_mass_.col(tet.nodes[static_cast<size_t>(a)]);
      A(0, 0) += w.dot(grad_d.col(a).cwiseAbs2());
      A(1, 1) += w.dot(grad_h.col(a).cwiseAbs2());
      A(0, 1) += w.dot(grad_d.col(a).cwiseProduct(grad_h.col(a)));
    }
    if (!(A(0, 0) > 0 || A(1, 1) > 0)) return;  // every node held
    A(1, 0) = A(0, 1);
    A(0, 0) += alpha_d;
    A(1, 1) += alpha_h;
    const Eigen::Vector2d rhs(-(norm + alpha_d * lambda_d_(p)), -(F.determinant() - law_.alpha + alpha_h * lambda_h_(p)));
    const Eigen::Vector2d d_lambda = A.inverse() * rhs;  // A is symmetric positive definite (alpha~ > 0)
    lambda_d_(p) += d_lambda(0);
    lambda_h_(p) += d_lambda(1);
    if (const int slot = held_slot_[static_cast<size_t>(p)]; slot >= 0)  // only this tet's projection writes it
      held_push_[static_cast<size_t>(slot)] += d_lambda(0) * grad_d + d_lambda(1) * grad_h;
    for (int a = 0; a < 4; ++a) {
      const int node = tet.nodes[static_cast<size_t>(a)];
      // A held node is not written: the colouring keeps a colour's tets apart only
      // through the nodes that move, so two threads may share a held one.
      if ((inverse_mass_.col(node).array() == 0).all()) continue;
      x_.col(node) += inverse_mass_.col(node).cwiseProduct(d_lambda(0) * grad_d.col(a) + d_lambda(1) * grad_h.col(a));
    }
  }

  XpbdTetSettings o_;
  std::vector<TetInSweep> tets_;   ///< the tets in sweep order
  Colouring colours_;              ///< the tet colours, as sweep positions
  Eigen::Matrix3Xd inverse_mass_;  ///< per component: 1 / m where free, 0 where held
  Eigen::VectorXd lambda_d_, lambda_h_;  ///< the multipliers, by sweep position
  Eigen::Matrix3Xd x_sub_;  ///< positions at the sub-step's start
  /// Per surface vertex and sphere (vertex * #spheres + k), the sub-step's sum of m dx
  /// of its projections out of the sphere, kg m (sized in each frame with contact).
  std::vector<Eigen::Vector3d> contact_impulse_;
  std::vector<int> held_slot_;      ///< per sweep position, its held_push_ slot or -1
  std::vector<int> slot_position_;  ///< per slot, the tet's sweep position
  /// Per slot, the sub-step's sum of grad_a C dlambda over the tet's projections,
  /// column a for node a (read at the held nodes only).
  std::vector<Eigen::Matrix<double, 3, 4>> held_push_;
  std::vector<int> held_entirely_;  ///< the tets whose every component is held (mesh indices)
};

}  // namespace

std::vector<ParameterSpec> xpbd_tet_parameters() {
  using P = ParameterSpec;
  const XpbdTetSettings d;
  std::vector<ParameterSpec> specs = time_stepping_parameters(d.stepping.time_step);
  specs.push_back(P::whole_number("substeps", d.substeps, 1, 100000, "sub-steps per frame (Macklin et al. 2019)"));
  specs.push_back(P::whole_number("iterations", d.iterations, 1, 100000, "sweeps over every tet colour per sub-step"));
  specs.push_back(P::number("damping", d.damping, 0, 1e6,
                            "c, 1/s: v <- v / (1 + c h) each sub-step (mass-proportional; the steady state does not "
                            "depend on it)"));
  return specs;
}

XpbdTetSettings xpbd_tet_settings(const Parameters& p) {
  XpbdTetSettings s;
  s.stepping = time_stepping(p);
  s.substeps = p.integer("substeps");
  s.iterations = p.integer("iterations");
  s.damping = p.number("damping");
  return s;
}

std::unique_ptr<ElasticSolve> make_xpbd_tet_solve(const ElasticBody& body, const XpbdTetSettings& settings) {
  return std::make_unique<XpbdTetSolve>(body, settings);
}

}  // namespace tb
