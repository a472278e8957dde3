// The static Newton solve with a budget of k iterations a frame
// (newton_max_iterations_per_frame, newton_solve.cc): a frame continues Newton's
// iteration from the last frame's iterate, so under a constant load k frames of
// budget 1 are one frame of budget k, and one frame of budget N (the iterations the
// unbudgeted solve takes) is the unbudgeted answer; its reported residual falls
// every frame until converged, and then the answer is the converged one to 1e-10;
// a plate's move is carried by the first iteration (the plate where it is put, every
// frame). And its parameter's errors.
#include <gtest/gtest.h>

#include <limits>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"
#include "models/realtime/settled_cube.h"
#include "tet_element.h"
#include "test_support.h"

namespace tb {
namespace {

using Cube = testing::SmallCube;  // 4 cm, clamped at z = 0, E = 3 kPa, nu = 0.45
using testing::kMaterial;
constexpr double a = Cube::a;

std::unique_ptr<ElasticSolve> newton(const ElasticBody& body, int budget, double tolerance = 1e-10) {
  return testing::make_solve(body, {{"solver", "newton"},
                                    {"material_law", "neo_hookean"},
                                    {"newton_tolerance", tolerance},
                                    {"newton_max_iterations_per_frame", budget}});
}

double relative_residual(const ElasticSolve& s) { return s.report().at("relative_residual_last_solve").get<double>(); }
bool converged(const ElasticSolve& s) { return s.report().at("converged_last_solve").get<bool>(); }

// 0.3 N up at the top centre: about a quarter of the height, several Newton iterations.
struct PointPull : ::testing::Test {
  Cube c;
  ElasticBody body{c.mesh, kMaterial, c.clamped()};
  BodyLoads loads{body, {containing_tet(c.mesh, {a / 2, a / 2, a}, "cube")}};
  std::vector<Eigen::Vector3d> force = {Eigen::Vector3d(0, 0, 0.3)};
};

TEST_F(PointPull, KFramesOfOneIterationAreOneFrameOfK) {
  for (int k : {2, 3}) {
    auto one = newton(body, 1), many = newton(body, k);
    ElasticFrame by_one(body, loads, *one), at_once(body, loads, *many);
    Eigen::VectorXd u_one, u_many;
    for (int f = 0; f < k; ++f) {
      by_one.step(force, {}, u_one);
      EXPECT_EQ(one->last_iterations(), 1);
    }
    at_once.step(force, {}, u_many);
    EXPECT_EQ(many->last_iterations(), k);
    EXPECT_LT((u_one - u_many).norm(), 1e-14 * u_many.norm()) << k;
    EXPECT_EQ(relative_residual(*one), relative_residual(*many)) << k;
  }
}

TEST_F(PointPull, TheUnbudgetedIterationCountAsABudgetIsTheUnbudgetedAnswer) {
  auto full = newton(body, 0);
  Eigen::VectorXd expected;
  ElasticFrame(body, loads, *full).step(force, {}, expected);
  const int n = full->last_iterations();
  ASSERT_GE(n, 3);
  auto exact = newton(body, n), short_of_it = newton(body, n - 1);
  Eigen::VectorXd u, u_short;
  ElasticFrame(body, loads, *exact).step(force, {}, u);
  ElasticFrame(body, loads, *short_of_it).step(force, {}, u_short);
  EXPECT_LT((u - expected).norm(), 1e-14 * expected.norm());
  EXPECT_GT((u_short - expected).norm(), 1e-10 * expected.norm());
  EXPECT_FALSE(converged(*short_of_it));
  RecordProperty("unbudgeted_newton_iterations", n);
}

TEST_F(PointPull, ResidualFallsEveryFrameToConvergenceAndThenIsTheConvergedAnswer) {
  auto reference = newton(body, 0, 1e-12);
  Eigen::VectorXd expected;
  ElasticFrame(body, loads, *reference).step(force, {}, expected);
  auto one = newton(body, 1);
  ElasticFrame frame(body, loads, *one);
  Eigen::VectorXd u;
  double last = std::numeric_limits<double>::infinity();
  std::string residuals;
  for (int f = 1; f <= 30; ++f) {
    frame.step(force, {}, u);
    const double r = relative_residual(*one);
    residuals += ::testing::PrintToString(r) + " ";
    EXPECT_LT(r, last) << "frame " << f;
    last = r;
    if (converged(*one)) break;
  }
  EXPECT_TRUE(converged(*one)) << residuals;
  EXPECT_LE(last, 1e-10);
  EXPECT_LT((u - expected).norm(), 1e-10 * expected.norm());
  // A budget larger than Newton needs: the converged answer in one frame.
  auto large = newton(body, 50);
  Eigen::VectorXd u_large;
  ElasticFrame(body, loads, *large).step(force, {}, u_large);
  EXPECT_TRUE(converged(*large));
  EXPECT_LT((u_large - expected).norm(), 1e-10 * expected.norm());
  RecordProperty("relative_residual_per_frame_budget_1", residuals);
}

// The top plate lifted 8 mm (20 %) over 4 frames, then held, at 2 iterations a
// frame: the plate is where it is put every frame, and the field and the plate's
// force reach Newton's.
TEST(NewtonBudget, APlateMovedInFramesIsHeldWhereItIsPutAndReachesNewtonsAnswer) {
  const Cube c;
  const ElasticBody body(c.mesh, kMaterial, c.clamped(), c.top_plate());
  const BodyLoads none(body, {});
  const Eigen::Vector3d lift(0, 0, 0.2 * a);
  auto reference = newton(body, 0, 1e-12);
  ElasticFrame reference_frame(body, none, *reference);
  Eigen::VectorXd expected;
  reference_frame.step({}, {lift}, expected);
  auto two = newton(body, 2);
  ElasticFrame frame(body, none, *two);
  Eigen::VectorXd u;
  int frames = 0;
  for (; frames < 30; ++frames) {
    frame.step({}, {lift * std::min(1.0, (frames + 1) / 4.0)}, u);
    EXPECT_EQ(two->report().at("prescribed_move_left_last_solve_m").get<double>(), 0.0) << "frame " << frames;
    if (frames >= 3 && converged(*two)) break;
  }
  EXPECT_TRUE(converged(*two));
  EXPECT_LT((u - expected).norm(), 1e-10 * expected.norm());
  EXPECT_LT((frame.group_forces()[0] - reference_frame.group_forces()[0]).norm(),
            1e-9 * reference_frame.group_forces()[0].norm());
  RecordProperty("frames_to_convergence", frames + 1);
}

// One iteration a frame while the plate keeps moving (and shaking sideways): a full step puts the held
// values exactly where the tool is (not an ulp off, which would keep the frame from
// ever counting as "held in place"), and the run's counters say how many frames
// ended unconverged.
TEST(NewtonBudget, AtOneIterationAMovingPlateIsExactlyWhereItIsPutEveryFrame) {
  const Cube c;
  const ElasticBody body(c.mesh, kMaterial, c.clamped(), c.top_plate());
  const BodyLoads none(body, {});
  auto one = newton(body, 1);
  ElasticFrame frame(body, none, *one);
  Eigen::VectorXd u;
  const int moving_frames = 7;
  int frames = 0;
  for (; frames < 40; ++frames) {
    // A sideways shake of changing sign and size, then rest: the move target - state
    // is then not exact in binary, and state + move can miss the target by an ulp.
    const int k = std::min(frames + 1, moving_frames);
    const double side = k < moving_frames ? (k % 2 ? 1 : -1) * 0.1e-3 * (1 + k / 7.0) : 0;
    const Eigen::Vector3d lift(side, side / 3, 0.7e-3 / 3 * k);
    frame.step({}, {lift}, u);
    ASSERT_EQ(one->report().at("prescribed_move_left_last_solve_m").get<double>(), 0.0) << "frame " << frames;
    if (frames >= moving_frames && converged(*one)) break;
  }
  ASSERT_TRUE(converged(*one));
  const nlohmann::json r = one->report();
  // Each moving frame spends its iteration on the move: not converged then.
  EXPECT_GE(r.at("frames_not_converged").get<long>(), moving_frames);
  EXPECT_EQ(r.at("frames_not_converged").get<long>(), frames);  // every frame before the converged one
  EXPECT_EQ(r.at("frames_stopped_early").get<long>(), 0);
  EXPECT_EQ(r.at("largest_prescribed_move_left_m").get<double>(), 0.0);
}

// Under a law defined when inverted (linear) a budgeted frame accepts an inverted
// state; it says how many tets are inverted, counted here independently.
TEST(NewtonBudget, InvertedTetsOfALawDefinedThereAreCounted) {
  const Cube c;
  const ElasticBody body(c.mesh, kMaterial, c.clamped());
  const BodyLoads loads(body, {containing_tet(c.mesh, {a / 2, a / 2, a}, "cube")});
  auto linear = testing::make_solve(
      body, {{"solver", "newton"}, {"material_law", "linear"}, {"newton_max_iterations_per_frame", 2}});
  Eigen::VectorXd u;
  ElasticFrame(body, loads, *linear).step({Eigen::Vector3d(0, 0, -20.0)}, {}, u);  // a hard push: tets invert
  int inverted = 0;
  for (Eigen::Index t = 0; t < c.mesh.T.rows(); ++t) {
    Eigen::Matrix<double, 3, 4> x;
    for (int k = 0; k < 4; ++k) x.col(k) = c.mesh.V.row(c.mesh.T(t, k)).transpose() + u.segment<3>(3 * c.mesh.T(t, k));
    const TetShape s = tet_shape(c.mesh.V.row(c.mesh.T(t, 0)), c.mesh.V.row(c.mesh.T(t, 1)),
                                 c.mesh.V.row(c.mesh.T(t, 2)), c.mesh.V.row(c.mesh.T(t, 3)));
    inverted += tet_deformation_gradient(s, x).determinant() > 0 ? 0 : 1;
  }
  ASSERT_GT(inverted, 0);
  EXPECT_EQ(linear->report().at("inverted_tets_last_solve").get<int>(), inverted);
}

TEST(NewtonBudget, BadBudgetsAreOneLineErrors) {
  const Cube c;
  const ElasticBody body(c.mesh, kMaterial, c.clamped());
  auto error = [&](const nlohmann::json& given) -> std::string {
    try {
      testing::make_solve(body, given);
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "(accepted)";
  };
  const std::pair<nlohmann::json, std::string> cases[] = {
      {{{"solver", "newton"}, {"newton_max_iterations_per_frame", 2}, {"newton_load_steps", 3}},
       "newton_max_iterations_per_frame 2: a budgeted frame takes the whole load at once, so newton_load_steps must "
       "be 1, not 3"},
      {{{"solver", "newton"}, {"newton_max_iterations_per_frame", -1}}, "test.newton_max_iterations_per_frame"},
      {{{"solver", "newton"}, {"newton_max_iterations_per_frame", 1.5}}, "test.newton_max_iterations_per_frame"},
      // Another strategy's parameter, given: it would be ignored.
      {{{"solver", "direct"}, {"newton_max_iterations_per_frame", 2}},
       "newton_max_iterations_per_frame is a parameter of the newton solver; solver is direct"},
      {{{"material_law", "neo_hookean"}}, "material_law is a parameter of the newton solver; solver is direct"},
  };
  for (const auto& [given, expected] : cases) {
    const std::string what = error(given);
    EXPECT_EQ(what.rfind(expected, 0), 0u) << given.dump() << ": " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
  EXPECT_EQ(error({{"solver", "newton"}, {"newton_max_iterations_per_frame", 2}}), "(accepted)");
}

}  // namespace
}  // namespace tb
