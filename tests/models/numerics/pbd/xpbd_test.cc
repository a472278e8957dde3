// XPBD (docs/xpbd.md): the scalar update against the PBD projection and against
// finite differences of the constraint functions, the compliances from the
// material, the parameter's error paths, and the steady state's independence of
// the iteration count on the paper's cube.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <iostream>
#include <random>

#include "cube_generator.h"
#include "load_mapping.h"
#include "mesh_checks.h"
#include "model.h"
#include "pbd_solver.h"
#include "reference_projections.h"
#include "test_support.h"
#include "xpbd_compliance.h"

namespace tb::pbd {
namespace {

constexpr double kPi = 3.14159265358979323846;

/// Four points with dihedral angle theta about the hinge p1 p2 (wings at heights
/// 0.3..1, feet along the hinge in [-0.5, 1.5]), randomly rotated and moved.
void random_hinge(double theta, std::mt19937& rng, Vec3 p[4]) {
  std::uniform_real_distribution<double> U(-1, 1), P(0, 1);
  const Eigen::Quaterniond q = Eigen::Quaterniond(U(rng), U(rng), U(rng), U(rng)).normalized();
  const Vec3 t(U(rng), U(rng), U(rng));
  const double h3 = 0.3 + 0.7 * P(rng), h4 = 0.3 + 0.7 * P(rng);
  const Vec3 local[4] = {{0, 0, 0},
                         {1, 0, 0},
                         {-0.5 + 2 * P(rng), h3, 0},
                         {-0.5 + 2 * P(rng), -h4 * std::cos(theta), h4 * std::sin(theta)}};
  for (int i = 0; i < 4; ++i) p[i] = q * local[i] + t;
}

TEST(XpbdUpdate, WithZeroComplianceAndMultiplierIsThePbdProjectionAtStiffnessOne) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> U(-1, 1), P(0, 1);
  for (int k = 0; k < 1000; ++k) {
    const Vec3 a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng));
    const double wa = P(rng), wb = k % 3 == 0 ? 0.0 : P(rng), rest = P(rng);
    Vec3 xa, xb, pa, pb;
    double lambda = 0;
    ASSERT_TRUE(reference::xpbd_stretch(a, wa, b, wb, rest, 0.0, lambda, xa, xb));
    ASSERT_TRUE(reference::project_stretch(a, wa, b, wb, rest, 1.0, pa, pb));
    EXPECT_LE((xa - pa).norm() + (xb - pb).norm(), 1e-14 * (pa.norm() + pb.norm() + 1e-300));
    EXPECT_NEAR(lambda, -((a - b).norm() - rest) / (wa + wb), 1e-14);

    Vec3 p[4], xc[4], pc[4];
    random_hinge(kPi * U(rng), rng, p);
    const double w[4] = {P(rng), P(rng), P(rng), P(rng)}, rest_angle = kPi * U(rng);
    for (BendingAngle kind : {BendingAngle::Unsigned, BendingAngle::Signed}) {
      double mu = 0;
      ASSERT_TRUE(
          reference::xpbd_bending(p[0], w[0], p[1], w[1], p[2], w[2], p[3], w[3], rest_angle, 0.0, mu, xc, kind));
      ASSERT_TRUE(
          reference::project_bending(p[0], w[0], p[1], w[1], p[2], w[2], p[3], w[3], rest_angle, 1.0, pc, kind));
      double diff = 0, scale = 0;
      for (int i = 0; i < 4; ++i) {
        diff += (xc[i] - pc[i]).norm();
        scale += pc[i].norm();
      }
      EXPECT_LE(diff, 1e-13 * scale) << k;
    }
  }
}

/// Central difference of f along direction d (step h).
template <class F>
double directional_difference(const F& f, double h) {
  return (f(h) - f(-h)) / (2 * h);
}

