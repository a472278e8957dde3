// The batched PBD sweep against one-at-a-time projection, and the vectorised
// atan2 against the C library (the sweep's speed must not change its numbers).
#include "constraint_batches.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <set>

#include "domain_partition.h"
#include "load_mapping.h"
#include "pbd_solver.h"
#include "projection_kernels.h"
#include "shapes.h"
#include "test_support.h"

namespace tb::pbd {
namespace {

/// Distance between a and b in units in the last place.
double ulps(double a, double b) { return std::abs(a - b) / (std::nextafter(std::abs(b), INFINITY) - std::abs(b)); }

TEST(LaneMath, Atan2AgreesWithTheCLibraryAndIsTheSameInEveryLane) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1), E(-8, 8);
  double worst = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    lanes::Batch y, x;
    for (int l = 0; l < lanes::kBatchWidth; ++l) {
      y[l] = U(rng) * std::pow(10.0, E(rng));
      x[l] = U(rng) * std::pow(10.0, E(rng));
    }
    const lanes::Batch r = lanes::atan2(y, x);
    for (int l = 0; l < lanes::kBatchWidth; ++l) {
      const double scalar = lanes::atan2(y[l], x[l]);
      ASSERT_EQ(r[l], scalar) << "lane " << l;
      worst = std::max(worst, ulps(scalar, std::atan2(y[l], x[l])));
    }
  }
  // Cephes atan peaks near 1 ulp, the octant reduction adds up to one rounding
  // and glibc is within about half an ulp: 3 ulps allowed (measured 2).
  EXPECT_LE(worst, 3.0);
  RecordProperty("max_ulps", std::to_string(worst));
  // Axes and the origin (atan2(0, 0) = 0: a degenerate pair gives no NaN).
  EXPECT_EQ(lanes::atan2(0.0, 0.0), 0.0);
  EXPECT_EQ(lanes::atan2(0.0, 2.0), 0.0);
  EXPECT_EQ(lanes::atan2(0.0, -2.0), M_PI);
  EXPECT_EQ(lanes::atan2(3.0, 0.0), M_PI / 2);
  EXPECT_EQ(lanes::atan2(-3.0, 0.0), -M_PI / 2);
  EXPECT_NEAR(lanes::atan2(1.0, 1.0), M_PI / 4, 1e-16);
  EXPECT_NEAR(lanes::atan2(-1.0, -1.0), -3 * M_PI / 4, 4e-16);
}

TEST(LaneMath, LogAgreesWithTheCLibraryAndIsTheSameInEveryLane) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> E(-30, 30), Near1(-1e-3, 1e-3);
  double worst = 0;
  for (int trial = 0; trial < 100000; ++trial) {
    lanes::Batch x;
    lanes::Twin<lanes::Vector2> twin;
    for (int l = 0; l < lanes::kBatchWidth; ++l) {
      // Over sixty decades, and near 1 (det F of a small deformation), where ln x is small
      // and a relative error shows.
      x[l] = l % 2 == 0 ? std::exp(E(rng)) : 1 + Near1(rng);
      (l < 2 ? twin.lo : twin.hi)[l % 2] = x[l];
    }
    const lanes::Batch r = lanes::log(x);
    const lanes::Twin<lanes::Vector2> rt = lanes::log(twin);
    for (int l = 0; l < lanes::kBatchWidth; ++l) {
      const double scalar = lanes::log(x[l]);
      ASSERT_EQ(r[l], scalar) << "lane " << l;
      ASSERT_EQ((l < 2 ? rt.lo : rt.hi)[l % 2], scalar) << "two-register lane " << l;
      worst = std::max(worst, ulps(scalar, std::log(x[l])));
    }
  }
  // fdlibm's log is within 1 ulp, glibc's within about half: 2 ulps allowed (measured 1).
  EXPECT_LE(worst, 2.0);
  RecordProperty("max_ulps", std::to_string(worst));
  // Exact points: ln 1 = 0, powers of two, and the bounds of normal numbers.
  EXPECT_EQ(lanes::log(1.0), 0.0);
  EXPECT_NEAR(lanes::log(2.0), M_LN2, 1e-16);
  EXPECT_NEAR(lanes::log(0.5), -M_LN2, 1e-16);
  EXPECT_NEAR(lanes::log(std::numeric_limits<double>::max()), std::log(std::numeric_limits<double>::max()), 1e-13);
  EXPECT_NEAR(lanes::log(std::numeric_limits<double>::min()), std::log(std::numeric_limits<double>::min()), 1e-13);
  EXPECT_NEAR(lanes::log(std::nextafter(std::sqrt(2.0), 0.0)), std::log(std::nextafter(std::sqrt(2.0), 0.0)), 2e-16);
  // Subnormal numbers (scaled by 2^54 first), down to the smallest.
  const double denorm_min = std::numeric_limits<double>::denorm_min();
  for (double x : {denorm_min, 3 * denorm_min, 1e-310, 0.5 * std::numeric_limits<double>::min()}) {
    EXPECT_LE(ulps(lanes::log(x), std::log(x)), 1.0) << x;
    const lanes::Batch b = lanes::log(lanes::Batch{x, 1.0, x, 2.0});
    EXPECT_EQ(b[0], lanes::log(x));
    EXPECT_EQ(b[2], lanes::log(x));
  }
}

