// The dynamic reference (models/fem_dynamic, the implicit Euler of
// numerics/elasticity/newton_solve.cc) against what it must equal: with the linear
// law, the linear recursion (M / h^2 + K) u_{n+1} = f + M / h^2 (u_n + h v_n)
// assembled here from K and a lumped mass computed here; with a nonlinear law, the
// static Newton answer once it has settled; and, as a model, reactions that balance
// the load at the steady state.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <cmath>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"
#include "test_support.h"

namespace tb {
namespace {

const Material kMaterial{3000, 0.45, 1000};

struct CubeBody {
  const HybridMesh& h = testing::scenario_mesh("cube-pull");
  ElasticBody body{h.fine_volume, kMaterial, testing::kCubeBottom.select(h.fine_volume.V)};
  BodyLoads loads{body, {containing_tet(h.fine_volume, {0, 0, 0.1}, "fine volume")}};
};

TEST(FemDynamic, WithTheLinearLawItIsTheLinearImplicitEulerRecursion) {
  const CubeBody c;
  const double h = 0.01;
  const TetMesh& m = c.body.mesh();
  // The lumped mass: a quarter of each tet's mass at each of its nodes.
  Eigen::VectorXd mass_full = Eigen::VectorXd::Zero(c.body.dofs()), mass;
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    Eigen::Matrix3d edges;
    for (int k = 0; k < 3; ++k) edges.col(k) = (m.V.row(m.T(t, k + 1)) - m.V.row(m.T(t, 0))).transpose();
    for (int a = 0; a < 4; ++a) mass_full.segment<3>(3 * m.T(t, a)).array() += kMaterial.density * std::abs(edges.determinant()) / 24;
  }
  c.body.to_free(mass_full, mass);
  const Eigen::SparseMatrix<double> K = c.body.free_stiffness();
  Eigen::SparseMatrix<double> A = K;
  for (Eigen::Index d = 0; d < A.rows(); ++d) A.coeffRef(d, d) += mass(d) / (h * h);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(A);
  ASSERT_EQ(ldlt.info(), Eigen::Success);

  auto solve = make_implicit_euler_solve(c.body, "linear", 1e-13, h);
  Eigen::VectorXd u, f, u_free, expected = Eigen::VectorXd::Zero(c.body.free_dofs()),
                               v = Eigen::VectorXd::Zero(c.body.free_dofs());
  const std::vector<Eigen::Vector3d> force = {Eigen::Vector3d(0, 0, 1)};
  c.loads.assemble(force, f);
  double worst = 0;
  for (int step = 0; step < 5; ++step) {
    solve->solve(c.loads, force, u);
    const Eigen::VectorXd rhs = f + (mass.array() / (h * h) * (expected + h * v).array()).matrix();
    const Eigen::VectorXd next = ldlt.solve(rhs);
    v = (next - expected) / h;
    expected = next;
    c.body.to_free(u, u_free);
    worst = std::max(worst, (u_free - expected).norm() / expected.norm());
  }
  EXPECT_LT(worst, 1e-9);
  RecordProperty("worst_relative_difference_5_steps", ::testing::PrintToString(worst));
}

TEST(FemDynamic, ANeoHookeanBodySettlesToTheStaticNewtonAnswer) {
  const CubeBody c;
  const std::vector<Eigen::Vector3d> force = {Eigen::Vector3d(0, 0, 0.5)};
  Eigen::VectorXd u_static, u, previous;
  testing::make_solve(c.body, {{"solver", "newton"}, {"newton_load_steps", 2}})->solve(c.loads, force, u_static);
  // A step long against the cube's slowest period (about 0.4 s) damps it within a few steps.
  auto dynamic = make_implicit_euler_solve(c.body, "neo_hookean", 1e-12, 0.5);
  int steps = 0;
  do {
    previous = u;
    dynamic->solve(c.loads, force, u);
  } while (++steps < 200 && (steps < 2 || (u - previous).norm() > 1e-13 * u.norm()));
  EXPECT_LT(steps, 200);
  EXPECT_LT((u - u_static).norm(), 1e-8 * u_static.norm());
  // Before it settles it is not the static answer: the transient is there to score.
  auto early = make_implicit_euler_solve(c.body, "neo_hookean", 1e-12, 0.05);
  early->solve(c.loads, force, previous);
  EXPECT_GT((previous - u_static).norm(), 0.1 * u_static.norm());
  RecordProperty("steps_to_settle", steps);
}

TEST(FemDynamic, AsAModelItIsDynamicAndItsReactionsBalanceTheLoadOnceSettled) {
  const ModelInfo& info = find_model("fem_dynamic");
  EXPECT_TRUE(info.dynamic);
  const HybridMesh& h = testing::scenario_mesh("cube-pull");
  auto model = testing::set_up_model("fem_dynamic", h, testing::kCubeBottom, {{"time_step", 0.5}},
                                     testing::kCubePull.scaled(0.5).loads());
  const FrameLoads frame = testing::kCubePull.scaled(0.5).frame();
  for (int k = 0; k < 30; ++k) model->step(frame);
  const std::vector<Eigen::Vector3d>& reactions = *model->reaction_forces();
  ASSERT_EQ(reactions.size(), 1u);  // the support's
  // The force the tissue exerts on the support is the load it carries.
  EXPECT_LT((reactions[0] - Eigen::Vector3d(0, 0, 0.5)).norm(), 1e-6 * 0.5);
}

}  // namespace
}  // namespace tb
