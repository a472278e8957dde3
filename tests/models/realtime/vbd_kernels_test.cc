// Vertex Block Descent's batched kernels (a vertex's tets four at a time in vector
// lanes, models/numerics/realtime/vbd_visit_blocks.h) against its scalar ones: the
// same frames give the same positions to round-off, with AVX2 and with SSE2, under a
// point force, under a plate whose move inverts tets unless staged, and around a
// vertex in more tets than the kernels cache (their positivity check recomputes F
// there). The kernels themselves on random tets against the law's scalar node terms,
// and their positivity checks at a step that crosses the smallest det F allowed;
// lanes::log as VBD compiles it (AVX2 with FMA) against the C library. And a law
// without batched node terms refuses the lanes with a one-line error, as a CPU without
// AVX2 refuses the AVX2 lanes.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <string>
#include <vector>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "lame_parameters.h"
#include "load_mapping.h"
#include "mesh_checks.h"
#include "settled_cube.h"
#include "test_support.h"
#include "neo_hookean.h"
#include "tet_element.h"
#include "vbd_solve.h"
#include "vbd_visit_blocks.h"

namespace tb {
namespace {

using testing::kMaterial;
using testing::PulledSmallCube;
using testing::SmallCube;

bool cpu_has_avx2() { return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma"); }

std::vector<VbdKernels> lane_kernels() {
  std::vector<VbdKernels> k = {VbdKernels::Sse2};
  if (cpu_has_avx2()) k.push_back(VbdKernels::Avx2);
  return k;
}

/// u after `frames` frames of VBD with `kernels`, the force and the groups' moves held.
Eigen::VectorXd run(const ElasticBody& body, const BodyLoads& loads, VbdKernels kernels,
                    const std::vector<Eigen::Vector3d>& force, const std::vector<Eigen::Vector3d>& moves, int frames,
                    std::string* ran = nullptr, int* stages = nullptr) {
  VbdSettings o;
  o.kernels = kernels;
  auto vbd = make_vbd_solve(body, o);
  ElasticFrame frame(body, loads, *vbd);
  Eigen::VectorXd u;
  for (int f = 0; f < frames; ++f) frame.step(force, moves, u);
  if (ran) *ran = vbd->report()["kernels"].get<std::string>();
  if (stages) *stages = vbd->report()["stages_last_frame"].get<int>();
  return u;
}

double relative(const Eigen::VectorXd& a, const Eigen::VectorXd& b) { return (a - b).norm() / b.norm(); }

TEST(VbdKernels, LanesGiveTheScalarAnswerUnderAPointForce) {
  const PulledSmallCube pulled;
  const auto& [c, body, loads, force] = pulled;
  std::string ran;
  const Eigen::VectorXd scalar = run(body, loads, VbdKernels::Scalar, force, {}, 20, &ran);
  EXPECT_EQ(ran, "scalar");
  ASSERT_GT(scalar.norm(), 1e-3 * c.a);
  for (VbdKernels k : lane_kernels()) {
    const Eigen::VectorXd lanes = run(body, loads, k, force, {}, 20, &ran);
    EXPECT_EQ(ran, k == VbdKernels::Avx2 ? "avx2" : "sse2");
    EXPECT_LT(relative(lanes, scalar), 1e-12) << ran;
  }
  // Auto takes lanes for neo_hookean, the best this CPU has.
  run(body, loads, VbdKernels::Auto, force, {}, 1, &ran);
  EXPECT_EQ(ran, cpu_has_avx2() ? "avx2" : "sse2");
}

TEST(VbdKernels, LanesGiveTheScalarAnswerWhereTheToolsMoveInStages) {
  const SmallCube c;
  const ElasticBody body(c.mesh, kMaterial, c.clamped(), c.top_plate());
  const BodyLoads none(body, {});
  const std::vector<Eigen::Vector3d> crush = {Eigen::Vector3d(0, 0, -0.4 * c.a)};
  int stages = 0;
  const Eigen::VectorXd scalar = run(body, none, VbdKernels::Scalar, {}, crush, 1, nullptr, &stages);
  ASSERT_GT(stages, 1);  // the step halvings and the positivity check are exercised
  for (VbdKernels k : lane_kernels()) {
    int lane_stages = 0;
    const Eigen::VectorXd lanes = run(body, none, k, {}, crush, 1, nullptr, &lane_stages);
    EXPECT_EQ(lane_stages, stages);
    EXPECT_LT(relative(lanes, scalar), 1e-12);
  }
}

/// A bicone: a centre node in 2 n tets, the n-gon around it and two apexes; the
/// n-gon clamped, the top apex one prescribed group.
TetMesh bicone(int n, double radius, double height) {
  TetMesh m;
  m.V.resize(n + 3, 3);
  m.V.row(0) << 0, 0, 0;
  m.V.row(1) << 0, 0, height;
  m.V.row(2) << 0, 0, -height;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * M_PI * i / n;
    m.V.row(3 + i) << radius * std::cos(t), radius * std::sin(t), 0;
  }
  m.T.resize(2 * n, 4);
  for (int i = 0; i < n; ++i) {
    const int a = 3 + i, b = 3 + (i + 1) % n;
    m.T.row(2 * i) << 0, a, b, 1;      // positive: the apex above the turning n-gon
    m.T.row(2 * i + 1) << 0, b, a, 2;  // and below it, turned the other way
  }
  return m;
}

TEST(VbdKernels, LanesGiveTheScalarAnswerAroundAVertexInMoreTetsThanCached) {
  const int n = 60;  // the centre in 120 tets: 30 blocks, beyond the 24 the kernels cache
  const TetMesh mesh = bicone(n, 0.03, 0.02);
  for (Eigen::Index t = 0; t < mesh.T.rows(); ++t)
    ASSERT_GT(tet_volume(mesh.V.row(mesh.T(t, 0)).transpose(), mesh.V.row(mesh.T(t, 1)).transpose(),
                         mesh.V.row(mesh.T(t, 2)).transpose(), mesh.V.row(mesh.T(t, 3)).transpose()),
              0)
        << "tet " << t;
  std::vector<char> clamped(static_cast<size_t>(mesh.V.rows()), 0);
  for (int i = 0; i < n; ++i) clamped[static_cast<size_t>(3 + i)] = 1;
  PrescribedGroup apex;
  apex.nodes = {1};
  const ElasticBody body(mesh, kMaterial, clamped, {apex});
  const BodyLoads none(body, {});
  // The apex pressed to a quarter of its height: the centre's tets above it flatten.
  const std::vector<Eigen::Vector3d> press = {Eigen::Vector3d(0, 0, -0.015)};
  const Eigen::VectorXd scalar = run(body, none, VbdKernels::Scalar, {}, press, 10);
  ASSERT_GT(std::abs(scalar(2)), 1e-4);  // the centre (node 0) moved
  for (VbdKernels k : lane_kernels()) EXPECT_LT(relative(run(body, none, k, {}, press, 10), scalar), 1e-12);
}

/// Tets around one vertex (node 0 of each), deformed at random but positive, in
/// blocks as vbd_solve.cc lays them out: `count` real tets, the last block padded.
struct KernelCase {
  NeoHookean law{lame_parameters(Material{3000, 0.45, 1000})};
  Eigen::Matrix3Xd x;  // node 0 the vertex, then three nodes per tet
  std::vector<VisitBlock> blocks;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();  // the scalar node terms' sums
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  std::vector<Eigen::Vector4d> cof_g_and_J;  // per tet
  explicit KernelCase(int count, unsigned seed) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> U(-0.3, 0.3);
    x.resize(3, 1 + 3 * count);
    x.col(0).setZero();
    blocks.resize(static_cast<size_t>((count + kVisitLanes - 1) / kVisitLanes));
    for (int t = 0; t < count; ++t) {
      // A rest tet scaled to 1 cm, and its nodes moved by up to 30 % of that.
      const Eigen::Vector3d X[4] = {{0, 0, 0}, {0.01, 0, 0}, {0, 0.01, 0}, {0, 0, 0.01}};
      const TetShape shape = tet_shape(X[0], X[1], X[2], X[3]);
      Eigen::Matrix<double, 3, 4> at;
      at.col(0) = x.col(0);
      for (int j = 1; j < 4; ++j) {
        at.col(j) = X[j] + 0.01 * Eigen::Vector3d(U(rng), U(rng), U(rng));
        x.col(1 + 3 * t + j - 1) = at.col(j);
      }
      VisitBlock& b = blocks[static_cast<size_t>(t / kVisitLanes)];
      const int l = t % kVisitLanes;
      for (int j = 1; j < 4; ++j)
        for (int i = 0; i < 3; ++i) b.g[j][i][l] = shape.gradients(i, j);
      for (int i = 0; i < 3; ++i) b.g[0][i][l] = -(b.g[1][i][l] + b.g[2][i][l] + b.g[3][i][l]);
      for (int j = 0; j < 3; ++j) b.other[j][l] = 1 + 3 * t + j;
      b.volume[l] = shape.volume;
      const Eigen::Vector3d g0(b.g[0][0][l], b.g[0][1][l], b.g[0][2][l]);
      Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
      for (int j = 1; j < 4; ++j) F += (at.col(j) - at.col(0)) * shape.gradients.col(j).transpose();
      const NodeTerms terms = law.node_terms(F, g0);
      gradient += shape.volume * terms.force;
      H += shape.volume * terms.stiffness;
      cof_g_and_J.push_back((Eigen::Vector4d() << terms.cof_g, terms.J).finished());
    }
    for (int t = count; t < kVisitLanes * static_cast<int>(blocks.size()); ++t) {
      VisitBlock& b = blocks.back();
      const int l = t % kVisitLanes;
      b.empty[l] = 1;  // g, volume 0; the vertex itself as the other nodes
    }
  }
};

/// What the kernels give on a KernelCase: the sums, and the two positivity checks
/// (cached determinants, recomputed F) at each step in `steps`.
struct KernelAnswer {
  int bad = 0;
  Eigen::Vector3d gradient = Eigen::Vector3d::Zero();
  Eigen::Matrix3d H = Eigen::Matrix3d::Zero();
  std::vector<char> cached, recomputed;
};
template <class L>
[[gnu::always_inline]] inline KernelAnswer run_kernels(const KernelCase& c, const std::vector<Eigen::Vector3d>& steps,
                                                      double bound) {
  KernelAnswer a;
  const int count = static_cast<int>(c.blocks.size());
  std::vector<BlockDeterminants<L>> dets(c.blocks.size());  // on the heap: the alignment tested
  a.bad = add_block_terms<L>(c.law, c.blocks.data(), count, c.x.data(), c.x.col(0), a.gradient, a.H, dets.data());
  for (const Eigen::Vector3d& dx : steps) {
    a.cached.push_back(blocks_stay_above<L>(dets.data(), count, dx, bound));
    a.recomputed.push_back(blocks_above_at<L>(c.blocks.data(), count, c.x.data(), c.x.col(0) + dx, bound));
  }
  return a;
}
KernelAnswer run_sse2(const KernelCase& c, const std::vector<Eigen::Vector3d>& steps, double bound) {
  return run_kernels<pbd::batches::SseLanes>(c, steps, bound);
}
__attribute__((target("avx2,fma"))) KernelAnswer run_avx2(const KernelCase& c, const std::vector<Eigen::Vector3d>& steps,
                                                          double bound) {
  return run_kernels<pbd::lanes::Vector<double, 4>>(c, steps, bound);
}

TEST(VbdKernels, BlockSumsEqualTheLawsScalarNodeTermsAndTheChecksSeeTheSmallestDeterminant) {
  for (int count : {1, 2, 3, 4, 5, 23}) {  // a padded block, full ones, and a vertex's typical 23
    const KernelCase c(count, 7u + static_cast<unsigned>(count));
    // Steps: none, a small one, and along a direction d to 0.99 and 1.01 times the
    // first crossing of det F = bound by any tet (det F + alpha d . cof(F) g = bound):
    // the last two must be taken and refused.
    const double bound = 1e-3;
    const Eigen::Vector3d d = -c.cof_g_and_J[0].head<3>().normalized();  // tet 0's det F falls along it
    double alpha = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector4d& e : c.cof_g_and_J)
      if (d.dot(e.head<3>()) < 0) alpha = std::min(alpha, (e(3) - bound) / -d.dot(e.head<3>()));
    ASSERT_TRUE(std::isfinite(alpha)) << count;
    const std::vector<Eigen::Vector3d> steps = {Eigen::Vector3d::Zero(), 1e-5 * Eigen::Vector3d(1, -2, 0.5),
                                                0.99 * alpha * d, 1.01 * alpha * d};
    const std::vector<char> expected = {1, 1, 1, 0};
    std::vector<KernelAnswer> answers = {run_sse2(c, steps, bound)};
    if (cpu_has_avx2()) answers.push_back(run_avx2(c, steps, bound));
    for (const KernelAnswer& a : answers) {
      EXPECT_EQ(a.bad, -1) << count;
      EXPECT_LT((a.gradient - c.gradient).norm(), 1e-12 * c.gradient.norm()) << count;
      EXPECT_LT((a.H - c.H).norm(), 1e-12 * c.H.norm()) << count;
      EXPECT_LT((a.H - a.H.transpose()).norm(), 1e-15 * a.H.norm()) << count;
      EXPECT_EQ(a.cached, expected) << count;
      EXPECT_EQ(a.recomputed, expected) << count;
    }
  }
}

