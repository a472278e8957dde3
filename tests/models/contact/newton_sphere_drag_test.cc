// Newton's contact with a rigid sphere (newton_solve.cc) through the suite palpation's
// path on a coarse cube: the sphere (radius 12.7 mm) pressed 10 mm into the top over 10
// frames, then dragged 20 mm along x over 20. On the suite gates' small mesh (TetGen
// max volume 1e-6 m^3) the drag reaches a fold of the quasi-static path: a node's
// contact force falls to zero where the body without that contact would be inside the
// sphere, so neither active set has an equilibrium nearby and the primal-dual set
// update cycled between them at every smaller increment (docs/suite.md, "The
// palpation's reference"). Pseudo-transient continuation crosses the fold; these tests
// check the KKT conditions at every frame, under the three neo-Hookean laws, and that a
// case the solve cannot converge is a one-line error, not a hang.
#include <gtest/gtest.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

#include "cube_generator.h"
#include "elastic_body.h"
#include "elastic_solve.h"
#include "sphere_obstacles.h"
#include "test_support.h"
#include "tetgen_driver.h"

namespace tb {
namespace {

constexpr double kRadius = 0.0127;  // m, the suite palpation's sphere

/// The suite's cube (0.1 m) with a surface lattice `spec` tetrahedralised by TetGen with
/// tets of at most max_volume; the surface vertices are the first nodes.
TetMesh cube_mesh(const CubeSpec& spec, double max_volume) {
  TetgenOptions o;
  o.max_volume = max_volume;
  return tetrahedralize_surface(make_cube_surface(spec), o, "cube");
}

/// The suite's cube (10 x 10 x 12 surface lattice) at the gates' small level: max
/// volume 1e-6 m^3 (3290 tets).
const TetMesh& coarse_cube() {
  static const TetMesh mesh = cube_mesh(CubeSpec{}, 1e-6);
  return mesh;
}

/// The palpation's sphere centre at frame f (experiments/scenarios/suite/cube-palpation.json):
/// from 0.2 mm above the top down 10 mm over frames 0-10, then 20 mm along +x over 10-30.
Eigen::Vector3d palpation_centre(int f) {
  const double z0 = 0.1 + kRadius + 0.0002;
  if (f <= 10) return {0, 0, z0 - 0.001 * f};
  return {0.001 * std::min(f - 10, 20), 0, z0 - 0.01};
}

/// The worst of the KKT conditions over the frames solved, and what the solve reported.
struct Drag {
  int frames = 0;          ///< frames solved
  std::string error;       ///< the solve's exception, if one ended the drag
  double penetration = 0;  ///< deepest surface node inside the sphere, over the radius
  double off_sphere = 0;   ///< largest |gap| / r of a node carrying a force (complementarity)
  double least_multiplier = std::numeric_limits<double>::infinity();  ///< min lambda = f . n (N)
  double tangential = 0;                                              ///< largest |f - (f . n) n| / |f| (frictionless)
  double equilibrium = 0;  ///< largest |f_int - contact| / |contact| on the free dofs
  long continuations = 0;  ///< pseudo-transient continuations over the run
  double seconds = 0;
};

/// A sphere's path on a cube: the mesh (its surface vertices the first `surface` nodes),
/// the sphere's radius and centre at each frame, the Newton solve's law.
struct DragCase {
  const TetMesh* mesh = &coarse_cube();
  int surface = 682;
  std::string law = "neo_hookean";
  int frames = 31;
  Eigen::Vector3d (*path)(int) = palpation_centre;
  double radius = kRadius;
};

/// The case's frames by the Newton solve (the fem model's solver newton) with E = 3 kPa,
/// nu = 0.45, the bottom clamped; the KKT conditions after each frame.
Drag drag(const DragCase& c) {
  const TetMesh& mesh = *c.mesh;
  const std::string& law = c.law;
  const double radius = c.radius;
  std::vector<char> clamped(static_cast<size_t>(mesh.V.rows()), 0);
  for (Eigen::Index n = 0; n < mesh.V.rows(); ++n) clamped[static_cast<size_t>(n)] = mesh.V(n, 2) < 1e-9;
  const ElasticBody body(mesh, Material{}, clamped);
  std::unique_ptr<ElasticSolve> solve = testing::make_solve(body, {{"solver", "newton"}, {"material_law", law}});
  std::vector<int> surface_nodes(static_cast<size_t>(c.surface));
  for (int v = 0; v < c.surface; ++v) surface_nodes[static_cast<size_t>(v)] = v;
  solve->enable_spheres(surface_nodes);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(body.dofs()), f_free = Eigen::VectorXd::Zero(body.free_dofs());
  Eigen::MatrixX3d centre(1, 3);
  Drag out;
  const auto start = std::chrono::steady_clock::now();
  for (int f = 0; f < c.frames; ++f) {
    centre.row(0) = c.path(f).transpose();
    SphereObstacles& spheres = *solve->spheres();
    spheres.set(centre, Eigen::VectorXd::Constant(1, radius));
    try {
      solve->solve(f_free, nullptr, u);
    } catch (const std::runtime_error& e) {
      out.error = e.what();
      break;
    }
    ++out.frames;
    out.penetration = std::max(out.penetration, spheres.penetration()[0] / radius);
    Eigen::VectorXd contact_full = Eigen::VectorXd::Zero(body.dofs());
    for (const auto& [node, force] : spheres.node_forces()) {
      const Eigen::Vector3d x = mesh.V.row(node).transpose() + u.segment<3>(3 * node);
      const Eigen::Vector3d d = x - centre.row(0).transpose();
      const Eigen::Vector3d n = d.normalized();
      const double lambda = force.dot(n);
      out.least_multiplier = std::min(out.least_multiplier, lambda);
      if (lambda > 0) out.off_sphere = std::max(out.off_sphere, std::abs(d.norm() - radius) / radius);
      if (force.norm() > 0) out.tangential = std::max(out.tangential, (force - lambda * n).norm() / force.norm());
      contact_full.segment<3>(3 * node) += force;
    }
    Eigen::VectorXd f_int_free, contact_free;
    body.to_free(*solve->internal_force(), f_int_free);
    body.to_free(contact_full, contact_free);
    if (contact_free.norm() > 0)
      out.equilibrium = std::max(out.equilibrium, (f_int_free - contact_free).norm() / contact_free.norm());
  }
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  const nlohmann::json report = solve->report();
  out.continuations = report.value("pseudo_transient_continuations", 0L);
  std::printf(
      "%s: %d frames, %ld pseudo-transient continuation(s), %.1f s; penetration %.2e r, active off the sphere "
      "%.2e r, least multiplier %.3e N, tangential %.1e, equilibrium %.2e%s%s\n",
      law.c_str(), out.frames, out.continuations, out.seconds, out.penetration, out.off_sphere, out.least_multiplier,
      out.tangential, out.equilibrium, out.error.empty() ? "" : "; error: ", out.error.c_str());
  return out;
}

/// The KKT conditions at the tolerances Newton converges to: no node inside by more than
/// the gap tolerance 1e-9 r, each force along the normal and compressive, each node with a
/// force on the sphere, f_int = the contact forces (the tolerance 1e-10 of the forces in play,
/// with a factor 100 for the free dofs' share of them).
void expect_kkt(const Drag& d, const std::string& law) {
  EXPECT_TRUE(d.error.empty()) << law << ": " << d.error;
  EXPECT_EQ(d.frames, 31) << law;
  EXPECT_LE(d.penetration, 1e-9) << law;
  EXPECT_LE(d.off_sphere, 1e-9) << law;
  EXPECT_GE(d.least_multiplier, 0) << law;
  EXPECT_LT(d.tangential, 1e-12) << law;
  EXPECT_LT(d.equilibrium, 1e-8) << law;
}

/// The case that failed: the neo-Hookean drag on the gates' mesh, which ended at frame 22
/// ("no equilibrium at load fraction 0.304932 after 12 halvings") before pseudo-transient
/// continuation; now every frame converges, crossing the fold by one continuation.
TEST(NewtonSphereDrag, CoarseCubeNeoHookeanCrossesTheFoldWithKktAtEveryFrame) {
  ASSERT_EQ(coarse_cube().T.rows(), 3290) << "the suite gates' small mesh";
  const Drag d = drag({});
  expect_kkt(d, "neo_hookean");
  EXPECT_GE(d.continuations, 1) << "the fold at frame 22 needs a continuation";
}

/// The law references' drag on the same mesh (measured: the stable law crosses two folds,
/// the isochoric none).
TEST(NewtonSphereDrag, CoarseCubeStableNeoHookeanWithKktAtEveryFrame) {
  DragCase c;
  c.law = "stable_neo_hookean";
  expect_kkt(drag(c), c.law);
}

TEST(NewtonSphereDrag, CoarseCubeIsochoricNeoHookeanWithKktAtEveryFrame) {
  DragCase c;
  c.law = "neo_hookean_isochoric";
  expect_kkt(drag(c), c.law);
}

/// A case the solve cannot converge within its limits: a sphere of radius 1 m pressed in
/// one frame from above a small cube (232 tets) to 2 mm above its clamped base, which
/// would crush the whole cube into a layer under it. Increments halve 12 times, the
/// pseudo-transient continuation does not converge in its 400 iterations either, and
/// the frame ends in a one-line error naming the law and the load fraction (measured:
/// 0.901611, about 1 s of CPU).
TEST(NewtonSphereDrag, CrushingASmallCubeUnderAWideSphereIsAOneLineError) {
  const CubeSpec lattice{0.1, 0.1, 4, 4, 4};
  static const TetMesh small = cube_mesh(lattice, 1e-4);
  DragCase c;
  c.mesh = &small;
  c.surface = static_cast<int>(make_cube_surface(lattice).V.rows());
  c.frames = 2;
  c.radius = 1;
  c.path = [](int f) -> Eigen::Vector3d { return {0, 0, f == 0 ? 1.1002 : 1.002}; };
  const Drag d = drag(c);
  EXPECT_EQ(d.frames, 1) << "the sphere above the cube converges; the crushing frame does not";
  EXPECT_EQ(d.error.find('\n'), std::string::npos) << d.error;
  EXPECT_EQ(d.error.rfind("newton solve (neo_hookean): no equilibrium at load fraction ", 0), 0u) << d.error;
  EXPECT_NE(d.error.find("after 12 halvings of the increment and a pseudo-transient continuation"),
            std::string::npos)
      << d.error;
  // Both reasons: plain Newton's last attempt and the continuation's.
  EXPECT_NE(d.error.find("(the last attempt: "), std::string::npos) << d.error;
  EXPECT_NE(d.error.find("; the continuation: the pseudo-time-shifted tangent is not positive definite; "),
            std::string::npos)
      << d.error;
}

}  // namespace
}  // namespace tb