TEST(LaneMath, SinglePrecisionAtan2AgreesWithTheCLibraryAndIsTheSameInEveryLane) {
  std::mt19937 rng(4);
  std::uniform_real_distribution<float> U(-1, 1), E(-8, 8);
  using Floats = lanes::Vector<float, 8>;
  double worst = 0;
  for (int trial = 0; trial < 50000; ++trial) {
    Floats y, x;
    for (int l = 0; l < 8; ++l) {
      y[l] = U(rng) * std::pow(10.0f, E(rng));
      x[l] = U(rng) * std::pow(10.0f, E(rng));
    }
    const Floats r = lanes::atan2(y, x);
    for (int l = 0; l < 8; ++l) {
      const float scalar = lanes::atan2(y[l], x[l]);
      ASSERT_EQ(r[l], scalar) << "lane " << l;
      const float exact = static_cast<float>(std::atan2(double{y[l]}, double{x[l]}));
      worst = std::max(
          worst, std::abs(double{scalar} - exact) / (std::nextafter(std::abs(exact), INFINITY) - std::abs(exact)));
    }
  }
  // Cephes' atanf is within about 1 float ulp, the octant reduction adds up to
  // two roundings: 4 ulps allowed.
  EXPECT_LE(worst, 4.0);
  RecordProperty("max_float_ulps", std::to_string(worst));
  EXPECT_EQ(lanes::atan2(0.0f, 0.0f), 0.0f);
  EXPECT_EQ(lanes::atan2(0.0f, -2.0f), static_cast<float>(M_PI));
}

/// A surface (by default the paper cube's), randomly disturbed, with its
/// vertices at z = 0 fixed.
struct DisturbedSurface {
  SurfaceMesh surface;
  ConstraintSet constraints = build_constraints(surface);
  Eigen::VectorXd inverse_mass;
  Points positions;
  explicit DisturbedSurface(SurfaceMesh s = testing::scenario_mesh("cube-pull", false).fine_surface)
      : surface(std::move(s)) {
    std::vector<char> fixed(static_cast<size_t>(surface.V.rows()));
    for (Eigen::Index v = 0; v < surface.V.rows(); ++v) fixed[static_cast<size_t>(v)] = surface.V(v, 2) == 0.0;
    inverse_mass = inverse_masses(surface, 1000, fixed);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> U(-0.002, 0.002);  // 20% of an edge
    positions = surface.V;
    for (Eigen::Index i = 0; i < positions.size(); ++i) positions.data()[i] += U(rng);
  }
};
using DisturbedCube = DisturbedSurface;