/// The update moves p by dp_i = w_i grad_i C dlambda with grad C the constraint
/// function's own (constraints.h, the SIMD kernels' arithmetic, checked here by
/// finite differences), and afterwards the linearised constraint equation
/// C(p) + grad C . dp + alpha~ (lambda + dlambda) = 0 of XPBD eq. (18) holds.
TEST(XpbdUpdate, SolvesTheLinearisedCompliantConstraintByFiniteDifferences) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> U(-1, 1), P(0, 1);
  constexpr double h = 1e-6;
  int checked = 0;
  for (int k = 0; k < 500; ++k) {
    const double alpha_tilde = k % 4 == 0 ? 0.0 : std::pow(10.0, -3 + 5 * P(rng)), lambda0 = U(rng);
    // Stretch.
    const Vec3 a(U(rng), U(rng), U(rng)), b(U(rng), U(rng), U(rng));
    const double wa = 0.2 + P(rng), wb = 0.2 + P(rng), rest = P(rng);
    double lambda = lambda0;
    Vec3 ca, cb;
    ASSERT_TRUE(reference::xpbd_stretch(a, wa, b, wb, rest, alpha_tilde, lambda, ca, cb));
    const double dlambda = lambda - lambda0;
    // grad_a C by finite differences, compared with ca / (wa dlambda).
    Vec3 grad_a;
    for (int j = 0; j < 3; ++j)
      grad_a(j) =
          directional_difference([&](double t) { return stretch_constraint(a + t * Vec3::Unit(j), b, rest); }, h);
    EXPECT_LE((ca / (wa * dlambda) - grad_a).norm(), 1e-7) << k;
    EXPECT_LE((cb / (wb * dlambda) + grad_a).norm(), 1e-7) << k;
    const double C = stretch_constraint(a, b, rest);
    const double dC =
        directional_difference([&](double t) { return stretch_constraint(a + t * ca, b + t * cb, rest); }, h);
    EXPECT_NEAR(C + dC + alpha_tilde * lambda, 0.0, 1e-7 * (std::abs(C) + alpha_tilde * std::abs(lambda) + 1e-3)) << k;

    // Bending (unsigned, the paper's eq. 19), away from theta = 0 where |theta| kinks,
    // with C and alpha~ lambda0 at most 0.03 rad: steps well inside their trust region
    // (constraints.h), where the update is XPBD's, unshortened.
    Vec3 p[4], corr[4];
    const double theta = (k % 2 ? 1 : -1) * (0.3 + 2.5 * P(rng));
    random_hinge(theta, rng, p);
    const double w[4] = {0.2 + P(rng), 0.2 + P(rng), 0.2 + P(rng), 0.2 + P(rng)};
    const double rest_angle = (U(rng) < 0 ? -1 : 1) * (std::abs(theta) + 0.03 * U(rng));
    const double mu0 = 0.03 * lambda0 / std::max(alpha_tilde, 1.0);
    double mu = mu0;
    ASSERT_TRUE(reference::xpbd_bending(p[0], w[0], p[1], w[1], p[2], w[2], p[3], w[3], rest_angle, alpha_tilde, mu,
                                        corr, BendingAngle::Unsigned));
    const double dmu = mu - mu0;
    // constraints.h's C = |theta| - phi0 takes the unsigned rest angle phi0 = |theta0|.
    auto bend_at = [&](const Vec3 q[4]) { return bending_constraint(q[0], q[1], q[2], q[3], std::abs(rest_angle)); };
    for (int i = 0; i < 4; ++i) {
      Vec3 grad;
      for (int j = 0; j < 3; ++j)
        grad(j) = directional_difference(
            [&](double t) {
              Vec3 q[4] = {p[0], p[1], p[2], p[3]};
              q[i] += t * Vec3::Unit(j);
              return bend_at(q);
            },
            h);
      EXPECT_LE((corr[i] / (w[i] * dmu) - grad).norm(), 1e-6 * (1 + grad.norm())) << k << " vertex " << i;
    }
    const double Cb = bend_at(p);
    const double dCb = directional_difference(
        [&](double t) {
          const Vec3 q[4] = {p[0] + t * corr[0], p[1] + t * corr[1], p[2] + t * corr[2], p[3] + t * corr[3]};
          return bend_at(q);
        },
        h);
    EXPECT_NEAR(Cb + dCb + alpha_tilde * mu, 0.0, 1e-6 * (std::abs(Cb) + alpha_tilde * std::abs(mu) + 1e-3)) << k;
    ++checked;
  }
  EXPECT_EQ(checked, 500);
}

