// The table of PBD constraint kinds (constraint_kinds.h), and two more kinds
// defined here through the same mechanism as stretch and bending: a struct of
// static members made into a ConstraintKind by define_constraint_kind, and a
// table that lists it. `rest_pin` (one vertex, three rest values: a zero-length
// spring to the rest position) and `tether` (two vertices like stretch, which the
// batches once told apart by arity: a distance that may shrink but not grow
// beyond its limit, 1.1 times the edge at rest) run batched on every instruction
// set, in both precisions, on threads and domains, with the reference kernels and
// with XPBD, and need nothing beyond their struct and their table entry. This file
// compiles their kernels: it has the lane-math options (tests/CMakeLists.txt).
#include "constraint_kinds.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <string>

#include "cube_generator.h"
#include "define_constraint_kind.h"
#include "domain_partition.h"
#include "load_mapping.h"
#include "pbd_solver.h"

namespace tb::pbd {
namespace {

using lanes::Triple;

/// A zero-length spring from each vertex to its rest position x0: C = |p - x0|,
/// dp = -k C grad C = k (x0 - p) for a free vertex (eq. 13 with one vertex).
struct RestPin {
  static constexpr const char* kName = "rest_pin";
  static constexpr int kArity = 1, kRestValues = 3;
  static constexpr const char* kStiffnessUnit = "N_per_m";

  static void build(const SurfaceMesh& s, KindConstraints& c) {
    c.resize(s.V.rows());
    for (Eigen::Index v = 0; v < s.V.rows(); ++v) {
      c.vertices(v, 0) = static_cast<int>(v);
      c.rest.row(v) = s.V.row(v);
    }
  }
  template <class T>
  static TB_PBD_INLINE void project(const Triple<T> p[1], const T w[1], const T rest[3], double stiffness,
                                    const ProjectionOptions&, Triple<T> corr[1]) {
    const T s = lanes::select(w[0] > T{}, lanes::splat<T>(stiffness), T{});
    corr[0] = s * (Triple<T>{rest[0], rest[1], rest[2]} - p[0]);
  }
  static bool reference(const Vec3 p[1], const double w[1], const double rest[3], double stiffness,
                        const ProjectionOptions&, Vec3 corr[1]) {
    corr[0].setZero();
    if (!(w[0] > 0)) return false;
    corr[0] = stiffness * (Vec3(rest[0], rest[1], rest[2]) - p[0]);
    return true;
  }
  static bool xpbd(const Vec3 p[1], const double w[1], const double rest[3], double alpha_tilde, double& lambda,
                   const ProjectionOptions&, Vec3 corr[1]) {
    corr[0].setZero();
    const Vec3 d = p[0] - Vec3(rest[0], rest[1], rest[2]);
    const double C = d.norm();
    if (!(w[0] > 0) || !(C > kTiny)) return false;
    const double dlambda = (-C - alpha_tilde * lambda) / (w[0] + alpha_tilde);  // |grad C| = 1
    lambda += dlambda;
    corr[0] = (w[0] * dlambda / C) * d;
    return true;
  }
  /// A spring of E h per vertex, N/m.
  static Eigen::VectorXd compliance(const SurfaceMesh&, const KindConstraints& c, const ShellMaterial& m) {
    return Eigen::VectorXd::Constant(c.size(), 1 / (m.youngs_modulus * m.thickness));
  }
};

/// One per edge: C = |p1 - p2| - limit where positive (a tether, slack below its
/// limit), the limit 1.1 times the rest length; the stretch projection's
/// corrections otherwise.
struct Tether {
  static constexpr const char* kName = "tether";
  static constexpr int kArity = 2, kRestValues = 1;
  static constexpr const char* kStiffnessUnit = "N_per_m";

