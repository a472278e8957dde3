// The batched PBD sweep against one-at-a-time projection, and the vectorised
// atan2 against the C library (issue 5: the sweep's speed must not change its
// numbers).
#include "constraint_batches.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "pbd_solver.h"
#include "projection_kernels.h"
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

/// The cube's surface, randomly disturbed, with its bottom fixed.
struct DisturbedCube {
  const SurfaceMesh& surface = testing::scenario_mesh("cube-pull", false).fine_surface;
  ConstraintSet constraints = build_constraints(surface);
  Eigen::VectorXd inverse_mass;
  Points positions;
  DisturbedCube() {
    std::vector<char> fixed(static_cast<size_t>(surface.V.rows()));
    for (Eigen::Index v = 0; v < surface.V.rows(); ++v) fixed[static_cast<size_t>(v)] = surface.V(v, 2) == 0.0;
    inverse_mass = inverse_masses(surface, 1000, fixed);
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> U(-0.002, 0.002);  // 20% of an edge
    positions = surface.V;
    for (Eigen::Index i = 0; i < positions.size(); ++i) positions.data()[i] += U(rng);
  }
};

/// One forward or reverse sweep as plain Gauss-Seidel: project_stretch and
/// project_bending on one constraint at a time, in the batches' order.
void sequential_sweep(const DisturbedCube& c, const ConstraintBatches& b, Points& x, bool reverse, double ks, double kb,
                      BendingAngle kind) {
  auto P = [&x](int v) { return Eigen::Map<Vec3>(x.data() + 3 * static_cast<Eigen::Index>(v)); };
  const Eigen::VectorXd& w = c.inverse_mass;
  const std::vector<int>& so = b.stretch_order();
  for (size_t k = 0; k < so.size(); ++k) {
    const int i = so[reverse ? so.size() - 1 - k : k];
    const int a = c.constraints.stretch(i, 0), d = c.constraints.stretch(i, 1);
    Vec3 ca, cd;
    project_stretch(P(a), w(a), P(d), w(d), c.constraints.stretch_rest(i), ks, ca, cd);
    P(a) += ca;
    P(d) += cd;
  }
  const std::vector<int>& bo = b.bending_order();
  for (size_t k = 0; k < bo.size(); ++k) {
    const int i = bo[reverse ? bo.size() - 1 - k : k];
    int q[4];
    for (int j = 0; j < 4; ++j) q[j] = c.constraints.bending(i, j);
    Vec3 corr[4];
    project_bending(P(q[0]), w(q[0]), P(q[1]), w(q[1]), P(q[2]), w(q[2]), P(q[3]), w(q[3]),
                    c.constraints.bending_rest(i), kb, corr, kind);
    for (int j = 0; j < 4; ++j) P(q[j]) += corr[j];
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

TEST(ConstraintBatches, EveryMovableConstraintIsProjectedOnce) {
  const DisturbedCube cube;
  const ConstraintBatches batches(cube.constraints, cube.inverse_mass);
  expect_every_movable_constraint_once(cube.constraints.stretch, batches.stretch_order(), cube.inverse_mass);
  expect_every_movable_constraint_once(cube.constraints.bending, batches.bending_order(), cube.inverse_mass);
  // Batches are mostly full: the colouring leaves few partial ones.
  const size_t full = (batches.stretch_order().size() + ConstraintBatches::kWidth - 1) / ConstraintBatches::kWidth;
  EXPECT_LT(batches.stretch_batch_count(), full + full / 10);
  RecordProperty("stretch_batches", std::to_string(batches.stretch_batch_count()));
  RecordProperty("bending_batches", std::to_string(batches.bending_batch_count()));
}

TEST(ConstraintBatches, SweepEqualsOneAtATimeProjectionBitwiseOnEveryInstructionSet) {
  const DisturbedCube cube;
  const ConstraintBatches batches(cube.constraints, cube.inverse_mass);
  std::vector<InstructionSet> sets = {InstructionSet::Sse2};
  if (best_instruction_set() == InstructionSet::Avx) sets.push_back(InstructionSet::Avx);
  for (BendingAngle kind : {BendingAngle::Unsigned, BendingAngle::Signed})
    for (InstructionSet isa : sets) {
      Points sequential = cube.positions;
      PaddedPoints batched = PaddedPoints::Zero(sequential.rows(), ConstraintBatches::kPositionStride);
      batched.leftCols<3>() = cube.positions;
      for (int sweep = 0; sweep < 4; ++sweep) {  // forward, reverse, forward, reverse
        batches.sweep(batched.data(), sweep % 2 == 1, 0.9, 0.7, kind, isa);
        sequential_sweep(cube, batches, sequential, sweep % 2 == 1, 0.9, 0.7, kind);
      }
      EXPECT_GT((batched.leftCols<3>() - cube.positions).cwiseAbs().maxCoeff(), 1e-4);  // it did move
      EXPECT_EQ((batched.leftCols<3>() - sequential).cwiseAbs().maxCoeff(), 0.0) << name(isa);
    }
}

/// Within each colour (batches [begin[c], begin[c + 1])), no vertex is used by two
/// constraints: what lets threads split a colour. Returns the colour count.
template <int N, class Rows>
size_t expect_colours_independent(const std::vector<ConstraintBatches::Batch<N>>& batches,
                                  const std::vector<size_t>& begin, const std::vector<int>& order, const Rows& vertices,
                                  Eigen::Index vertex_count) {
  EXPECT_EQ(begin.front(), 0u);
  EXPECT_EQ(begin.back(), batches.size());
  size_t next = 0;  // position in `order` of the current batch's lane 0
  for (size_t c = 0; c + 1 < begin.size(); ++c) {
    std::vector<char> used(static_cast<size_t>(vertex_count), 0);
    for (size_t b = begin[c]; b < begin[c + 1]; ++b) {
      EXPECT_GT(batches[b].count, 0);
      for (int l = 0; l < batches[b].count; ++l, ++next)
        for (int j = 0; j < N; ++j) {
          const int v = vertices(order[next], j);
          EXPECT_EQ(batches[b].q[j][l], v);
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
  const ConstraintBatches batches(cube.constraints, cube.inverse_mass);
  const Eigen::Index n = cube.surface.V.rows();
  const size_t stretch_colours = expect_colours_independent(batches.stretch_batches(), batches.stretch_colour_begin(),
                                                            batches.stretch_order(), cube.constraints.stretch, n);
  const size_t bending_colours = expect_colours_independent(batches.bending_batches(), batches.bending_colour_begin(),
                                                            batches.bending_order(), cube.constraints.bending, n);
  RecordProperty("stretch_colours", std::to_string(stretch_colours));
  RecordProperty("bending_colours", std::to_string(bending_colours));
}

TEST(ConstraintBatches, ProjectionIsBitwiseTheSameOnAnyNumberOfThreads) {
  const DisturbedCube cube;
  const ConstraintBatches batches(cube.constraints, cube.inverse_mass);
  PaddedPoints start = PaddedPoints::Zero(cube.positions.rows(), ConstraintBatches::kPositionStride);
  start.leftCols<3>() = cube.positions;
  for (InstructionSet isa : {InstructionSet::Sse2, best_instruction_set()}) {
    PaddedPoints one = start;
    batches.project(one.data(), 6, 0.9, 0.7, BendingAngle::Unsigned, isa, nullptr);
    // The same as six single sweeps, alternating direction.
    PaddedPoints swept = start;
    for (int it = 0; it < 6; ++it) batches.sweep(swept.data(), it % 2 == 1, 0.9, 0.7, BendingAngle::Unsigned, isa);
    EXPECT_EQ((one - swept).cwiseAbs().maxCoeff(), 0.0);
    for (int threads : {1, 2, 3, 5}) {
      ThreadTeam team(threads);
      PaddedPoints many = start;
      for (int repeat = 0; repeat < 3; ++repeat) {  // the team is reused
        many = start;
        batches.project(many.data(), 6, 0.9, 0.7, BendingAngle::Unsigned, isa, &team);
      }
      EXPECT_EQ((many - one).cwiseAbs().maxCoeff(), 0.0) << threads << " threads, " << name(isa);
    }
  }
}

TEST(ConstraintBatches, SolverResultDoesNotDependOnItsThreadCount) {
  const DisturbedCube cube;
  const int load_vertex = nearest_vertex(cube.surface.V, Vec3(0, 0, 0.1));
  Points reference;
  for (int threads : {1, 2, 4}) {
    Settings s;
    s.threads = threads;
    Solver solver(cube.surface, cube.inverse_mass, s);
    // Pins as in the hybrid: a few vertices moved each frame.
    const std::vector<int> pinned = {load_vertex + 1, load_vertex + 2};
    Points pinned_positions(2, 3);
    for (int f = 0; f < 30; ++f) {
      for (int k = 0; k < 2; ++k)
        pinned_positions.row(k) =
            cube.surface.V.row(pinned[static_cast<size_t>(k)]) + Eigen::RowVector3d(0, 0, 1e-4 * f);
      solver.step(load_vertex, Vec3(0, 0, 1), pinned, pinned_positions);
    }
    if (threads == 1)
      reference = solver.positions();
    else
      EXPECT_EQ((solver.positions() - reference).cwiseAbs().maxCoeff(), 0.0) << threads << " threads";
    EXPECT_EQ(solver.details()["threads"], threads);
  }
  EXPECT_GT((reference - cube.surface.V).cwiseAbs().maxCoeff(), 1e-4);
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
