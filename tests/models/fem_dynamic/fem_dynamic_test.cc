// The dynamic reference (models/fem_dynamic, the implicit Euler of
// numerics/elasticity/newton_solve.cc) against what it must equal: with the linear
// law, the linear recursion (M / h^2 + K) u_{n+1} = f + M / h^2 (u_n + h v_n)
// assembled here from K and a lumped mass computed here; with a nonlinear law, the
// static Newton answer once it has settled, a rigid sphere's contact included; and,
// as a model, reactions that balance the load at the steady state.
#include <gtest/gtest.h>

#include <Eigen/LU>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"
#include "sphere_obstacles.h"
#include "test_support.h"

namespace tb {
namespace {

const Material kMaterial{3000, 0.45, 1000};

/// The lumped mass (3 #V): a quarter of each tet's mass at each of its nodes.
Eigen::VectorXd lumped_mass(const TetMesh& m, double density) {
  Eigen::VectorXd mass = Eigen::VectorXd::Zero(3 * m.V.rows());
  for (Eigen::Index t = 0; t < m.T.rows(); ++t) {
    Eigen::Matrix3d edges;
    for (int k = 0; k < 3; ++k) edges.col(k) = (m.V.row(m.T(t, k + 1)) - m.V.row(m.T(t, 0))).transpose();
    for (int a = 0; a < 4; ++a) mass.segment<3>(3 * m.T(t, a)).array() += density * std::abs(edges.determinant()) / 24;
  }
  return mass;
}

struct CubeBody {
  const HybridMesh& h = testing::scenario_mesh("cube-pull");
  ElasticBody body{h.fine_volume, kMaterial, testing::kCubeBottom.select(h.fine_volume.V)};
  BodyLoads loads{body, {containing_tet(h.fine_volume, {0, 0, 0.1}, "fine volume")}};
};

TEST(FemDynamic, WithTheLinearLawItIsTheLinearImplicitEulerRecursion) {
  const CubeBody c;
  const double h = 0.01;
  Eigen::VectorXd mass;
  c.body.to_free(lumped_mass(c.body.mesh(), kMaterial.density), mass);
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
  double worst = 0, worst_balance = 0;
  Eigen::VectorXd f_int_free;
  for (int step = 0; step < 5; ++step) {
    solve->solve(c.loads, force, u);
    const Eigen::VectorXd rhs = f + (mass.array() / (h * h) * (expected + h * v).array()).matrix();
    const Eigen::VectorXd next = ldlt.solve(rhs);
    v = (next - expected) / h;
    expected = next;
    c.body.to_free(u, u_free);
    worst = std::max(worst, (u_free - expected).norm() / expected.norm());
    // The internal force the reactions are read from carries this step's inertia,
    // M (u_{n+1} - u_n - h v_n) / h^2: on the free dofs it balances the load. (Assembled
    // around the next step's start it would carry -M v_{n+1} / h instead.)
    c.body.to_free(*solve->internal_force(), f_int_free);
    worst_balance = std::max(worst_balance, (f_int_free - f).norm() / f.norm());
  }
  EXPECT_LT(worst, 1e-9);
  EXPECT_LT(worst_balance, 1e-9);
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

/// A rigid sphere pressed 5 mm into the cube's top and held: every implicit-Euler step
/// satisfies the contact's complementarity (no node inside, compressive forces, each
/// node with a force on the sphere; the balance of forces is
/// MomentumBalancesAtEveryStepUnderAMovingGraspAndAMovingSphere's), the first 10 ms
/// step is far from the static answer (the top has not
/// yet moved the whole way), and once settled the state and the sphere's force are the
/// static Newton contact's on the same mesh.
TEST(FemDynamic, WithASphereEveryStepIsInContactAndItSettlesToTheStaticNewtonContact) {
  const CubeBody c;
  const double R = 0.03;
  Eigen::MatrixX3d centre(1, 3);
  centre << 0, 0, 0.1 + R - 0.005;
  const Eigen::VectorXd radius = Eigen::VectorXd::Constant(1, R);
  const Eigen::VectorXd no_force = Eigen::VectorXd::Zero(c.body.free_dofs());
  const auto with_sphere = [&](std::unique_ptr<ElasticSolve> s) {
    s->enable_spheres(c.h.fine_surface_to_volume);
    s->spheres()->set(centre, radius);
    return s;
  };
  // The worst violation of the complementarity of the contact the solve just recorded.
  const auto kkt_violation = [&](ElasticSolve& s, const Eigen::VectorXd& u) {
    double worst = s.spheres()->penetration()[0] / R;
    for (const auto& [node, force] : s.spheres()->node_forces()) {
      const Eigen::Vector3d x = c.body.mesh().V.row(node).transpose() + u.segment<3>(3 * node);
      const Eigen::Vector3d n = (x - centre.row(0).transpose()).normalized();
      worst = std::max(worst, -force.dot(n));                                                        // compressive
      worst = std::max(worst, std::abs((x - centre.row(0).transpose()).norm() - R) / R);             // on the sphere
    }
    return worst;
  };
  auto statically = with_sphere(testing::make_solve(c.body, {{"solver", "newton"}}));
  Eigen::VectorXd u_static;
  statically->solve(no_force, nullptr, u_static);
  const Eigen::Vector3d force_static = statically->spheres()->forces()[0];
  ASSERT_GT(force_static.z(), 0.01) << "the sphere presses the top";

  auto early = with_sphere(make_implicit_euler_solve(c.body, "neo_hookean", 1e-12, 0.01));
  Eigen::VectorXd u_early;
  early->solve(no_force, nullptr, u_early);
  EXPECT_LT(kkt_violation(*early, u_early), 1e-9);
  EXPECT_GT((u_early - u_static).norm(), 0.1 * u_static.norm()) << "the first 10 ms step is a transient";

  // A step long against the cube's slowest period settles it within a few steps.
  auto settling = with_sphere(make_implicit_euler_solve(c.body, "neo_hookean", 1e-12, 0.5));
  Eigen::VectorXd u, previous;
  int steps = 0;
  double worst_kkt = 0;
  do {
    previous = u;
    settling->solve(no_force, nullptr, u);
    worst_kkt = std::max(worst_kkt, kkt_violation(*settling, u));
  } while (++steps < 100 && (steps < 2 || (u - previous).norm() > 1e-13 * u.norm()));
  EXPECT_LT(steps, 100);
  EXPECT_LT(worst_kkt, 1e-9);
  EXPECT_LT((u - u_static).norm(), 1e-8 * u_static.norm());
  EXPECT_LT((settling->spheres()->forces()[0] - force_static).norm(), 1e-8 * force_static.norm());
  RecordProperty("steps_to_settle", steps);
  RecordProperty("sphere_force_z", ::testing::PrintToString(force_static.z()));
}

/// Momentum at every 10 ms step while a grasp lifts the top on one side (3 mm over 10
/// steps, then held) and a sphere presses into the other (4 mm over 10 steps) and
/// slides 10 mm along x (10 more): the lumped mass's total M a, over every node (the
/// held ones included), is the force from outside, minus what the body exerts on
/// the grasp, the support and the sphere. It holds only if the held nodes' reactions
/// carry their inertia M (u_{n+1} - u_n - h v_n) / h^2 and the sphere's multipliers
/// balance the step's inertia as well as its stress.
TEST(FemDynamic, MomentumBalancesAtEveryStepUnderAMovingGraspAndAMovingSphere) {
  const HybridMesh& h = testing::scenario_mesh("cube-pull");
  const TetMesh& m = h.fine_volume;
  PrescribedGroup grasp;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    if ((m.V.row(v) - Eigen::RowVector3d(0.03, 0, 0.1)).norm() < 0.005) grasp.nodes.push_back(static_cast<int>(v));
  ASSERT_GT(grasp.nodes.size(), 0u);
  const ElasticBody body(m, kMaterial, testing::kCubeBottom.select(m.V), {grasp});
  const BodyLoads none(body, {});
  const double step = 0.01, R = 0.02;
  auto solve = make_implicit_euler_solve(body, "neo_hookean", 1e-12, step);
  solve->enable_spheres(h.fine_surface_to_volume);
  ElasticFrame frame(body, none, *solve);
  const Eigen::VectorXd mass = lumped_mass(m, kMaterial.density);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(body.dofs()), previous = u, velocity = u;
  Eigen::MatrixX3d centre(1, 3);
  const Eigen::VectorXd radius = Eigen::VectorXd::Constant(1, R);
  double worst = 0;
  for (int n = 1; n <= 20; ++n) {
    const double ramp = std::min(n, 10) / 10.0, slide = std::clamp(n - 10, 0, 10) / 10.0;
    centre << -0.03 + 0.01 * slide, 0, 0.1 + R + 1e-4 - 0.004 * ramp;
    solve->spheres()->set(centre, radius);
    frame.step({}, {Eigen::Vector3d(0, 0, 0.003 * ramp)}, u);
    const Eigen::VectorXd inertia = (mass.array() * (u - previous - step * velocity).array()).matrix() / (step * step);
    Eigen::Vector3d total_inertia = Eigen::Vector3d::Zero();
    for (Eigen::Index v = 0; v < m.V.rows(); ++v) total_inertia += inertia.segment<3>(3 * v);
    const Eigen::Vector3d on_sphere = solve->spheres()->forces()[0];
    const Eigen::Vector3d imbalance = total_inertia + frame.group_forces()[0] + frame.support_force() + on_sphere;
    const double scale = std::max({frame.group_forces()[0].norm(), on_sphere.norm(), total_inertia.norm()});
    worst = std::max(worst, imbalance.norm() / scale);
    if (n == 10) {
      EXPECT_GT(on_sphere.z(), 0) << "the sphere presses the top";
      EXPECT_GT(total_inertia.norm(), 1e-3 * scale) << "the body accelerates: the balance tests the inertia";
    }
    velocity = (u - previous) / step;
    previous = u;
  }
  EXPECT_LT(worst, 1e-8);
  RecordProperty("worst_momentum_imbalance", ::testing::PrintToString(worst));
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