  /// On the stretch constraints' edges, limits 1.1 times their rest lengths.
  static void build(const SurfaceMesh& s, KindConstraints& c) {
    const KindConstraints edges = build_constraints(s).of("stretch");
    c.vertices = edges.vertices;
    c.rest = 1.1 * edges.rest;
  }
  template <class T>
  static TB_PBD_INLINE void project(const Triple<T> p[2], const T w[2], const T rest[1], double stiffness,
                                    const ProjectionOptions&, Triple<T> corr[2]) {
    const T one = lanes::splat<T>(1);
    const Triple<T> d = p[0] - p[1];
    const T len = lanes::sqrt(dot(d, d)), wsum = w[0] + w[1];
    const auto taut = (wsum > T{}) & (len > rest[0]);
    const T s =
        lanes::select(taut, lanes::splat<T>(stiffness) * (len - rest[0]) / (lanes::select(taut, len * wsum, one)), T{});
    corr[0] = (-s * w[0]) * d;
    corr[1] = (s * w[1]) * d;
  }
  /// Whether the tether on p is taut (and can move): corr zeroed, d = p1 - p2, len = |d|.
  static bool taut(const Vec3 p[2], const double w[2], const double rest[1], Vec3 corr[2], Vec3& d, double& len) {
    corr[0].setZero();
    corr[1].setZero();
    d = p[0] - p[1];
    len = d.norm();
    return w[0] + w[1] > 0 && len > rest[0];
  }
  static bool reference(const Vec3 p[2], const double w[2], const double rest[1], double stiffness,
                        const ProjectionOptions&, Vec3 corr[2]) {
    Vec3 d;
    double len;
    if (!taut(p, w, rest, corr, d, len)) return false;
    const double s = stiffness * (len - rest[0]) / (len * (w[0] + w[1]));
    corr[0] = (-s * w[0]) * d;
    corr[1] = (s * w[1]) * d;
    return true;
  }
  /// XPBD (Macklin et al. eqs. 17-18) with the multiplier kept at or below 0: a
  /// tether pulls, it never pushes.
  static bool xpbd(const Vec3 p[2], const double w[2], const double rest[1], double alpha_tilde, double& lambda,
                   const ProjectionOptions&, Vec3 corr[2]) {
    Vec3 d;
    double len;
    if (!taut(p, w, rest, corr, d, len)) return false;
    const double C = len - rest[0];
    const double next = std::min(lambda + (-C - alpha_tilde * lambda) / (w[0] + w[1] + alpha_tilde), 0.0);
    const double dlambda = next - lambda;
    lambda = next;
    corr[0] = (w[0] * dlambda / len) * d;
    corr[1] = (-w[1] * dlambda / len) * d;
    return true;
  }
  static Eigen::VectorXd compliance(const SurfaceMesh&, const KindConstraints& c, const ShellMaterial& m) {
    return Eigen::VectorXd::Constant(c.size(), 1 / (m.youngs_modulus * m.thickness));
  }
};

const ConstraintKind& rest_pin_kind() {
  static const ConstraintKind kind = define_constraint_kind<RestPin>();
  return kind;
}
const ConstraintKind& tether_kind() {
  static const ConstraintKind kind = define_constraint_kind<Tether>();
  return kind;
}

/// The surface kinds with the two of this file after them: the table line.
KindTable four_kinds() {
  KindTable kinds = surface_constraint_kinds();
  kinds.push_back(&rest_pin_kind());
  kinds.push_back(&tether_kind());
  return kinds;
}

/// A 6 x 6 x 6 cube surface, bottom fixed, randomly disturbed.
struct Cube {
  SurfaceMesh surface = make_cube_surface({0.1, 0.1, 6, 6, 6});
  Eigen::VectorXd inverse_mass;
  PaddedPoints disturbed;
  Cube() {
    std::vector<char> fixed(static_cast<size_t>(surface.V.rows()));
    for (Eigen::Index v = 0; v < surface.V.rows(); ++v) fixed[static_cast<size_t>(v)] = surface.V(v, 2) == 0.0;
    inverse_mass = inverse_masses(surface, 1000, fixed);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> U(-0.004, 0.004);  // a quarter of an edge
    disturbed = PaddedPoints::Zero(surface.V.rows(), kPositionStride);
    disturbed.leftCols<3>() = surface.V;
    for (Eigen::Index v = 0; v < surface.V.rows(); ++v)
      for (int d = 0; d < 3; ++d) disturbed(v, d) += U(rng);
  }
};

std::vector<InstructionSet> instruction_sets() {
  std::vector<InstructionSet> sets;
  for (InstructionSet isa : kInstructionSets)
    if (cpu_supports(isa)) sets.push_back(isa);
  return sets;
}

/// One pass of kind K's kernel over its constraints one at a time, in the batches'
/// order (reversed if asked), in precision S on rows of kPositionStride.
template <class K, class S>
void one_at_a_time(const KindConstraints& c, const KindBatches& b, const Eigen::VectorXd& w, S* x, bool reverse,
                   double stiffness) {
  constexpr int N = K::kArity, R = K::kRestValues;
  for (size_t k = 0; k < b.order.size(); ++k) {
    const int i = b.order[reverse ? b.order.size() - 1 - k : k];
    Triple<S> p[N], corr[N];
    S wq[N], rest[R];
    for (int j = 0; j < N; ++j) {
      const S* row = x + kPositionStride * c.vertices(i, j);
      p[j] = {row[0], row[1], row[2]};
      wq[j] = static_cast<S>(w(c.vertices(i, j)));
    }
    for (int r = 0; r < R; ++r) rest[r] = static_cast<S>(c.rest(i, r));
    K::project(p, wq, rest, stiffness, {}, corr);
    for (int j = 0; j < N; ++j) {
      S* row = x + kPositionStride * c.vertices(i, j);
      row[0] += corr[j].x;
      row[1] += corr[j].y;
      row[2] += corr[j].z;
    }
  }
}

TEST(ConstraintKinds, TheTableListsStretchThenBendingWithTheirStiffnessParameters) {
  const KindTable& kinds = surface_constraint_kinds();
  ASSERT_EQ(kinds.size(), 2u);
  EXPECT_STREQ(kinds[0]->name, "stretch");
  EXPECT_EQ(kinds[0]->arity, 2);
  EXPECT_STREQ(kinds[1]->name, "bending");
  EXPECT_EQ(kinds[1]->arity, 4);
  const Parameters p = resolve_parameters(parameter_specs(), {{"bending_stiffness", 0.25}}, "test");
  EXPECT_EQ(p.number("stretch_stiffness"), 1.0);
  EXPECT_EQ(Settings::from(p).stiffness_of("bending"), 0.25);
  EXPECT_THROW(resolve_parameters(parameter_specs(), {{"rest_pin_stiffness", 0.5}}, "test"), std::invalid_argument);
}

TEST(ConstraintKinds, ABadTableIsAnError) {
  EXPECT_THROW(check_kinds({&rest_pin_kind(), &rest_pin_kind()}), std::invalid_argument);  // listed twice
  ConstraintKind unnamed = tether_kind();
  unnamed.name = "Tether";
  EXPECT_THROW(check_kinds({&unnamed}), std::invalid_argument);
  const Cube cube;
  EXPECT_THROW(build_constraints(cube.surface, {&tether_kind(), &unnamed}), std::invalid_argument);
  EXPECT_THROW(build_constraints(cube.surface).of("tether"), std::invalid_argument);
}

/// A sweep over the four kinds is the sweep over stretch and bending, then the
/// two kinds of this file one constraint at a time (their kernels on numbers, in
/// the batches' order), bitwise, on every instruction set, in both precisions,
/// on any number of threads and with domains.
template <class S>
void expect_new_kinds_batched_like_the_others(Precision precision) {
  const Cube cube;
  const ConstraintSet all = build_constraints(cube.surface, four_kinds());
  ASSERT_EQ(all.kinds.size(), 4u);
  EXPECT_EQ(all.of("rest_pin").size(), cube.surface.V.rows());
  EXPECT_EQ(all.of("tether").size(), all.of("stretch").size());
  ConstraintSet two = all;
  two.kinds.erase(two.kinds.begin() + 2, two.kinds.end());  // stretch, bending
  const std::vector<double> k = {0.9, 0.7, 0.3, 0.8};
  using Rows = Eigen::Matrix<S, -1, kPositionStride, Eigen::RowMajor>;
  for (InstructionSet isa : instruction_sets()) {
    const int width = batch_width(isa, precision);
    const ConstraintBatches batches(all, cube.inverse_mass, width, precision),
        first(two, cube.inverse_mass, width, precision);
    Rows batched = cube.disturbed.cast<S>(), split = batched;
    for (int sweep = 0; sweep < 4; ++sweep) {
      const bool reverse = sweep % 2 == 1;
      batches.sweep(batched.data(), reverse, k, {}, isa);
      first.sweep(split.data(), reverse, {k[0], k[1]}, {}, isa);
      one_at_a_time<RestPin>(all.of("rest_pin"), batches.of("rest_pin"), cube.inverse_mass, split.data(), reverse,
                             k[2]);
      one_at_a_time<Tether>(all.of("tether"), batches.of("tether"), cube.inverse_mass, split.data(), reverse, k[3]);
    }
    EXPECT_GT((batched.template cast<double>() - cube.disturbed).cwiseAbs().maxCoeff(), 1e-4);
    EXPECT_EQ((batched - split).cwiseAbs().maxCoeff(), S(0)) << name(isa) << " " << name(precision);
    // Threads and domains: the same numbers on any team (domains change the order).
    Rows one = cube.disturbed.cast<S>();
    batches.project(one.data(), 6, k, {}, isa, nullptr);
    ThreadTeam team(3);
    Rows three = cube.disturbed.cast<S>();
    batches.project(three.data(), 6, k, {}, isa, &team);
    EXPECT_EQ((three - one).cwiseAbs().maxCoeff(), S(0)) << name(isa);
    const ConstraintBatches by_domain(all, cube.inverse_mass, width, precision, bisect_into_domains(cube.surface.V, 2));
    Rows domains_one = cube.disturbed.cast<S>(), domains_two = domains_one;
    by_domain.project(domains_one.data(), 6, k, {}, isa, nullptr);
    ThreadTeam pair(2);
    by_domain.project(domains_two.data(), 6, k, {}, isa, &pair);
    EXPECT_EQ((domains_two - domains_one).cwiseAbs().maxCoeff(), S(0)) << name(isa) << ", 2 domains";
  }
}

TEST(ConstraintKinds, KindsDefinedInATestAreBatchedSweptAndThreadedLikeTheOthers) {
  expect_new_kinds_batched_like_the_others<double>(Precision::Double);
  expect_new_kinds_batched_like_the_others<float>(Precision::Single);
}

TEST(ConstraintKinds, TheNewKindsKernelsAgreeWithTheirReferenceProjections) {
  const Cube cube;
  const ConstraintSet all = build_constraints(cube.surface, four_kinds());
  const std::vector<double> k = {0.9, 0.7, 0.3, 0.8};
  for (InstructionSet isa : instruction_sets()) {
    const ConstraintBatches batches(all, cube.inverse_mass, batch_width(isa, Precision::Double));
    std::vector<Eigen::MatrixXd> corrections;
    batches.corrections(cube.disturbed.data(), k, {}, isa, corrections);
    ASSERT_EQ(corrections.size(), 4u);
    for (size_t kind = 2; kind < 4; ++kind) {
      int moved = 0;
      const KindConstraints& c = all.kinds[kind];
      const int N = c.kind->arity;
      for (Eigen::Index i = 0; i < c.size(); ++i) {
        Vec3 p[2], corr[2];
        double w[2];
        for (int j = 0; j < N; ++j) {
          p[j] = cube.disturbed.row(c.vertices(i, j)).head<3>().transpose();
          w[j] = cube.inverse_mass(c.vertices(i, j));
        }
        moved += c.kind->reference(p, w, c.rest.row(i).data(), k[kind], {}, corr);
        for (int j = 0; j < N; ++j)
          EXPECT_NEAR((corrections[kind].row(i).segment<3>(3 * j).transpose() - corr[j]).norm(), 0,
                      1e-15 * (1 + corr[j].norm()))
              << c.kind->name << " " << i << " " << name(isa);
      }
      EXPECT_GT(moved, 20) << c.kind->name;  // pins off their rest positions, taut tethers
    }
  }
}

/// The solver runs the new kinds like stretch and bending: with stiffness 0 they
/// are not swept (bitwise the two-kind solver); with stiffness the pins hold the
/// surface nearer its rest shape, bitwise the same on two threads, with the
/// reference kernels close to the SIMD ones, and with XPBD.
TEST(ConstraintKinds, TheSolverRunsTheNewKindsInEveryMode) {
  const Cube cube;
  const NodalWeights load = nearest_vertex(cube.surface.V, Vec3(0, 0, 0.1));
  auto run = [&](Settings s, const KindTable& kinds) {
    Solver solver(cube.surface, cube.inverse_mass, s, kinds);
    solver.set_loads({load});
    for (int f = 0; f < 40; ++f) solver.step({Vec3(0, 0, 0.5)}, {}, Points());
    return std::make_pair(Points(solver.positions()), solver.details());
  };
  auto displacement = [&](const Points& x) { return (x - cube.surface.V).rowwise().norm().maxCoeff(); };
  Settings off;
  off.stiffness = {{"rest_pin", 0}, {"tether", 0}};
  const Points two_kinds = run(Settings{}, surface_constraint_kinds()).first;
  EXPECT_EQ((run(off, four_kinds()).first - two_kinds).cwiseAbs().maxCoeff(), 0.0);
  Settings on;
  on.stiffness = {{"rest_pin", 0.2}, {"tether", 1}};
  const Points pinned = run(on, four_kinds()).first;
  EXPECT_LT(displacement(pinned), 0.8 * displacement(two_kinds));
  Settings threads = on;
  threads.threads = 2;
  threads.domains = 2;
  Settings domains = threads;
  domains.threads = 1;
  EXPECT_EQ((run(threads, four_kinds()).first - run(domains, four_kinds()).first).cwiseAbs().maxCoeff(), 0.0);
  Settings reference = on;
  reference.kernels = Kernels::Reference;
  EXPECT_LT((run(reference, four_kinds()).first - pinned).cwiseAbs().maxCoeff(), 1e-9 * displacement(pinned));
  Settings xpbd;
  xpbd.kernels = Kernels::Reference;
  xpbd.constraint_solve = ConstraintSolve::Xpbd;
  xpbd.bending_angle = BendingAngle::Signed;
  const auto [x, details] = run(xpbd, four_kinds());
  EXPECT_TRUE(x.allFinite());
  EXPECT_GT(displacement(x), 1e-4);
  EXPECT_NEAR(details["rest_pin_stiffness_N_per_m"][0].get<double>(), 3000 * 0.1 / 6, 1e-9);  // E h
  EXPECT_TRUE(details.contains("tether_stiffness_N_per_m"));
  EXPECT_TRUE(details.contains("bending_stiffness_N_m"));
}

}  // namespace
}  // namespace tb::pbd