TEST(VbdKernels, AnInvertedTetIsReportedByItsLane) {
  KernelCase c(6, 11u);
  // Tet 5 (block 1, lane 1): its first other node moved through the opposite face.
  VisitBlock& b = c.blocks[1];
  const int node = b.other[0][1];
  c.x.col(node) = -c.x.col(node);
  const KernelAnswer a = run_sse2(c, {}, 0);
  EXPECT_EQ(a.bad, kVisitLanes * 1 + 1);
  if (cpu_has_avx2()) {
    EXPECT_EQ(run_avx2(c, {}, 0).bad, kVisitLanes * 1 + 1);
  }
}

/// The largest distance from the C library's log, in ulps, of lanes::log compiled as
/// VBD's lanes are (AVX2 with FMA contraction), over normal and subnormal numbers.
__attribute__((target("avx2,fma"))) double worst_log_ulps_avx2() {
  using V = pbd::lanes::Vector<double, 4>;
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> E(-700, 700), Near1(-1e-3, 1e-3), Sub(0, 1);
  double worst = 0;
  for (int trial = 0; trial < 50000; ++trial) {
    V x;
    x[0] = std::exp(E(rng));
    x[1] = 1 + Near1(rng);
    x[2] = std::numeric_limits<double>::min() * Sub(rng) + std::numeric_limits<double>::denorm_min();  // subnormal
    x[3] = std::exp(E(rng) / 100);
    const V r = pbd::lanes::log(x);
    for (int l = 0; l < 4; ++l) {
      const double exact = std::log(x[l]);
      worst = std::max(worst, std::abs(r[l] - exact) / (std::nextafter(std::abs(exact), INFINITY) - std::abs(exact)));
    }
  }
  return worst;
}

