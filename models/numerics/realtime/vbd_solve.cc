#include "vbd_solve.h"

#include <array>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include "cholesky3.h"
#include "node_terms.h"
#include "vbd_visit_blocks.h"

namespace tb {
namespace {

const char* start_name(VbdStart s) {
  switch (s) {
    case VbdStart::Previous: return "previous";
    case VbdStart::Inertial: return "inertial";
    case VbdStart::Adaptive: return "adaptive";
  }
  return "";
}

const char* kernels_name(VbdKernels k) {
  switch (k) {
    case VbdKernels::Auto: return "auto";
    case VbdKernels::Avx2: return "avx2";
    case VbdKernels::Sse2: return "sse2";
    case VbdKernels::Scalar: return "scalar";
  }
  return "";
}

/// One tet around a vertex as the vertex's update reads it. The visits are stored
/// contiguously in sweep order (colour by colour, a colour's vertices in increasing
/// index, each vertex's tets in increasing index), so that a sweep streams through
/// them instead of gathering each tet's shape and nodes from wherever TetGen's
/// numbering put them (docs/realtime_nonlinear.md, "What a frame costs").
struct TetVisit {
  Eigen::Matrix<double, 3, 4> g;  ///< column 0: the vertex's own shape gradient; 1..3: the other nodes', 1/m
  double volume = 0;              ///< rest volume, m^3
  std::array<int, 3> other{};     ///< the tet's other nodes, in the tet's order
};

template <class Law>
class VbdSolve : public TetTimeStepper<Law> {
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
  VbdSolve(const ElasticBody& body, const Law& law, const VbdSettings& settings, bool defined_when_inverted)
      : Base(body, law, settings.stepping, "vbd"),
        o_(settings),
        keep_positive_(!defined_when_inverted),
        // The lanes' kernel checks det F > 0 as a law undefined there needs (vbd_visit_blocks.h).
        kernels_(choose_vbd_kernels(o_.kernels, HasLaneNodeTerms<Law>::value && keep_positive_, o_.law,
                                    __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"))),
        batched_(kernels_ != VbdKernels::Scalar) {
    if (o_.iterations < 1) throw std::invalid_argument("vbd: iterations must be at least 1");
    if (!(o_.chebyshev_rho >= 0 && o_.chebyshev_rho < 1))
      throw std::invalid_argument("vbd: chebyshev_rho must lie in [0, 1)");
    if (!(o_.damping >= 0 && std::isfinite(o_.damping)))
      throw std::invalid_argument("vbd: damping must be finite and at least 0");
    const Eigen::Index n = x_.cols();
    std::vector<int> moving;
    for (Eigen::Index v = 0; v < n; ++v)
      if (free_.col(v).sum() > 0) moving.push_back(static_cast<int>(v));
    lay_out_visits(colour_vertices(T_, static_cast<int>(n), moving));
    y_ = x_;
    a_last_ = Eigen::Matrix3Xd::Zero(3, n);
    accelerated_ = prev1_ = prev2_ = x_;
  }

 protected:
  bool takes_springs() const override { return true; }

  void advance() override {
    const double h = s_.time_step, h2 = h * h;
    const Eigen::Index n = x_.cols();
    // The inertial target and the start (held components at the frame's end).
    this->for_node_ranges([&](Eigen::Index begin, Eigen::Index end, int) {
      for (Eigen::Index v = begin; v < end; ++v) start_at(v, h);
    });
    bool positive = !keep_positive_ || this->all_positive(x_);
    if (!positive) {
      // The start inverted a tet: begin from x_n, the held nodes moved in stages.
      for (Eigen::Index v = 0; v < n; ++v)
        for (int i = 0; i < 3; ++i)
          if (free_(i, v) != 0) x_(i, v) = x_n_(i, v);
      positive = this->all_positive(x_);
    }
    stages_ = 0;
    if (positive) {
      sweeps(h2);
      stages_ = 1;
    } else {
      this->move_held_in_stages([&] { sweeps(h2); }, o_.law, stages_);  // a frame costs its sweeps once per stage
    }
    this->for_node_ranges([&](Eigen::Index begin, Eigen::Index end, int) {
      for (Eigen::Index v = begin; v < end; ++v)
        for (int i = 0; i < 3; ++i)
          if (free_(i, v) != 0) {
            const double v_new = (x_(i, v) - x_n_(i, v)) / h;
            a_last_(i, v) = (v_new - v_(i, v)) / h;
            v_(i, v) = v_new;
          }
    });
  }

  nlohmann::json own_report() const override {
    return {{"solve", "vertex block descent (Chen et al. 2024)"},
            {"material_law", o_.law},
            {"iterations", o_.iterations},
            {"chebyshev_rho", o_.chebyshev_rho},
            {"damping", o_.damping},
            {"start", start_name(o_.start)},
            {"kernels", kernels_name(kernels_)},
            {"vertex_colours", colours_.size()},
            {"chebyshev_restarts", restarts_},
            {"stages_last_frame", stages_}};
  }

  int last_iterations() const override { return o_.iterations * stages_; }

 private:
  /// Node v's inertial target y and the frame's first iterate x (held components at
  /// the frame's end), from the start asked for.
  void start_at(Eigen::Index v, double h) {
    const double h2 = h * h;
    // The target of the node's inertia and springs (node_target); a_ext the
    // acceleration towards it, f / m where the node has no spring.
    y_.col(v) = this->node_target(v, x_n_.col(v) + h * v_.col(v) + h2 * this->f_ext_.col(v) / mass_(v), h2);
    const Eigen::Vector3d a_ext = (y_.col(v) - x_n_.col(v) - h * v_.col(v)) / h2;
    Eigen::Vector3d start = x_n_.col(v);
    if (o_.start == VbdStart::Inertial) {
      start = y_.col(v);
    } else if (o_.start == VbdStart::Adaptive) {
      // Their adaptive initialisation: the last acceleration's component along the external one,
      // clamped to [0, |a_ext|]; none where no external force acts.
      Eigen::Vector3d a = Eigen::Vector3d::Zero();
      const double norm = a_ext.norm();
      if (norm > 0) a = std::clamp(a_last_.col(v).dot(a_ext / norm), 0.0, norm) * (a_ext / norm);
      start = x_n_.col(v) + h * v_.col(v) + h2 * a;
    }
    for (int i = 0; i < 3; ++i) {
      x_(i, v) = free_(i, v) != 0 ? start(i) : this->target_(i, v);
      y_(i, v) = free_(i, v) != 0 ? y_(i, v) : this->target_(i, v);
    }
  }

  /// `iterations` sweeps over every colour, with Chebyshev acceleration if asked.
  void sweeps(double h2) {
    if (o_.chebyshev_rho > 0) prev1_ = prev2_ = x_;
    double omega = 1;
    auto scalar = [this, h2](int p) { update_vertex(p, h2); };
    auto avx2 = [this, h2](int p) { update_vertex_avx2(p, h2); };
    auto sse2 = [this, h2](int p) { update_vertex_sse2(p, h2); };
    for (int k = 1; k <= o_.iterations; ++k) {
      if (kernels_ == VbdKernels::Avx2)
        this->sweep(colours_, avx2, &shares_);
      else if (kernels_ == VbdKernels::Sse2)
        this->sweep(colours_, sse2, &shares_);
      else
        this->sweep(colours_, scalar, &shares_);
      if (o_.chebyshev_rho > 0) accelerate(k, omega);
    }
  }

  /// Tets around a vertex whose determinant update update_vertex keeps on the stack
  /// (TetGen's meshes have about 20-30; a vertex in more takes the slower path), and
  /// the smallest det F a step may leave.
  static constexpr int kCachedTets = 96;
  static constexpr int kCachedBlocks = kCachedTets / kVisitLanes;
  static constexpr double kMinDet = 1e-9;

  /// The sweep's data: the vertices in sweep order (order_), their tets' visits
  /// (vertex order_[p]'s from visit_begin_[p] to visit_begin_[p + 1]: one by one in
  /// visits_ for the scalar kernels, four to a block from block_begin_[p] in blocks_
  /// for the batched ones), the colour classes as sweep positions, and the thread
  /// team's shares of each class by tet count.
  void lay_out_visits(const Colouring& by_vertex) {
    const VertexTets around = vertex_tets(T_, static_cast<int>(x_.cols()));
    visit_begin_.push_back(0);
    for (const std::vector<int>& c : by_vertex) {
      std::vector<int> positions;
      for (int v : c) {
        positions.push_back(static_cast<int>(order_.size()));
        order_.push_back(v);
        for (int k = around.offset[static_cast<size_t>(v)]; k < around.offset[static_cast<size_t>(v) + 1]; ++k) {
          const auto [t, a] = around.around[static_cast<size_t>(k)];
          const TetShape& shape = shapes_[static_cast<size_t>(t)];
          TetVisit visit;
          visit.volume = shape.volume;
          visit.g.col(0) = shape.gradients.col(a);
          for (int b = 0, j = 0; b < 4; ++b)
            if (b != a) {
              visit.g.col(j + 1) = shape.gradients.col(b);
              visit.other[static_cast<size_t>(j++)] = T_(t, b);
            }
          visits_.push_back(visit);
        }
        visit_begin_.push_back(static_cast<int>(visits_.size()));
        if (batched_) {  // this vertex's visits into blocks of four; only the blocks are kept
          const int first = visit_begin_[visit_begin_.size() - 2];
          block_begin_.push_back(static_cast<int>(blocks_.size()));
          for (int k = first; k < visit_begin_.back(); k += kVisitLanes) {
            VisitBlock block;
            for (int l = 0; l < kVisitLanes; ++l) {
              const bool real = k + l < visit_begin_.back();
              const TetVisit* visit = real ? &visits_[static_cast<size_t>(k + l)] : nullptr;
              for (int node = 1; node < 4; ++node)
                for (int i = 0; i < 3; ++i) block.g[node][i][l] = real ? visit->g(i, node) : 0;
              // The vertex's own gradient as minus the others' sum (vbd_visit_blocks.h):
              // TetShape's holds that for a tet's node 0 only, to round-off for the others.
              for (int i = 0; i < 3; ++i) block.g[0][i][l] = -(block.g[1][i][l] + block.g[2][i][l] + block.g[3][i][l]);
              block.volume[l] = real ? visit->volume : 0;
              block.empty[l] = real ? 0 : 1;
              for (int j = 0; j < 3; ++j) block.other[j][l] = real ? visit->other[static_cast<size_t>(j)] : v;
            }
            blocks_.push_back(block);
          }
        }
      }
      colours_.push_back(std::move(positions));
    }
    if (batched_) {
      block_begin_.push_back(static_cast<int>(blocks_.size()));
      visits_ = {};
    }
    shares_ = this->shares_by_cost(colours_, [this](int p) {
      return static_cast<double>(visit_begin_[static_cast<size_t>(p) + 1] - visit_begin_[static_cast<size_t>(p)]);
    });
  }

  /// F of a visit's tet with its vertex at xv (tet_F, the vertex's term first).
  [[gnu::always_inline]] Eigen::Matrix3d deformation_gradient(const TetVisit& visit, const Eigen::Vector3d& xv) const {
    return tet_F(visit.g, xv, x_.col(visit.other[0]), x_.col(visit.other[1]), x_.col(visit.other[2]));
  }

  /// One Newton step on the block of vertex order_[p] of the incremental potential,
  /// its tets summed one at a time.
  void update_vertex(int p, double h2) {
    const int v = order_[static_cast<size_t>(p)];
    const Eigen::Vector3d from = x_.col(v);
    Eigen::Vector3d gradient;
    Eigen::Matrix3d H;
    inertia(v, h2, gradient, H);
    // Per tet around v, det F and cof(F) g: moving v by dx changes F by the rank-one
    // dx g^T, so det F becomes det F + dx . cof(F) g exactly (the matrix determinant
    // lemma), and the positivity check after the step needs no new F.
    std::array<Eigen::Vector4d, kCachedTets> det_change;
    const TetVisit* visits = visits_.data() + visit_begin_[static_cast<size_t>(p)];
    const int count = visit_begin_[static_cast<size_t>(p) + 1] - visit_begin_[static_cast<size_t>(p)];
    const bool cached = keep_positive_ && count <= kCachedTets;
    for (int k = 0; k < count; ++k) {
      const TetVisit& visit = visits[k];
      const NodeTerms terms = node_terms(this->law_, deformation_gradient(visit, from), visit.g.col(0));
      gradient += visit.volume * terms.force;
      H += visit.volume * terms.stiffness;
      if (cached) det_change[static_cast<size_t>(k)] << terms.cof_g, terms.J;
    }
    damp(v, from, h2, gradient, H);
    step(v, from, gradient, H, [&](const Eigen::Vector3d& dx) {
      return cached ? positive_after(det_change, count, dx) : positive_around(visits, count, from + dx);
    });
  }

  /// The same with the tets four at a time in lanes L (vbd_visit_blocks.h), inlined
  /// into one function per instruction set.
  template <class L>
  [[gnu::always_inline]] void update_vertex_batched(int p, double h2) {
    if constexpr (!HasLaneNodeTerms<Law>::value) {
      update_vertex(p, h2);  // not reached: batched_ is false for such a law
    } else {
      const int v = order_[static_cast<size_t>(p)];
      const Eigen::Vector3d from = x_.col(v);
      Eigen::Vector3d gradient;
      Eigen::Matrix3d H;
      inertia(v, h2, gradient, H);
      const VisitBlock* blocks = blocks_.data() + block_begin_[static_cast<size_t>(p)];
      const int count = block_begin_[static_cast<size_t>(p) + 1] - block_begin_[static_cast<size_t>(p)];
      const bool cached = count <= kCachedBlocks;
      std::array<BlockDeterminants<L>, kCachedBlocks> dets;
      const int bad = add_block_terms<L>(this->law_, blocks, count, x_.data(), from, gradient, H,
                                         cached ? dets.data() : nullptr);
      if (bad >= 0) throw_at_lane(v, blocks[bad / kVisitLanes], bad % kVisitLanes, from);
      damp(v, from, h2, gradient, H);
      // Inlined (as the lanes' kernels are) into the per-instruction-set caller.
      step(v, from, gradient, H, [&](const Eigen::Vector3d& dx) __attribute__((always_inline)) {
        return cached ? blocks_stay_above<L>(dets.data(), count, dx, kMinDet)
                      : blocks_above_at<L>(blocks, count, x_.data(), from + dx, kMinDet);
      });
    }
  }
  __attribute__((target("avx2,fma"))) void update_vertex_avx2(int p, double h2) {
    update_vertex_batched<pbd::lanes::Vector<double, 4>>(p, h2);
  }
  void update_vertex_sse2(int p, double h2) { update_vertex_batched<pbd::batches::SseLanes>(p, h2); }

  /// The inertial term of vertex v's Newton system, its springs included
  /// (node_weight): w (x - y') and w I.
  [[gnu::always_inline]] void inertia(int v, double h2, Eigen::Vector3d& gradient, Eigen::Matrix3d& H) const {
    const double m = this->node_weight(v, h2);
    gradient = m * (x_.col(v) - y_.col(v));
    H = m * Eigen::Matrix3d::Identity();
  }

  /// Chen et al. 2024's damping ("Damping") in vertex v's Newton system, whose H holds
  /// the inertial m / h^2 I and the tets' elastic block H_e: with d = k_d / h,
  /// gradient += d H_e (x - x_n) and H += d H_e. Where H_e is indefinite (neo_hookean
  /// dilated beyond J = e^(1 + mu / lambda)) step()'s Cholesky test decides as without.
  [[gnu::always_inline]] void damp(int v, const Eigen::Vector3d& from, double h2, Eigen::Vector3d& gradient,
                                   Eigen::Matrix3d& H) const {
    if (o_.damping == 0) return;
    // Plain loops: GCC left the Eigen expression out of line in the AVX2 caller
    // (perf: 8 % of a frame in it), which made a damped frame 30-45 % dearer.
    const double d = o_.damping / s_.time_step, m = this->node_weight(v, h2);
    double elastic[3][3], moved[3];
    for (int i = 0; i < 3; ++i) {
      moved[i] = from(i) - x_n_(i, v);
      for (int j = 0; j < 3; ++j) elastic[i][j] = H(i, j) - (i == j ? m : 0);
    }
    for (int i = 0; i < 3; ++i) {
      gradient(i) += d * (elastic[i][0] * moved[0] + elastic[i][1] * moved[1] + elastic[i][2] * moved[2]);
      for (int j = 0; j < 3; ++j) H(i, j) += d * elastic[i][j];
    }
  }

  /// The law's own error for the tet in lane l of a block, whose det F the batched
  /// kernel found not positive (its scalar node terms throw it; should F recomputed
  /// here round to a positive det F, a one-line error of the same kind).
  [[noreturn]] void throw_at_lane(int v, const VisitBlock& b, int l, const Eigen::Vector3d& from) const {
    Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
    for (int j = 0; j < 3; ++j)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c) F(r, c) += (x_(r, b.other[j][l]) - from(r)) * b.g[j + 1][c][l];
    node_terms(this->law_, F, Eigen::Vector3d(b.g[0][0][l], b.g[0][1][l], b.g[0][2][l]));
    std::ostringstream msg;
    msg << "vbd: a tet at node " << v << " reached det F <= 0 in the batched kernels (" << F.determinant()
        << " recomputed), where the " << o_.law << " law is undefined";
    throw std::runtime_error(msg.str());
  }

  /// The end of a vertex's update from its Newton system: held components removed,
  /// the 3x3 solve, the spheres' constraint, and halvings of the step until
  /// `positive(dx)` (every tet around the vertex keeps det F > kMinDet) where the law
  /// needs it.
  template <class Positive>
  [[gnu::always_inline]] void step(int v, const Eigen::Vector3d& from, Eigen::Vector3d& gradient, Eigen::Matrix3d& H,
                                   Positive&& positive) {
    for (int i = 0; i < 3; ++i)
      if (free_(i, v) == 0) {  // a held component does not move
        H.row(i).setZero();
        H.col(i).setZero();
        H(i, i) = 1;
        gradient(i) = 0;
      }
    const Cholesky3 cholesky(H);
    if (!cholesky.ok()) return;  // not a descent direction: the vertex waits this sweep
    Eigen::Vector3d dx = -cholesky.solve(gradient);
    if (!dx.allFinite()) return;
    if (this->contact_on() && this->surface_vertex(v) >= 0) constrain_to_spheres(v, cholesky, dx);
    for (int halving = 0; halving < 10; ++halving) {
      if (!keep_positive_ || positive(dx)) {
        x_.col(v) = from + dx;
        return;
      }
      dx /= 2;
    }
  }

  /// The vertex's step with the linearised gap of each sphere it would enter as a
  /// constraint of its 3x3 Newton step (instead of Chen et al. 2024's penalty): the
  /// minimiser of the local quadratic model subject to g + n . dx >= 0 is
  ///   dx = dx_free + mu H^-1 n,  mu = -(g + n . dx_free) / (n . H^-1 n) > 0,
  /// so the step ends on the tangent plane at the point of the sphere nearest the
  /// vertex (n the normal there, held components left out). A fixed point of the
  /// sweeps (dx = 0 everywhere) then has g = 0 and grad = mu n at each contact: the
  /// KKT conditions of the step's minimiser with the spheres.
  void constrain_to_spheres(int v, const Cholesky3& cholesky, Eigen::Vector3d& dx) {
    for (int k = 0; k < this->spheres_->spheres(); ++k) {
      Eigen::Vector3d n;
      const double g = this->spheres_->gap(x_.col(v), k, n);
      n = n.cwiseProduct(free_.col(v));
      const double predicted = g + n.dot(dx);
      const Eigen::Vector3d Hn = cholesky.solve(n);
      const double nHn = n.dot(Hn);
      const bool on = predicted < 0 && nHn > 0;
      this->mark_contact(v, k, on);
      if (on) dx += (-predicted / nHn) * Hn;
    }
  }

  /// Whether every tet around a vertex keeps det F above kMinDet after the vertex
  /// moves by dx, from the (cof(F) g, det F) of each (update_vertex). The margin
  /// keeps a determinant that the lemma puts just above zero from being at or below
  /// it when F is recomputed, where the law would be evaluated undefined.
  static bool positive_after(const std::array<Eigen::Vector4d, kCachedTets>& det_change, int count,
                             const Eigen::Vector3d& dx) {
    for (int k = 0; k < count; ++k) {
      const Eigen::Vector4d& c = det_change[static_cast<size_t>(k)];
      if (!(c(3) + dx.dot(c.head<3>()) > kMinDet)) return false;
    }
    return true;
  }

  /// The same, recomputing F of the vertex's `count` visits with it at `at`, for a
  /// vertex in more tets than kCachedTets.
  bool positive_around(const TetVisit* visits, int count, const Eigen::Vector3d& at) const {
    for (int k = 0; k < count; ++k)
      if (!(deformation_gradient(visits[k], at).determinant() > kMinDet)) return false;
    return true;
  }

  /// Chebyshev semi-iterative acceleration (Wang 2015, as Chen et al. 2024 use it):
  /// x^k = omega_k (x_sweep^k - x^(k-2)) + x^(k-2), omega_1 = 1, omega_2 = 2 / (2 - rho^2),
  /// omega_k = 4 / (4 - rho^2 omega_(k-1)). Restarted (omega = 1) where it would
  /// invert a tet under a law undefined there.
  void accelerate(int k, double& omega) {
    const double rho2 = o_.chebyshev_rho * o_.chebyshev_rho;
    omega = k == 1 ? 1 : k == 2 ? 2 / (2 - rho2) : 4 / (4 - rho2 * omega);
    if (k >= 2) {
      accelerated_ = prev2_ + omega * (x_ - prev2_);
      if (!keep_positive_ || this->all_positive(accelerated_)) {
        x_.swap(accelerated_);
      } else {
        omega = 1;
        ++restarts_;
      }
    }
    prev2_.swap(prev1_);
    prev1_ = x_;
  }

  VbdSettings o_;
  bool keep_positive_;
  VbdKernels kernels_;  ///< the kernels it runs (never Auto)
  bool batched_;        ///< the tets four at a time (vbd_visit_blocks.h)
  std::vector<int> order_;        ///< the moving vertices in sweep order
  std::vector<TetVisit> visits_;  ///< their tets, in sweep order (lay_out_visits)
  std::vector<int> visit_begin_;  ///< per sweep position p, where vertex order_[p]'s visits begin (#order_ + 1)
  std::vector<VisitBlock> blocks_;  ///< the visits four to a block (batched_; visits_ is then empty)
  std::vector<int> block_begin_;    ///< per sweep position p, where its blocks begin (#order_ + 1; batched_)
  Colouring colours_;             ///< the vertex colours, as sweep positions
  typename Base::Shares shares_;  ///< each thread's part of each colour, by tet count
  Eigen::Matrix3Xd y_;                       ///< the inertial target
  Eigen::Matrix3Xd a_last_;                  ///< the last step's acceleration (the adaptive start)
  Eigen::Matrix3Xd accelerated_, prev1_, prev2_;
  long restarts_ = 0;
  int stages_ = 0;  ///< sweeps of `iterations` in the last frame (more than one where the tools moved in stages)
};

}  // namespace

std::vector<ParameterSpec> vbd_parameters() {
  using P = ParameterSpec;
  const VbdSettings d;
  std::vector<ParameterSpec> specs = time_stepping_parameters(d.stepping.time_step);
  specs.push_back(material_law_parameter(d.law));
  specs.push_back(P::whole_number("iterations", d.iterations, 1, 100000, "sweeps over every vertex colour per frame"));
  specs.push_back(P::number("chebyshev_rho", d.chebyshev_rho, 0, 0.9999,
                            "> 0: Chebyshev acceleration with this spectral radius estimate (0: off)"));
  specs.push_back(P::number("damping", d.damping, 0, 1e3,
                            "k_d (s): the paper's damping, the vertex's elastic block times (x - x_n) k_d / h as a "
                            "force (0: none)"));
  specs.push_back(P::choice("start", {"previous", "inertial", "adaptive"}, start_name(d.start),
                            "a frame's first iterate: the last positions, the inertial target, or the paper's adaptive "
                            "start (the last acceleration along the external force)"));
  specs.push_back(P::choice("kernels", {"auto", "avx2", "sse2", "scalar"}, kernels_name(d.kernels),
                            "avx2, sse2: a vertex's tets four at a time in vector lanes with those instructions (laws "
                            "that offer it: neo_hookean); scalar: one at a time; auto: the best lanes this CPU and "
                            "the law allow, else scalar"));
  return specs;
}

VbdSettings vbd_settings(const Parameters& p) {
  VbdSettings s;
  s.stepping = time_stepping(p);
  s.law = p.choice("material_law");
  s.iterations = p.integer("iterations");
  s.chebyshev_rho = p.number("chebyshev_rho");
  s.damping = p.number("damping");
  const std::string& start = p.choice("start");
  s.start = start == "previous" ? VbdStart::Previous : start == "inertial" ? VbdStart::Inertial : VbdStart::Adaptive;
  const std::string& kernels = p.choice("kernels");
  for (VbdKernels k : {VbdKernels::Auto, VbdKernels::Avx2, VbdKernels::Sse2, VbdKernels::Scalar})
    if (kernels == kernels_name(k)) s.kernels = k;
  return s;
}

VbdKernels choose_vbd_kernels(VbdKernels asked, bool law_has_lanes, const std::string& law, bool cpu_has_avx2) {
  if (asked == VbdKernels::Auto)
    return !law_has_lanes ? VbdKernels::Scalar : cpu_has_avx2 ? VbdKernels::Avx2 : VbdKernels::Sse2;
  if (asked != VbdKernels::Scalar && !law_has_lanes)
    throw std::invalid_argument(std::string("vbd: kernels ") + kernels_name(asked) + " need a law with batched node " +
                                "terms (neo_hookean); material_law " + law + " has none");
  if (asked == VbdKernels::Avx2 && !cpu_has_avx2)
    throw std::invalid_argument("vbd: kernels avx2: this CPU has no AVX2 and FMA");
  return asked;
}

std::unique_ptr<ElasticSolve> make_vbd_solve(const ElasticBody& body, const VbdSettings& settings) {
  return make_for_law<VbdSolve>(settings.law, body, settings);
}

}  // namespace tb