/// One forward or reverse sweep as plain Gauss-Seidel in precision S: the
/// kernels on one constraint at a time (for double, what constraints.h's
/// project_stretch and project_bending compute), in the batches' order.
template <class S>
void sequential_sweep(const DisturbedCube& c, const ConstraintBatches& b, Eigen::Matrix<S, -1, 3, Eigen::RowMajor>& x,
                      bool reverse, double ks, double kb, BendingAngle kind) {
  using lanes::Triple;
  auto get = [&x](int v) { return Triple<S>{x(v, 0), x(v, 1), x(v, 2)}; };
  auto add = [&x](int v, const Triple<S>& d) {
    x(v, 0) += d.x;
    x(v, 1) += d.y;
    x(v, 2) += d.z;
  };
  auto w = [&c](int v) { return static_cast<S>(c.inverse_mass(v)); };
  const KindConstraints& stretch = c.constraints.of("stretch");
  const std::vector<int>& so = b.of("stretch").order;
  for (size_t k = 0; k < so.size(); ++k) {
    const int i = so[reverse ? so.size() - 1 - k : k];
    const int a = stretch.vertices(i, 0), d = stretch.vertices(i, 1);
    S share_a, share_d;
    kernels::stretch_shares(w(a), w(d), share_a, share_d);
    Triple<S> ca, cd;
    kernels::project_stretch(get(a), share_a, get(d), share_d, static_cast<S>(stretch.rest(i, 0)), ks, ca, cd);
    add(a, ca);
    add(d, cd);
  }
  const KindConstraints& bending = c.constraints.of("bending");
  const std::vector<int>& bo = b.of("bending").order;
  for (size_t k = 0; k < bo.size(); ++k) {
    const int i = bo[reverse ? bo.size() - 1 - k : k];
    int q[4];
    for (int j = 0; j < 4; ++j) q[j] = bending.vertices(i, j);
    const Triple<S> p[4] = {get(q[0]), get(q[1]), get(q[2]), get(q[3])};
    const S wq[4] = {w(q[0]), w(q[1]), w(q[2]), w(q[3])};
    Triple<S> corr[4];
    kernels::project_bending(p, wq, static_cast<S>(bending.rest(i, 0)), kb, kind, corr);
    for (int j = 0; j < 4; ++j) add(q[j], corr[j]);
  }
}

/// Each row of `vertices` is in `order` exactly once if one of its vertices is
/// free, else not at all.
template <class Rows>
void expect_every_movable_constraint_once(const Rows& vertices, const std::vector<int>& order,
                                          const Eigen::VectorXd& w) {
  std::vector<int> seen(static_cast<size_t>(vertices.rows()), 0);
  for (int i : order) ++seen[static_cast<size_t>(i)];
  for (Eigen::Index i = 0; i < vertices.rows(); ++i) {
    bool movable = false;
    for (Eigen::Index j = 0; j < vertices.cols(); ++j) movable = movable || w(vertices(i, j)) > 0;
    EXPECT_EQ(seen[static_cast<size_t>(i)], movable ? 1 : 0) << "constraint " << i;
  }
}

/// Every instruction set this CPU has.
std::vector<InstructionSet> instruction_sets() {
  std::vector<InstructionSet> sets;
  for (InstructionSet isa : kInstructionSets)
    if (cpu_supports(isa)) sets.push_back(isa);
  return sets;
}

TEST(ConstraintBatches, EveryMovableConstraintIsProjectedOnce) {
  const DisturbedCube cube;
  for (int width : {4, 8, 16}) {
    const ConstraintBatches batches(cube.constraints, cube.inverse_mass, width);
    const KindBatches &stretch = batches.of("stretch"), &bending = batches.of("bending");
    expect_every_movable_constraint_once(cube.constraints.of("stretch").vertices, stretch.order, cube.inverse_mass);
    expect_every_movable_constraint_once(cube.constraints.of("bending").vertices, bending.order, cube.inverse_mass);
    // Batches are mostly full: the colouring leaves few partial ones.
    const size_t full = (stretch.order.size() + width - 1) / width;
    EXPECT_LT(stretch.layout.batch_count(), full + full / 5) << width << " lanes";
    RecordProperty("stretch_batches_" + std::to_string(width), std::to_string(stretch.layout.batch_count()));
    RecordProperty("bending_batches_" + std::to_string(width), std::to_string(bending.layout.batch_count()));
  }
}

