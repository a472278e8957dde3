// Projective Dynamics (models/numerics/realtime/pd_solve.h) against the static
// Newton solve of the same law on the same mesh: its fixed point is the minimiser of
// each frame's incremental potential, whose steady state is the law's static
// equilibrium; so, run until it stops moving, it must reach Newton's answer to 1e-6
// (field and reactions), under a point force pulling and pushing and under a plate:
// the suite SettledStepper of tests/models/realtime (settled_cube.h), instantiated
// here for both modes. Measured (relative to Newton, frames of 0.5 s to settle):
// quasi_newton 7e-12..2e-11 in 14-15 frames (neo_hookean, stable_neo_hookean,
// arap_volume; plate 2e-13..4e-13 in 6-7); local_global (arap_volume) 1.8e-10 in
// 211 frames (pull), 2.0e-10 in 201 (push), 1.6e-11 in 58 (plate).
#include <gtest/gtest.h>

#include "models/realtime/settled_cube.h"
#include "pd_solve.h"

namespace tb {
namespace {

using testing::SettledStepper;

/// Long steps (0.5 s against the cube's periods of milliseconds: inertia damps out in
/// a few frames), 20 iterations a frame, no early stop but the rounding floor.
testing::Stepper settled(PdMode mode, const std::string& law) {
  PdSettings o;
  o.mode = mode;
  o.law = law;
  o.stepping.time_step = 0.5;
  o.iterations = 20;
  o.tolerance = 0;
  const std::string name = std::string(mode == PdMode::LocalGlobal ? "local_global_" : "quasi_newton_") + law;
  return {name, law, [o](const ElasticBody& b) { return make_pd_solve(b, o); }, 2000, 1e-6};
}

INSTANTIATE_TEST_SUITE_P(Pd, SettledStepper,
                         ::testing::Values(settled(PdMode::QuasiNewton, "neo_hookean"),
                                           settled(PdMode::QuasiNewton, "stable_neo_hookean"),
                                           settled(PdMode::QuasiNewton, "arap_volume"),
                                           settled(PdMode::LocalGlobal, "arap_volume")),
                         [](const ::testing::TestParamInfo<testing::Stepper>& i) { return i.param.name; });

}  // namespace
}  // namespace tb