TEST(XpbdUpdate, MovesNothingWhereThePbdProjectionMovesNothing) {
  Vec3 c1, c2;
  double lambda = 0.5;
  EXPECT_FALSE(reference::xpbd_stretch(Vec3(1, 1, 1), 1.0, Vec3(1, 1, 1), 1.0, 0.5, 10.0, lambda, c1, c2));
  EXPECT_FALSE(reference::xpbd_stretch(Vec3(0, 0, 0), 0.0, Vec3(1, 0, 0), 0.0, 0.5, 10.0, lambda, c1, c2));
  EXPECT_EQ(c1.norm() + c2.norm(), 0.0);
  EXPECT_EQ(lambda, 0.5);
}

/// Two equilateral triangles sharing an edge of length L in the plane z = 0.
SurfaceMesh equilateral_pair(double L) {
  SurfaceMesh s;
  s.V.resize(4, 3);
  s.V << 0, 0, 0, L, 0, 0, L / 2, L * std::sqrt(3.0) / 2, 0, L / 2, -L * std::sqrt(3.0) / 2, 0;
  s.F.resize(2, 3);
  s.F << 0, 1, 2, 1, 0, 3;
  return s;
}

TEST(XpbdCompliance, EquilateralMeshGivesTheLatticeAndHingeConstants) {
  const double L = 0.01, E = 3000, nu = 0.45, h = 0.002;
  const SurfaceMesh s = equilateral_pair(L);
  const ConstraintSet c = build_constraints(s);
  const KindConstraints &stretch = c.of("stretch"), &bending = c.of("bending");
  ASSERT_EQ(stretch.size(), 5);
  ASSERT_EQ(bending.size(), 1);
  const Eigen::VectorXd as = stretch_compliances(s, stretch, E, h), ab = bending_compliances(s, bending, E, nu, h);
  for (Eigen::Index i = 0; i < 5; ++i) {
    const bool shared = (stretch.vertices(i, 0) == 0 && stretch.vertices(i, 1) == 1);
    // Triangular lattice: 2D modulus 2 k / sqrt(3) = E h for an interior edge (two
    // triangles); a boundary edge has one triangle, half of it.
    const double k = (shared ? 1.0 : 0.5) * std::sqrt(3.0) / 2 * E * h;
    EXPECT_NEAR(1 / as(i), k, 1e-12 * k) << i;
  }
  const double D = E * h * h * h / (12 * (1 - nu * nu));
  EXPECT_NEAR(1 / ab(0), 2 * std::sqrt(3.0) * D, 1e-12 * D);  // 3 L^2 / A_e = 2 sqrt(3)
}

TEST(XpbdCompliance, VolumePreservingThicknessOfACubeIsASixthOfItsSide) {
  const SurfaceMesh s = make_cube_surface({0.1, 0.1, 6, 6, 6});
  EXPECT_NEAR(volume_preserving_thickness(s), 0.1 / 6, 1e-14);
}

TEST(XpbdCompliance, BadMaterialOrDegenerateEdgesAreErrors) {
  const SurfaceMesh s = equilateral_pair(0.01);
  const ConstraintSet c = build_constraints(s);
  EXPECT_THROW(stretch_compliances(s, c.of("stretch"), 0.0, 0.01), std::invalid_argument);
  EXPECT_THROW(stretch_compliances(s, c.of("stretch"), 3000, 0.0), std::invalid_argument);
  EXPECT_THROW(bending_compliances(s, c.of("bending"), 3000, 0.5001, 0.01), std::invalid_argument);
  EXPECT_THROW(bending_compliances(s, c.of("bending"), 3000, -1.0, 0.01), std::invalid_argument);
  SurfaceMesh flat = s;
  flat.V.row(2) = flat.V.row(3) = Eigen::RowVector3d(0.005, 0, 0);  // both triangles of zero area
  const ConstraintSet cf = build_constraints(flat);
  EXPECT_THROW(stretch_compliances(flat, cf.of("stretch"), 3000, 0.01), std::invalid_argument);
  EXPECT_THROW(bending_compliances(flat, cf.of("bending"), 3000, 0.45, 0.01), std::invalid_argument);
  EXPECT_THROW(volume_preserving_thickness(s), std::invalid_argument);  // an open patch encloses nothing
}