/// The batched sweep against one-at-a-time projection, bitwise, on every
/// instruction set this CPU has, in both precisions.
template <class S>
void expect_sweep_equals_one_at_a_time(Precision precision) {
  const DisturbedCube cube;
  using Rows = Eigen::Matrix<S, -1, 3, Eigen::RowMajor>;
  for (BendingAngle kind : {BendingAngle::Unsigned, BendingAngle::Signed})
    for (InstructionSet isa : instruction_sets()) {
      const ConstraintBatches batches(cube.constraints, cube.inverse_mass, batch_width(isa, precision), precision);
      Rows sequential = cube.positions.cast<S>();
      Eigen::Matrix<S, -1, 4, Eigen::RowMajor> batched =
          Eigen::Matrix<S, -1, 4, Eigen::RowMajor>::Zero(sequential.rows(), ConstraintBatches::kPositionStride);
      batched.template leftCols<3>() = sequential;
      for (int sweep = 0; sweep < 4; ++sweep) {  // forward, reverse, forward, reverse
        batches.sweep(batched.data(), sweep % 2 == 1, {0.9, 0.7}, {kind}, isa);
        sequential_sweep<S>(cube, batches, sequential, sweep % 2 == 1, 0.9, 0.7, kind);
      }
      EXPECT_GT((batched.template leftCols<3>().template cast<double>() - cube.positions).cwiseAbs().maxCoeff(), 1e-4);
      EXPECT_EQ((batched.template leftCols<3>() - sequential).cwiseAbs().maxCoeff(), S(0))
          << name(isa) << " " << name(precision);
    }
}

TEST(ConstraintBatches, SweepEqualsOneAtATimeProjectionBitwiseOnEveryInstructionSet) {
  expect_sweep_equals_one_at_a_time<double>(Precision::Double);
  expect_sweep_equals_one_at_a_time<float>(Precision::Single);
}

TEST(ConstraintBatches, EveryInstructionSetGivesTheSameNumbersInDoublePrecision) {
  const DisturbedCube cube;
  PaddedPoints first;
  for (InstructionSet isa : instruction_sets()) {
    const ConstraintBatches batches(cube.constraints, cube.inverse_mass, batch_width(isa, Precision::Double));
    PaddedPoints x = PaddedPoints::Zero(cube.positions.rows(), ConstraintBatches::kPositionStride);
    x.leftCols<3>() = cube.positions;
    batches.project(x.data(), 4, {0.9, 0.7}, {BendingAngle::Unsigned}, isa, nullptr);
    if (first.size() == 0)
      first = x;
    else
      EXPECT_EQ((x - first).cwiseAbs().maxCoeff(), 0.0) << name(isa);
  }
}

TEST(ConstraintBatches, SweepOnTheWrongInstructionSetOrPrecisionIsAnError) {
  const DisturbedCube cube;
  const ConstraintBatches four(cube.constraints, cube.inverse_mass, 4);
  PaddedPoints x = PaddedPoints::Zero(cube.positions.rows(), ConstraintBatches::kPositionStride);
  Eigen::Matrix<float, -1, 4, Eigen::RowMajor> xf = x.cast<float>();
  EXPECT_THROW(four.sweep(xf.data(), false, {1, 1}, {BendingAngle::Unsigned}, InstructionSet::Sse2),
               std::invalid_argument);  // double batches, float positions
  if (cpu_supports(InstructionSet::Avx512)) {
    EXPECT_THROW(four.sweep(x.data(), false, {1, 1}, {BendingAngle::Unsigned}, InstructionSet::Avx512),
                 std::invalid_argument);  // 4 lanes packed, 8 swept
  }
  EXPECT_THROW(ConstraintBatches(cube.constraints, cube.inverse_mass, 6), std::invalid_argument);
}

/// Within each colour (batches [begin[c], begin[c + 1])), no vertex is used by two
/// constraints: what lets threads split a colour. Returns the colour count.
template <int N, class Rows>
size_t expect_colours_independent(const BatchLayout& layout, int width, const std::vector<int>& order,
                                  const Rows& vertices, Eigen::Index vertex_count) {
  const std::vector<size_t>& begin = layout.colours.begin;
  EXPECT_EQ(begin.front(), 0u);
  EXPECT_EQ(begin.back(), layout.batch_count());
  size_t next = 0;  // position in `order` of the current batch's lane 0
  const size_t W = static_cast<size_t>(width);
  for (size_t c = 0; c + 1 < begin.size(); ++c) {
    std::vector<char> used(static_cast<size_t>(vertex_count), 0);
    for (size_t b = begin[c]; b < begin[c + 1]; ++b) {
      EXPECT_GT(layout.count[b], 0);
      for (size_t l = 0; l < static_cast<size_t>(layout.count[b]); ++l, ++next)
        for (size_t j = 0; j < N; ++j) {
          const int v = vertices(order[next], static_cast<Eigen::Index>(j));
          EXPECT_EQ(layout.q[(b * N + j) * W + l], v);
          EXPECT_FALSE(used[static_cast<size_t>(v)]) << "colour " << c << " uses vertex " << v << " twice";
          used[static_cast<size_t>(v)] = 1;
        }
    }
  }
  EXPECT_EQ(next, order.size());
  return begin.size() - 1;
}

