// PBD and hybrid models on the paper's cube (issue 5): rest under zero load,
// stability, symmetry.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "cube_generator.h"
#include "hybrid_builder.h"
#include "model.h"

namespace tb {
namespace {

const HybridMesh& cube() {
  static const HybridMesh h = [] {
    HybridBuildOptions o;
    o.fine_tetgen.max_volume = 9e-8;
    return build_hybrid_from_surface(make_cube_surface({}), o, "cube");
  }();
  return h;
}

std::unique_ptr<Model> make(const std::string& name, const nlohmann::json& params = {}) {
  const ModelInfo& info = find_model(name);
  Problem p{&cube(), Material{}, SupportBox{{-1, -1, -1e-9}, {1, 1, 1e-9}},
            resolve_parameters(info.parameters, params, name)};
  auto m = info.create();
  m->setup(p);
  return m;
}

class DynamicModel : public ::testing::TestWithParam<std::string> {};

TEST_P(DynamicModel, ZeroLoadLeavesEveryVertexAtRest) {
  auto m = make(GetParam());
  for (int f = 0; f < 50; ++f) m->step({{0, 0, 0.1}, {0, 0, 0}});
  EXPECT_EQ(m->surface_displacement().cwiseAbs().maxCoeff(), 0.0);
}

TEST_P(DynamicModel, TenThousandFramesStayFiniteAndSymmetric) {
  auto m = make(GetParam());
  for (int f = 0; f < 10000; ++f) m->step({{0, 0, 0.1}, {0, 0, 1}});
  const Displacements& u = m->surface_displacement();
  ASSERT_TRUE(u.allFinite());
  // Mirror symmetry of u_z about x = 0. Not exact: Gauss-Seidel order (PBD,
  // measured 8.8% of max u_z with alternating sweeps, 21% without) and, for the
  // hybrid, a coarse mesh whose vertex selection and Delaunay mesh are not
  // mirror-symmetric (measured 14.5%). Stated tolerances: 10% and 20%; both are
  // known defects to remove (symmetric selection, colour-ordered Jacobi sweeps).
  const Points& V = cube().fine_surface.V;
  const double umax = u.col(2).cwiseAbs().maxCoeff();
  ASSERT_GT(umax, 0);
  double worst = 0;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    Eigen::RowVector3d mv = V.row(v);
    mv.x() = -mv.x();
    Eigen::Index w;
    (V.rowwise() - mv).rowwise().norm().minCoeff(&w);
    worst = std::max(worst, std::abs(u(v, 2) - u(w, 2)));
  }
  EXPECT_LT(worst, (GetParam() == "pbd" ? 0.10 : 0.20) * umax);
  RecordProperty("max_asymmetry_relative", std::to_string(worst / umax));
}

INSTANTIATE_TEST_SUITE_P(Models, DynamicModel, ::testing::Values("pbd", "hybrid"));

TEST(HybridModel, ControlPointsFollowTheCoarseSolution) {
  auto m = make("hybrid", {{"surface_force", "none"}});
  m->step({{0, 0, 0.1}, {0, 0, 1}});
  const Displacements& u = m->surface_displacement();
  // Control points on the clamped bottom stay put; some control point moves up.
  double top = 0;
  for (const auto& cp : cube().control_points) {
    if (cube().fine_surface.V(cp.surface_vertex, 2) == 0.0) EXPECT_EQ(u.row(cp.surface_vertex).norm(), 0.0);
    top = std::max(top, u(cp.surface_vertex, 2));
  }
  EXPECT_GT(top, 0);
}

TEST(Registry, UnknownModelAndParametersAreErrors) {
  EXPECT_THROW(find_model("nope"), std::invalid_argument);
  const ModelInfo& pbd = find_model("pbd");
  EXPECT_THROW(resolve_parameters(pbd.parameters, {{"iteration", 3}}, "x"), std::invalid_argument);
  EXPECT_THROW(resolve_parameters(pbd.parameters, {{"iterations", 0}}, "x"), std::invalid_argument);
  EXPECT_THROW(resolve_parameters(pbd.parameters, {{"iterations", 2.5}}, "x"), std::invalid_argument);
  EXPECT_THROW(resolve_parameters(pbd.parameters, {{"stiffness_correction", "maybe"}}, "x"), std::invalid_argument);
  EXPECT_EQ(resolve_parameters(pbd.parameters, {{"iterations", 5}}, "x").integer("iterations"), 5);
}

}  // namespace
}  // namespace tb
