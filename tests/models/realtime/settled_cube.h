// The small clamped cube the real-time steppers are tested on (tests/models/realtime,
// tests/models/pd), run until it stops moving, and the static Newton answer of a law
// on it: a stepper whose fixed point is that law's equilibrium must reach it.
#pragma once

#include <gtest/gtest.h>

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"
#include "test_support.h"

namespace tb::testing {

/// E = 3 kPa, nu = 0.45, 1000 kg/m^3.
inline const Material kMaterial{3000, 0.45, 1000};

/// A 4 cm cube, its surface a 4 x 4 x 4 grid, clamped at z = 0; optionally its top
/// held by a bonded plate (one prescribed group).
struct SmallCube {
  static constexpr double a = 0.04;
  TetMesh mesh = box_mesh(a, a, a, 4, 4, 4, 2e-6);
  std::vector<char> clamped() const {
    std::vector<char> c(static_cast<size_t>(mesh.V.rows()), 0);
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) c[static_cast<size_t>(v)] = mesh.V(v, 2) < 1e-12;
    return c;
  }
  std::vector<PrescribedGroup> top_plate() const {
    PrescribedGroup g;
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
      if (mesh.V(v, 2) > a - 1e-12) g.nodes.push_back(static_cast<int>(v));
    return {g};
  }
};

/// SmallCube clamped at its base with a point force at its top centre, 0.2 N up: the
/// set-up most of the steppers' tests share, taken apart as
///   const PulledSmallCube pulled;
///   const auto& [c, body, loads, force] = pulled;
/// Not copyable: the body and the loads refer to the cube's mesh.
struct PulledSmallCube {
  SmallCube c;
  ElasticBody body{c.mesh, kMaterial, c.clamped()};
  BodyLoads loads{body, {containing_tet(c.mesh, {c.a / 2, c.a / 2, c.a}, "cube")}};
  std::vector<Eigen::Vector3d> force{Eigen::Vector3d(0, 0, 0.2)};

  PulledSmallCube() = default;
  PulledSmallCube(const PulledSmallCube&) = delete;
  PulledSmallCube& operator=(const PulledSmallCube&) = delete;
};

/// Frames of `frame` until u moves by at most 1e-11 |u| in a frame (or `max_frames`).
inline int settle(ElasticFrame& frame, const std::vector<Eigen::Vector3d>& loads, const std::vector<Eigen::Vector3d>& groups,
           Eigen::VectorXd& u, int max_frames) {
  Eigen::VectorXd previous;
  for (int f = 1; f <= max_frames; ++f) {
    previous = u;
    frame.step(loads, groups, u);
    if (f > 1 && (u - previous).norm() <= 1e-11 * u.norm()) return f;
  }
  return max_frames + 1;
}

inline Eigen::VectorXd newton_answer(const ElasticBody& body, const BodyLoads& loads, const std::string& law,
                              const std::vector<Eigen::Vector3d>& force, const std::vector<Eigen::Vector3d>& groups,
                              std::vector<Eigen::Vector3d>* group_forces = nullptr) {
  auto newton = make_solve(
      body, {{"solver", "newton"}, {"material_law", law}, {"newton_tolerance", 1e-12}, {"newton_load_steps", 4}});
  ElasticFrame frame(body, loads, *newton);
  Eigen::VectorXd u;
  frame.step(force, groups, u);
  if (group_forces) *group_forces = frame.group_forces();
  return u;
}

/// A stepper run until settled against Newton's answer of its law: the parameterised
/// suite SettledStepper (its tests in tests/models/realtime/realtime_solvers_test.cc,
/// instantiated there for VBD and XPBD and in tests/models/pd for PD).
using MakeStepper = std::function<std::unique_ptr<ElasticSolve>(const ElasticBody&)>;

struct Stepper {
  std::string name, law;
  MakeStepper make;
  int max_frames;
  /// Relative to Newton's answer, field and reactions. VBD's and PD's fixed point is
  /// the law's equilibrium: 1e-6. XPBD's is not: lambda restarts each sub-step, and the
  /// first-order update leaves a bias of order h^2 (XpbdSteadyStateBiasShrinksAsTheSubstepSquared);
  /// at the 40 sub-steps of 10 ms used here, measured 1.19e-3 (pull) and 1.52e-3
  /// (push): its tolerance is 3e-3, twice that.
  double tolerance;
};

class SettledStepper : public ::testing::TestWithParam<Stepper> {};

}  // namespace tb::testing