TEST(VbdKernels, LogWithAvx2AndFmaIsWithinTwoUlpsOfTheCLibrary) {
  if (!cpu_has_avx2()) GTEST_SKIP() << "this CPU has no AVX2 and FMA";
  const double worst = worst_log_ulps_avx2();
  EXPECT_LE(worst, 2.0);
  RecordProperty("max_ulps", std::to_string(worst));
}

TEST(VbdKernels, ALawWithoutLanesRefusesThemInOneLine) {
  const SmallCube c;
  const ElasticBody body(c.mesh, kMaterial, c.clamped());
  VbdSettings o;
  o.law = "stable_neo_hookean";
  o.kernels = VbdKernels::Sse2;
  try {
    make_vbd_solve(body, o);
    ADD_FAILURE() << "sse2 lanes accepted for stable_neo_hookean";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("vbd: kernels sse2 need a law with batched node terms"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  o.kernels = VbdKernels::Auto;  // auto falls back to the scalar kernels
  EXPECT_EQ(make_vbd_solve(body, o)->report()["kernels"].get<std::string>(), "scalar");
}

// The choice on a CPU without AVX2 and FMA, whatever this one has: auto takes SSE2
// (or the scalar sum for a law without lanes), an explicit avx2 is refused in one
// line, sse2 and scalar run as asked.
TEST(VbdKernels, ACpuWithoutAvx2GetsSse2ForAutoAndRefusesAvx2InOneLine) {
  const std::string law = "neo_hookean";
  EXPECT_EQ(choose_vbd_kernels(VbdKernels::Auto, true, law, false), VbdKernels::Sse2);
  EXPECT_EQ(choose_vbd_kernels(VbdKernels::Auto, true, law, true), VbdKernels::Avx2);
  EXPECT_EQ(choose_vbd_kernels(VbdKernels::Auto, false, law, false), VbdKernels::Scalar);
  EXPECT_EQ(choose_vbd_kernels(VbdKernels::Sse2, true, law, false), VbdKernels::Sse2);
  EXPECT_EQ(choose_vbd_kernels(VbdKernels::Scalar, true, law, false), VbdKernels::Scalar);
  try {
    choose_vbd_kernels(VbdKernels::Avx2, true, law, false);
    ADD_FAILURE() << "avx2 accepted on a CPU without it";
  } catch (const std::invalid_argument& e) {
    const std::string what = e.what();
    EXPECT_EQ(what, "vbd: kernels avx2: this CPU has no AVX2 and FMA");
  }
}

}  // namespace
}  // namespace tb
