// Sub-stepping (Macklin et al. 2019; docs/liver_steady_state.md): Settings::substeps = n runs a frame
// as n steps of time_step / n. substeps = 1 is the paper's step bit for bit (written
// out here from eqs. 31-35 as the solver had it before sub-steps); substeps = n is
// n such steps of time_step / n, pins held at the frame's positions; bad values are
// errors naming the parameter.
#include <gtest/gtest.h>

#include <random>
#include <stdexcept>
#include <string>

#include "constraint_batches.h"
#include "load_mapping.h"
#include "parameters.h"
#include "pbd_solver.h"
#include "test_support.h"

namespace tb::pbd {
namespace {

/// The paper's cube surface, bottom clamped, a load shared over a surface
/// triangle, and two pins moved a little each frame (as the hybrid's control points).
struct LoadedCube {
  const SurfaceMesh& surface = testing::scenario_mesh("cube-pull", false).fine_surface;
  Eigen::VectorXd inverse_mass;
  NodalWeights load = nearest_surface_point(surface, Eigen::Vector3d(0.003, -0.002, 0.1));
  std::vector<int> pinned;
  LoadedCube() {
    std::vector<char> fixed(static_cast<size_t>(surface.V.rows()));
    for (Eigen::Index v = 0; v < surface.V.rows(); ++v) fixed[static_cast<size_t>(v)] = surface.V(v, 2) == 0.0;
    // Two pinned vertices on the top face away from the load.
    for (Eigen::Index v = 0; v < surface.V.rows() && pinned.size() < 2; ++v)
      if (surface.V(v, 2) > 0.1 - 1e-9 && std::abs(surface.V(v, 0)) > 0.03) {
        pinned.push_back(static_cast<int>(v));
        fixed[static_cast<size_t>(v)] = 1;
      }
    inverse_mass = inverse_masses(surface, 1000, fixed);
  }
  Points pins_at(int frame) const {
    Points p(2, 3);
    for (int k = 0; k < 2; ++k)
      p.row(k) = surface.V.row(pinned[static_cast<size_t>(k)]) + Eigen::RowVector3d(1e-4 * frame, 0, 2e-4 * frame);
    return p;
  }
};

/// The PBD step as the solver ran it before sub-steps (SIMD kernels, double or
/// single precision sweep), one step of `dt`: eq. (31) on the load's vertices,
/// damping, eq. (32), eq. (33) pins, the symmetric Gauss-Seidel projection, eqs. (34)-(35).
struct HandStep {
  Points x, v;
  PaddedPositions p;
  PaddedRows<float> q;
  ConstraintSet c;
  ConstraintBatches batches;
  Eigen::VectorXd w;
  Settings s;
  HandStep(const SurfaceMesh& rest, const Eigen::VectorXd& inverse_mass, const Settings& settings)
      : x(rest.V),
        v(Points::Zero(rest.V.rows(), 3)),
        p(rest.V.rows()),
        q(rest.V.rows()),
        c(build_constraints(rest)),
        batches(c, inverse_mass, batch_width(best_instruction_set(), settings.precision), settings.precision),
        w(inverse_mass),
        s(settings) {}
  void step(double dt, const NodalWeights& load, const Eigen::Vector3d& force, const std::vector<int>& pinned,
            const Points& pinned_positions) {
    for (int k = 0; k < 4; ++k)
      if (load.weights(k) != 0) v.row(load.nodes(k)) += (dt * w(load.nodes(k)) * load.weights(k)) * force.transpose();
    v *= (1 - s.damping);
    p.matrix().leftCols<3>() = x + dt * v;
    for (size_t k = 0; k < pinned.size(); ++k)
      p.matrix().row(pinned[k]).head<3>() = pinned_positions.row(static_cast<Eigen::Index>(k));
    const double ks = stiffness_per_iteration(s.stiffness_of("stretch"), s.iterations);
    const double kb = stiffness_per_iteration(s.stiffness_of("bending"), s.iterations);
    if (s.precision == Precision::Single) {
      q.matrix() = p.matrix().cast<float>();
      batches.project(q.data(), s.iterations, {ks, kb}, {s.bending_angle}, best_instruction_set(), nullptr);
      p.matrix() = q.matrix().cast<double>();
    } else {
      batches.project(p.data(), s.iterations, {ks, kb}, {s.bending_angle}, best_instruction_set(), nullptr);
    }
    v = (p.matrix().leftCols<3>() - x) / dt;
    x = p.matrix().leftCols<3>();
  }
};

double max_difference(const Points& a, const Points& b) { return (a - b).cwiseAbs().maxCoeff(); }

TEST(Substeps, OneSubstepIsThePapersStepBitForBit) {
  const LoadedCube cube;
  for (Precision precision : {Precision::Double, Precision::Single})
    for (BendingAngle angle : {BendingAngle::Unsigned, BendingAngle::Signed}) {
      Settings s;
      ASSERT_EQ(s.substeps, 1);  // the default
      s.precision = precision;
      s.bending_angle = angle;
      Solver solver(cube.surface, cube.inverse_mass, s);
      solver.set_loads({cube.load});
      HandStep hand(cube.surface, cube.inverse_mass, s);
      for (int f = 0; f < 40; ++f) {
        const Points pins = cube.pins_at(f);
        solver.step({Eigen::Vector3d(0.2, 0, 1)}, cube.pinned, pins);
        hand.step(0.01, cube.load, Eigen::Vector3d(0.2, 0, 1), cube.pinned, pins);
      }
      EXPECT_EQ(max_difference(solver.positions(), hand.x), 0.0) << name(precision);
      EXPECT_GT(max_difference(solver.positions(), cube.surface.V), 1e-3);  // it moved
    }
}

TEST(Substeps, NSubstepsAreNStepsOfTheSubstepByHand) {
  const LoadedCube cube;
  for (int n : {2, 3, 5}) {
    Settings s;
    s.substeps = n;
    s.damping = 0.1;
    Solver solver(cube.surface, cube.inverse_mass, s);
    solver.set_loads({cube.load});
    HandStep hand(cube.surface, cube.inverse_mass, s);
    for (int f = 0; f < 25; ++f) {
      const Points pins = cube.pins_at(f);  // held at the frame's positions in every sub-step
      solver.step({Eigen::Vector3d(0, 0.3, -1)}, cube.pinned, pins);
      for (int k = 0; k < n; ++k) hand.step(0.01 / n, cube.load, Eigen::Vector3d(0, 0.3, -1), cube.pinned, pins);
    }
    EXPECT_EQ(max_difference(solver.positions(), hand.x), 0.0) << n << " substeps";
    EXPECT_GT(max_difference(solver.positions(), cube.surface.V), 1e-4);
  }
}

TEST(Substeps, EqualFramesOfTheSubstepForEveryConstraintSolve) {
  // substeps n at time_step dt against substeps 1 at dt / n stepped n times a frame:
  // the same numbers with PBD (SIMD, on spatial domains too, and reference kernels) and XPBD, whose
  // compliance term is alpha / h^2 with h the sub-step and whose multipliers
  // restart each sub-step.
  const LoadedCube cube;
  struct Case {
    const char* name;
    Kernels kernels;
    ConstraintSolve solve;
    int domains, threads;
  };
  for (const Case& c : {Case{"simd pbd", Kernels::Simd, ConstraintSolve::Pbd, 1, 1},
                        Case{"simd pbd, 2 domains, 2 threads", Kernels::Simd, ConstraintSolve::Pbd, 2, 2},
                        Case{"reference pbd", Kernels::Reference, ConstraintSolve::Pbd, 1, 1},
                        Case{"xpbd", Kernels::Reference, ConstraintSolve::Xpbd, 1, 1}}) {
    const int n = 4;
    Settings coarse, fine;
    coarse.domains = fine.domains = c.domains;
    coarse.threads = fine.threads = c.threads;
    coarse.kernels = fine.kernels = c.kernels;
    coarse.constraint_solve = fine.constraint_solve = c.solve;
    coarse.bending_angle = fine.bending_angle = BendingAngle::Signed;
    coarse.material = fine.material = Material{3000, 0.45, 1000};
    coarse.substeps = n;
    fine.time_step = coarse.time_step / n;
    Solver a(cube.surface, cube.inverse_mass, coarse), b(cube.surface, cube.inverse_mass, fine);
    a.set_loads({cube.load});
    b.set_loads({cube.load});
    for (int f = 0; f < 20; ++f) {
      const Points pins = cube.pins_at(f);
      a.step({Eigen::Vector3d(0, 0, 1)}, cube.pinned, pins);
      for (int k = 0; k < n; ++k) b.step({Eigen::Vector3d(0, 0, 1)}, cube.pinned, pins);
    }
    EXPECT_EQ(max_difference(a.positions(), b.positions()), 0.0) << c.name;
    EXPECT_GT(max_difference(a.positions(), cube.surface.V), 1e-4) << c.name;
    if (c.solve == ConstraintSolve::Xpbd) {
      EXPECT_EQ((a.multipliers("stretch") - b.multipliers("stretch")).cwiseAbs().maxCoeff(), 0.0);
      EXPECT_EQ((a.multipliers("bending") - b.multipliers("bending")).cwiseAbs().maxCoeff(), 0.0);
      EXPECT_EQ((a.compliance("stretch") - b.compliance("stretch")).cwiseAbs().maxCoeff(), 0.0);
    }
  }
}

TEST(Substeps, BadValuesAreErrorsNamingTheParameter) {
  const std::vector<ParameterSpec> specs = parameter_specs();
  EXPECT_EQ(resolve_parameters(specs, {}, "p").integer("substeps"), 1);  // default: the paper's step
  EXPECT_EQ(Settings::from(resolve_parameters(specs, {{"substeps", 4}}, "p")).substeps, 4);
  auto message = [&](const nlohmann::json& given) -> std::string {
    try {
      resolve_parameters(specs, given, "liver.json: models[2].parameters");
    } catch (const std::invalid_argument& e) {
      return e.what();
    }
    return "no error";
  };
  EXPECT_EQ(message({{"substeps", 0}}), "liver.json: models[2].parameters.substeps: 0 is outside [1, 1000]");
  EXPECT_EQ(message({{"substeps", -2}}), "liver.json: models[2].parameters.substeps: -2 is outside [1, 1000]");
  EXPECT_EQ(message({{"substeps", 2.5}}), "liver.json: models[2].parameters.substeps: must be an integer");
  EXPECT_EQ(message({{"substeps", "4"}}), "liver.json: models[2].parameters.substeps: must be a number");
  // Settings made in code are checked by the solver.
  const LoadedCube cube;
  for (int bad : {0, -1}) {
    Settings s;
    s.substeps = bad;
    try {
      Solver(cube.surface, cube.inverse_mass, s);
      ADD_FAILURE() << "no error for substeps " << bad;
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(std::string(e.what()), "PBD solver: substeps must be at least 1 (" + std::to_string(bad) + " given)");
    }
  }
}

}  // namespace
}  // namespace tb::pbd