TEST(ConstraintBatches, BatchesNeverStraddleColoursAndAColourSharesNoVertex) {
  const DisturbedCube cube;
  const Eigen::Index n = cube.surface.V.rows();
  for (int width : {4, 8, 16}) {
    const ConstraintBatches batches(cube.constraints, cube.inverse_mass, width);
    const KindBatches &stretch = batches.of("stretch"), &bending = batches.of("bending");
    const size_t stretch_colours =
        expect_colours_independent<2>(stretch.layout, width, stretch.order, cube.constraints.of("stretch").vertices, n);
    const size_t bending_colours =
        expect_colours_independent<4>(bending.layout, width, bending.order, cube.constraints.of("bending").vertices, n);
    RecordProperty("stretch_colours", std::to_string(stretch_colours));
    RecordProperty("bending_colours", std::to_string(bending_colours));
  }
}

TEST(ConstraintBatches, ProjectionIsBitwiseTheSameOnAnyNumberOfThreads) {
  const DisturbedCube cube;
  PaddedPoints start = PaddedPoints::Zero(cube.positions.rows(), ConstraintBatches::kPositionStride);
  start.leftCols<3>() = cube.positions;
  for (InstructionSet isa : instruction_sets()) {
    const ConstraintBatches batches(cube.constraints, cube.inverse_mass, batch_width(isa, Precision::Double));
    PaddedPoints one = start;
    batches.project(one.data(), 6, {0.9, 0.7}, {BendingAngle::Unsigned}, isa, nullptr);
    // The same as six single sweeps, alternating direction.
    PaddedPoints swept = start;
    for (int it = 0; it < 6; ++it) batches.sweep(swept.data(), it % 2 == 1, {0.9, 0.7}, {BendingAngle::Unsigned}, isa);
    EXPECT_EQ((one - swept).cwiseAbs().maxCoeff(), 0.0);
    for (int threads : {1, 2, 3, 5}) {
      ThreadTeam team(threads);
      PaddedPoints many = start;
      for (int repeat = 0; repeat < 3; ++repeat) {  // the team is reused
        many = start;
        batches.project(many.data(), 6, {0.9, 0.7}, {BendingAngle::Unsigned}, isa, &team);
      }
      EXPECT_EQ((many - one).cwiseAbs().maxCoeff(), 0.0) << threads << " threads, " << name(isa);
    }
  }
}

TEST(ConstraintBatches, SolverResultDoesNotDependOnItsThreadCount) {
  const DisturbedCube cube;
  const NodalWeights load_vertex = nearest_vertex(cube.surface.V, Vec3(0, 0, 0.1));
  for (Precision precision : {Precision::Double, Precision::Single})
    for (int domains : {1, 2}) {
      Points reference;
      for (int threads : {1, 2, 4}) {
        Settings s;
        s.threads = threads;
        s.domains = domains;
        s.precision = precision;
        Solver solver(cube.surface, cube.inverse_mass, s);
        solver.set_loads({load_vertex});
        // Pins as in the hybrid: a few vertices moved each frame.
        const std::vector<int> pinned = {load_vertex.nodes(0) + 1, load_vertex.nodes(0) + 2};
        Points pinned_positions(2, 3);
        for (int f = 0; f < 30; ++f) {
          for (int k = 0; k < 2; ++k)
            pinned_positions.row(k) =
                cube.surface.V.row(pinned[static_cast<size_t>(k)]) + Eigen::RowVector3d(0, 0, 1e-4 * f);
          solver.step({Vec3(0, 0, 1)}, pinned, pinned_positions);
        }
        if (threads == 1)
          reference = solver.positions();
        else
          EXPECT_EQ((solver.positions() - reference).cwiseAbs().maxCoeff(), 0.0) << threads << " threads";
        EXPECT_EQ(solver.details()["threads"], threads);
        EXPECT_EQ(solver.details()["precision"], name(precision));
        EXPECT_EQ(solver.details()["domains"], domains);
      }
      EXPECT_GT((reference - cube.surface.V).cwiseAbs().maxCoeff(), 1e-4);
    }
}