TEST(XpbdParameters, ResolveAndRefuseWhatXpbdCannotDo) {
  const std::vector<ParameterSpec> specs = parameter_specs();
  const Settings s = Settings::from(
      resolve_parameters(specs, {{"constraint_solve", "xpbd"}, {"kernels", "reference"}, {"bending_angle", "signed"}},
                         "test"),
      Material{5000, 0.3, 1000});
  EXPECT_EQ(s.constraint_solve, ConstraintSolve::Xpbd);
  EXPECT_EQ(s.material.youngs_modulus, 5000);
  EXPECT_EQ(s.shell_thickness, 0);
  // The SIMD kernels (the default) have no XPBD update.
  EXPECT_THROW(Settings::from(resolve_parameters(specs, {{"constraint_solve", "xpbd"}}, "test")),
               std::invalid_argument);
  const nlohmann::json stiffness_given = {
      {"constraint_solve", "xpbd"}, {"kernels", "reference"}, {"bending_angle", "signed"}, {"stretch_stiffness", 0.5}};
  EXPECT_THROW(Settings::from(resolve_parameters(specs, stiffness_given, "test")), std::invalid_argument);
  // The paper's unsigned angle (the default) with xpbd.
  EXPECT_THROW(
      Settings::from(resolve_parameters(specs, {{"constraint_solve", "xpbd"}, {"kernels", "reference"}}, "test")),
      std::invalid_argument);
  EXPECT_THROW(Settings::from(resolve_parameters(specs, {{"shell_thickness", 0.01}}, "test")),
               std::invalid_argument);  // pbd has no thickness
  EXPECT_THROW(resolve_parameters(specs, {{"constraint_solve", "XPBD"}}, "test"), std::invalid_argument);
  EXPECT_THROW(resolve_parameters(specs, {{"shell_thickness", -0.01}}, "test"), std::invalid_argument);
  Settings simd = s;
  simd.kernels = Kernels::Simd;
  const SurfaceMesh cube = make_cube_surface({0.1, 0.1, 4, 4, 4});
  EXPECT_THROW(Solver(cube, Eigen::VectorXd::Ones(cube.V.rows()), simd), std::invalid_argument);
}

/// The solver derives the compliances once (thickness: V / A by default) and
/// reports them; the multipliers are reset every frame.
TEST(XpbdSolver, DerivesComplianceFromTheMaterialAndResetsMultipliersEachFrame) {
  Settings s;
  s.kernels = Kernels::Reference;
  s.constraint_solve = ConstraintSolve::Xpbd;
  s.bending_angle = BendingAngle::Signed;
  s.material = Material{3000, 0.45, 1000};
  const SurfaceMesh cube = make_cube_surface({0.1, 0.1, 6, 6, 6});
  std::vector<char> fixed(static_cast<size_t>(cube.V.rows()));
  for (Eigen::Index v = 0; v < cube.V.rows(); ++v) fixed[static_cast<size_t>(v)] = cube.V(v, 2) == 0.0;
  const Eigen::VectorXd w = inverse_masses(cube, 1000, fixed);
  Solver a(cube, w, s);
  EXPECT_NEAR(a.shell_thickness(), 0.1 / 6, 1e-14);
  ASSERT_EQ(a.compliance("stretch").size(), a.constraints().of("stretch").size());
  EXPECT_NEAR(a.compliance("stretch")(0), stretch_compliances(cube, a.constraints().of("stretch"), 3000, 0.1 / 6)(0),
              1e-15);
  Settings stiffer = s;
  stiffer.material.youngs_modulus = 6000;
  Solver b(cube, w, stiffer);
  EXPECT_NEAR((a.compliance("stretch") - 2 * b.compliance("stretch")).norm(), 0,
              1e-12 * a.compliance("stretch").norm());
  EXPECT_NEAR((a.compliance("bending") - 2 * b.compliance("bending")).norm(), 0,
              1e-12 * a.compliance("bending").norm());
  a.set_loads({nearest_vertex(cube.V, cube.V.row(0).transpose())});
  a.step({Vec3(0, 0, 0)}, {}, Points());
  EXPECT_EQ(a.multipliers("stretch").cwiseAbs().maxCoeff(), 0.0);  // at rest: nothing to do
  // Under a constant force the surface comes to rest and each frame's multipliers
  // (the constraint forces times dt^2) settle: they start from 0 every frame. Kept
  // across frames they would grow by about their own size every frame.
  Eigen::Index loaded = 0;
  (cube.V.col(2).array() - 0.1).abs().minCoeff(&loaded);
  Eigen::VectorXd previous;
  a.set_loads({nearest_vertex(cube.V, cube.V.row(loaded).transpose())});
  for (int f = 0; f < 400; ++f) {
    previous = a.multipliers("stretch");
    a.step({Vec3(0, 0, 0.2)}, {}, Points());
  }
  const double size = a.multipliers("stretch").norm();
  EXPECT_GT(size, 0.0);
  EXPECT_LT((a.multipliers("stretch") - previous).norm(), 1e-3 * size);
  EXPECT_EQ(a.details()["constraint_solve"], "xpbd");
  EXPECT_NEAR(a.details()["shell_thickness_m"].get<double>(), 0.1 / 6, 1e-14);
}

}  // namespace
}  // namespace tb::pbd

