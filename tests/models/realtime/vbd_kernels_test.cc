// Vertex Block Descent's batched kernels (a vertex's tets four at a time in vector
// lanes, models/numerics/realtime/vbd_visit_blocks.h) against its scalar ones: the
// same frames give the same positions to round-off, with AVX2 and with SSE2, under a
// point force, under a plate whose move inverts tets unless staged, and around a
// vertex in more tets than the kernels cache (their positivity check recomputes F
// there). And a law without batched node terms refuses the lanes with a one-line
// error.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"
#include "mesh_checks.h"
#include "settled_cube.h"
#include "test_support.h"
#include "vbd_solve.h"

namespace tb {
namespace {

using testing::kMaterial;
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
  const SmallCube c;
  const ElasticBody body(c.mesh, kMaterial, c.clamped());
  const BodyLoads loads(body, {containing_tet(c.mesh, {c.a / 2, c.a / 2, c.a}, "cube")});
  const std::vector<Eigen::Vector3d> force = {Eigen::Vector3d(0, 0, 0.2)};
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

}  // namespace
}  // namespace tb