/// With a partition into domains: each domain's group holds only constraints
/// with every vertex in that domain, the interface group only constraints across
/// domains; the sweep still equals one-at-a-time projection in the batches' order
/// and is bitwise the same on any number of threads.
TEST(ConstraintBatches, DomainsAreIndependentAndTheirSweepIsBitwiseTheSameOnAnyThreads) {
  // The paper cube, and two surfaces a bisection plane cuts less neatly: a torus
  // (each plane cuts its ring twice) and a non-convex L-block.
  for (const std::string shape : {"cube", "torus", "l_block"}) {
    const DisturbedSurface cube =
        shape == "cube" ? DisturbedSurface() : DisturbedSurface(make_shape_surface({shape, 10}));
    SCOPED_TRACE(shape);
    for (int domains : {2, 3, 5}) {
      const std::vector<int> domain = bisect_into_domains(cube.surface.V, domains);
      for (InstructionSet isa : instruction_sets()) {
        const ConstraintBatches batches(cube.constraints, cube.inverse_mass, batch_width(isa, Precision::Double),
                                        Precision::Double, domain);
        for (const KindBatches& kind : batches.kinds()) {
          const BatchLayout* layout = &kind.layout;
          const bool stretch = kind.kind->name == std::string("stretch");
          const std::vector<int>& order = kind.order;
          ASSERT_EQ(layout->domain_count(), static_cast<size_t>(domains));
          size_t next = 0, interface = 0;
          for (size_t g = 0; g <= layout->domain_count(); ++g) {
            const size_t end = layout->colours.begin[layout->group_begin[g + 1]];
            for (size_t b = layout->colours.begin[layout->group_begin[g]]; b < end; ++b)
              for (int l = 0; l < layout->count[b]; ++l, ++next) {
                std::set<int> touched;
                for (int j = 0; j < (stretch ? 2 : 4); ++j)
                  touched.insert(
                      domain[static_cast<size_t>(cube.constraints.of(kind.kind->name).vertices(order[next], j))]);
                if (g < layout->domain_count()) {
                  EXPECT_EQ(touched, std::set<int>{static_cast<int>(g)}) << "domain " << g;
                } else {
                  EXPECT_GT(touched.size(), 1u) << "interface";
                  ++interface;
                }
              }
          }
          EXPECT_EQ(next, order.size());
          // Bisection planes cut few edges: the interface is a small part, growing
          // with the cuts (on the paper's 682-vertex cube).
          if (shape == "cube") {
            EXPECT_LT(interface, order.size() * static_cast<size_t>(domains - 1) / 10) << domains << " domains";
          }
          RecordProperty(shape + (stretch ? "_stretch_interface_" : "_bending_interface_") + std::to_string(domains),
                         std::to_string(interface) + " of " + std::to_string(order.size()));
        }
        PaddedPoints start = PaddedPoints::Zero(cube.positions.rows(), ConstraintBatches::kPositionStride);
        start.leftCols<3>() = cube.positions;
        Eigen::Matrix<double, -1, 3, Eigen::RowMajor> sequential = cube.positions;
        PaddedPoints one = start;
        batches.project(one.data(), 4, {0.9, 0.7}, {BendingAngle::Unsigned}, isa, nullptr);
        for (int sweep = 0; sweep < 4; ++sweep)
          sequential_sweep<double>(cube, batches, sequential, sweep % 2 == 1, 0.9, 0.7, BendingAngle::Unsigned);
        EXPECT_EQ((one.leftCols<3>() - sequential).cwiseAbs().maxCoeff(), 0.0) << domains << " domains";
        for (int threads : {2, 3, 4}) {
          ThreadTeam team(threads);
          PaddedPoints many = start;
          batches.project(many.data(), 4, {0.9, 0.7}, {BendingAngle::Unsigned}, isa, &team);
          EXPECT_EQ((many - one).cwiseAbs().maxCoeff(), 0.0) << threads << " threads, " << domains << " domains";
        }
      }
    }
  }
  const DisturbedCube cube;
  EXPECT_THROW(ConstraintBatches(cube.constraints, cube.inverse_mass, 4, Precision::Double, std::vector<int>(3, 0)),
               std::invalid_argument);
}

