// Projective Dynamics (models/numerics/realtime/pd_solve.h) against the static
// Newton solve of the same law on the same mesh: its fixed point is the minimiser of
// each frame's incremental potential, whose steady state is the law's static
// equilibrium; so, run until it stops moving, it must reach Newton's answer, under a
// point force pulling and pushing and under a prescribed plate with its reaction, on
// the small clamped cube of tests/models/realtime.
#include <gtest/gtest.h>

#include <cmath>

#include "load_mapping.h"
#include "models/realtime/settled_cube.h"
#include "pd_solve.h"

namespace tb {
namespace {

using testing::kMaterial;
using testing::newton_answer;
using testing::settle;
using testing::SmallCube;

struct Case {
  std::string name;
  PdSettings settings;
};

/// Long steps (0.5 s against the cube's periods of milliseconds: inertia damps out in
/// a few frames), 20 iterations a frame, no early stop.
PdSettings settled(PdMode mode, const std::string& law) {
  PdSettings o;
  o.mode = mode;
  o.law = law;
  o.stepping.time_step = 0.5;
  o.iterations = 20;
  o.tolerance = 0;
  return o;
}

std::vector<Case> cases() {
  return {{"quasi_newton_neo_hookean", settled(PdMode::QuasiNewton, "neo_hookean")},
          {"quasi_newton_stable_neo_hookean", settled(PdMode::QuasiNewton, "stable_neo_hookean")},
          {"quasi_newton_arap_volume", settled(PdMode::QuasiNewton, "arap_volume")},
          {"local_global_arap_volume", settled(PdMode::LocalGlobal, "arap_volume")}};
}

class SettledPd : public ::testing::TestWithParam<Case> {};

// 0.2 N at the top centre, up then down (17 % of the height under Newton): the
// settled field to 1e-6 of Newton's, and the support's reaction balances the load.
TEST_P(SettledPd, EqualsTheStaticNewtonAnswerUnderAPointForce) {
  const Case& c = GetParam();
  const SmallCube cube;
  const ElasticBody body(cube.mesh, kMaterial, cube.clamped());
  const BodyLoads loads(body, {containing_tet(cube.mesh, {cube.a / 2, cube.a / 2, cube.a}, "cube")});
  for (double fz : {0.2, -0.2}) {
    const std::vector<Eigen::Vector3d> force = {Eigen::Vector3d(0, 0, fz)};
    const Eigen::VectorXd expected = newton_answer(body, loads, c.settings.law, force, {});
    auto pd = make_pd_solve(body, c.settings);
    ElasticFrame frame(body, loads, *pd);
    Eigen::VectorXd u;
    const int frames = settle(frame, force, {}, u, 2000);
    EXPECT_LE(frames, 2000) << c.name << " did not settle, force " << fz;
    const double error = (u - expected).norm() / expected.norm();
    EXPECT_LT(error, 1e-6) << c.name << " force " << fz << " frames " << frames;
    EXPECT_LT((frame.support_force() - force[0]).norm(), 1e-6 * std::abs(fz)) << c.name;
    const std::string key = c.name + (fz > 0 ? "_pull" : "_push");
    RecordProperty(key + "_frames", frames);
    RecordProperty(key + "_relative_error", ::testing::PrintToString(error));
  }
}

// The top held by a bonded plate lifted 8 mm (20 %), ramped over 10 frames: the field
// and the plate's reaction equal Newton's.
TEST_P(SettledPd, EqualsTheStaticNewtonAnswerUnderAPlate) {
  const Case& c = GetParam();
  const SmallCube cube;
  const ElasticBody body(cube.mesh, kMaterial, cube.clamped(), cube.top_plate());
  const BodyLoads none(body, {});
  const std::vector<Eigen::Vector3d> lift = {Eigen::Vector3d(0, 0, 0.2 * cube.a)};
  std::vector<Eigen::Vector3d> expected_force;
  const Eigen::VectorXd expected = newton_answer(body, none, c.settings.law, {}, lift, &expected_force);
  auto pd = make_pd_solve(body, c.settings);
  ElasticFrame frame(body, none, *pd);
  Eigen::VectorXd u;
  for (int f = 1; f <= 10; ++f) frame.step({}, {lift[0] * (f / 10.0)}, u);
  const int frames = settle(frame, {}, lift, u, 2000);
  EXPECT_LE(frames, 2000) << c.name;
  const double error = (u - expected).norm() / expected.norm();
  EXPECT_LT(error, 1e-6) << c.name;
  EXPECT_LT((frame.group_forces()[0] - expected_force[0]).norm(), 1e-6 * expected_force[0].norm()) << c.name;
  // The tissue pulls the plate down, and the support up by as much (the body is at rest).
  EXPECT_LT(expected_force[0].z(), 0);
  EXPECT_LT((frame.group_forces()[0] + frame.support_force()).norm(), 1e-6 * expected_force[0].norm());
  RecordProperty(c.name + "_plate_frames", frames);
  RecordProperty(c.name + "_plate_relative_error", ::testing::PrintToString(error));
}

INSTANTIATE_TEST_SUITE_P(Modes, SettledPd, ::testing::ValuesIn(cases()),
                         [](const ::testing::TestParamInfo<Case>& i) { return i.param.name; });

}  // namespace
}  // namespace tb