namespace tb {
namespace {

/// The steady state of `model` on the paper's cube pull (1 N at the top centre,
/// ramped over 50 frames, bottom clamped), run as the runner does: until the
/// largest per-vertex change of a frame is at most 1e-5 of the largest
/// displacement (experiments/scenarios/cube-pull.json), or 5000 frames.
Displacements cube_pull_steady_state(const std::string& model, nlohmann::json parameters) {
  const ModelInfo& info = find_model(model);
  Problem p{&testing::scenario_mesh("cube-pull"), Material{}, LoadCase{testing::kCubeBottom, testing::kCubePull.loads(), {}},
            resolve_parameters(info.parameters, parameters, model), Points()};
  auto m = info.create();
  m->setup(p);
  Displacements last = Displacements::Zero(p.mesh->fine_surface.V.rows(), 3);
  for (int frame = 0; frame < 5000; ++frame) {
    m->step(testing::kCubePull.scaled(std::min(1.0, (frame + 1) / 50.0)).frame());
    const Displacements& u = m->surface_displacement();
    const double change = (u - last).rowwise().norm().maxCoeff(), largest = u.rowwise().norm().maxCoeff();
    last = u;
    if (frame >= 49 && change <= 1e-5 * largest) return last;
  }
  ADD_FAILURE() << model << " " << parameters.dump() << ": no steady state in 5000 frames";
  return last;
}

double relative_l2(const Displacements& a, const Displacements& b) { return (a - b).norm() / b.norm(); }

/// Issue 15: XPBD's steady state does not depend on the iteration count; pure
/// PBD's does (measured 11.4 relative L2 between 10 and 100 iterations here; the
/// hybrid's PBD 5e-6, its control points hold the surface). XPBD's independence
/// needs a frame's Gauss-Seidel solve to converge: at the paper's 10 ms step the
/// cube pull's steady state moved 48% (pbd) and 5% (hybrid) between 10 and 100
/// iterations, at 5 ms 8.8%, at 2.5 ms 0.85% (pbd; README). The test runs 1 ms
/// (measured 1.7e-5 and 1.5e-5).
TEST(XpbdIterations, SteadyStateWithin1PercentBetween10And100IterationsAtAMillisecondStep) {
  for (const std::string model : {"pbd", "hybrid"}) {
    const nlohmann::json xpbd = {
        {"constraint_solve", "xpbd"}, {"kernels", "reference"}, {"bending_angle", "signed"}, {"time_step", 0.001}};
    nlohmann::json x10 = xpbd, x100 = xpbd, p10 = {{"time_step", 0.001}}, p100 = p10;
    x10["iterations"] = p10["iterations"] = 10;
    x100["iterations"] = p100["iterations"] = 100;
    const Displacements u100 = cube_pull_steady_state(model, x100);
    const double xpbd_change = relative_l2(cube_pull_steady_state(model, x10), u100);
    const double pbd_change = relative_l2(cube_pull_steady_state(model, p10), cube_pull_steady_state(model, p100));
    EXPECT_GT(u100.rowwise().norm().maxCoeff(), 1e-3) << model;
    EXPECT_LT(xpbd_change, 0.01) << model;
    if (model == "pbd") {
      EXPECT_GT(pbd_change, 0.01);  // the contrast: PBD's stiffness depends on the iterations
    }
    RecordProperty(model + "_xpbd_relative_change", ::testing::PrintToString(xpbd_change));
    RecordProperty(model + "_pbd_relative_change", ::testing::PrintToString(pbd_change));
    std::cout << model << ": steady state 10 vs 100 iterations, relative L2: xpbd " << xpbd_change << ", pbd "
              << pbd_change << "\n";
  }
}

}  // namespace
}  // namespace tb