TEST(DomainPartition, BisectionGivesBalancedDeterministicSpatialDomains) {
  const DisturbedCube cube;
  const Eigen::Index n = cube.surface.V.rows();
  for (int domains : {1, 2, 3, 4, 7}) {
    const std::vector<int> d = bisect_into_domains(cube.surface.V, domains);
    ASSERT_EQ(d.size(), static_cast<size_t>(n));
    std::vector<int> size(static_cast<size_t>(domains), 0);
    for (int v : d) {
      ASSERT_GE(v, 0);
      ASSERT_LT(v, domains);
      ++size[static_cast<size_t>(v)];
    }
    EXPECT_LE(*std::max_element(size.begin(), size.end()) - *std::min_element(size.begin(), size.end()), 1);
    EXPECT_EQ(d, bisect_into_domains(cube.surface.V, domains));
  }
  // Two domains: a plane across one axis separates them (every vertex of domain
  // 0 at or below every vertex of domain 1 along it).
  const std::vector<int> two = bisect_into_domains(cube.surface.V, 2);
  bool separated = false;
  for (int axis = 0; axis < 3; ++axis) {
    double domain0_top = -INFINITY, domain1_bottom = INFINITY;
    for (Eigen::Index v = 0; v < n; ++v) {
      if (two[static_cast<size_t>(v)] == 0)
        domain0_top = std::max(domain0_top, cube.surface.V(v, axis));
      else
        domain1_bottom = std::min(domain1_bottom, cube.surface.V(v, axis));
    }
    separated = separated || domain0_top <= domain1_bottom;
  }
  EXPECT_TRUE(separated);
  EXPECT_THROW(bisect_into_domains(cube.surface.V, 0), std::invalid_argument);
  EXPECT_THROW(bisect_into_domains(cube.surface.V, 2, std::vector<double>(3, 1.0)), std::invalid_argument);
  EXPECT_THROW(bisect_into_domains(cube.surface.V, 2, std::vector<double>(static_cast<size_t>(n), -1.0)),
               std::invalid_argument);
}

TEST(DomainPartition, WorkWeightsBalanceTheFreeVerticesNotAllVertices) {
  // A cube 1 % taller than wide, so its longest axis runs through the fixed bottom:
  // by vertex count one domain would hold the bottom face's vertices, which carry no
  // work (the 40 346-vertex cube's split was 40 / 60 % of the constraints so).
  const DisturbedCube cube;
  Points tall = cube.surface.V;
  tall.col(2) *= 1.01;
  std::vector<double> work(static_cast<size_t>(tall.rows()));
  for (Eigen::Index v = 0; v < tall.rows(); ++v) work[static_cast<size_t>(v)] = cube.inverse_mass(v) > 0 ? 1 : 0;
  const int free = static_cast<int>(std::count(work.begin(), work.end(), 1.0));
  ASSERT_LT(free, tall.rows());
  for (int domains : {2, 3, 4}) {
    const std::vector<int> by_count = bisect_into_domains(tall, domains),
                           by_work = bisect_into_domains(tall, domains, work);
    std::vector<int> free_by_count(static_cast<size_t>(domains), 0), free_by_work(static_cast<size_t>(domains), 0);
    for (size_t v = 0; v < work.size(); ++v) {
      free_by_count[static_cast<size_t>(by_count[v])] += work[v] > 0;
      free_by_work[static_cast<size_t>(by_work[v])] += work[v] > 0;
    }
    EXPECT_LE(*std::max_element(free_by_work.begin(), free_by_work.end()) -
                  *std::min_element(free_by_work.begin(), free_by_work.end()),
              1)
        << domains << " domains";
    if (domains == 2) {  // the contrast: by count the bottom half has the fixed face's vertices and less work
      EXPECT_GT(free_by_count[1] - free_by_count[0], free / 20);
    }
  }
  // No work anywhere: split by count.
  EXPECT_EQ(bisect_into_domains(tall, 2, std::vector<double>(work.size(), 0.0)), bisect_into_domains(tall, 2));
}

TEST(ConstraintBatches, ConstraintOnAVertexWithoutInverseMassIsAnError) {
  const DisturbedCube cube;
  const Eigen::VectorXd too_few = cube.inverse_mass.head(10);
  EXPECT_THROW(ConstraintBatches(cube.constraints, too_few), std::invalid_argument);
  // The solver names the problem before the batches see it.
  try {
    Solver(cube.surface, too_few, Settings{});
    ADD_FAILURE() << "no error for 10 inverse masses on " << cube.surface.V.rows() << " vertices";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "inverse masses: one per vertex expected");
  }
}

}  // namespace
}  // namespace tb::pbd
