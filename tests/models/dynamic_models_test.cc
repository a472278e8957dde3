// PBD and hybrid models on the paper's cube: rest under zero load, stability,
// symmetry; and the registry's rules.
#include <gtest/gtest.h>

#include <Eigen/Geometry>

#include "cube_generator.h"
#include "hybrid_builder.h"
#include "model.h"
#include "pbd_solver.h"
#include "test_support.h"

namespace tb {
namespace {

const HybridMesh& cube() { return testing::scenario_mesh("cube-pull"); }

std::unique_ptr<Model> make(const std::string& name, const nlohmann::json& params = {}) {
  return testing::set_up_model(name, cube(), testing::kCubeBottom, params);
}

class DynamicModel : public ::testing::TestWithParam<std::string> {};

TEST_P(DynamicModel, ZeroLoadLeavesEveryVertexAtRest) {
  auto m = make(GetParam());
  const FrameLoads none = testing::kCubePull.scaled(0).frame();
  for (int f = 0; f < 50; ++f) m->step(none);
  EXPECT_EQ(m->surface_displacement().cwiseAbs().maxCoeff(), 0.0);
}

TEST_P(DynamicModel, TenThousandFramesStayFiniteAndSymmetric) {
  auto m = make(GetParam());
  const FrameLoads pull = testing::kCubePull.frame();
  for (int f = 0; f < 10000; ++f) m->step(pull);
  const Displacements& u = m->surface_displacement();
  ASSERT_TRUE(u.allFinite());
  // Mirror symmetry of u_z about x = 0. Not exact: Gauss-Seidel order (PBD,
  // measured 6.8% of max u_z with colour-ordered alternating sweeps, 8.8% in edge
  // order, 21% without alternating) and, for the hybrid, a coarse mesh whose
  // vertex selection and Delaunay mesh are not mirror-symmetric (measured 10.0%,
  // 14.5% in edge order). Stated tolerances: 10% and 20%; both are known defects
  // to remove (symmetric selection, Jacobi sweeps).
  const Points& V = cube().fine_surface.V;
  const double umax = u.col(2).cwiseAbs().maxCoeff();
  ASSERT_GT(umax, 0);
  const double worst = testing::mirror_asymmetry(V, u.col(2), 0);
  EXPECT_LT(worst, (GetParam() == "pbd" ? 0.10 : 0.20) * umax);
  RecordProperty("max_asymmetry_relative", std::to_string(worst / umax));
}

INSTANTIATE_TEST_SUITE_P(Models, DynamicModel, ::testing::Values("pbd", "hybrid"));

/// The single-precision sweep's contract: the paper cube's steady state (pull, 300
/// frames) within 1e-4 of max |u| of double precision's (measured 5e-6 for both
/// models: floats round positions at 6e-8 of the cube's 0.1 m).
TEST_P(DynamicModel, SinglePrecisionSweepReachesDoublePrecisionsSteadyState) {
  auto d = make(GetParam()), f = make(GetParam(), {{"precision", "single"}});
  for (int frame = 0; frame < 300; ++frame) {
    const FrameLoads load = testing::kCubePull.scaled(std::min(1.0, (frame + 1) / 50.0)).frame();
    d->step(load);
    f->step(load);
  }
  const double umax = d->surface_displacement().rowwise().norm().maxCoeff();
  const double diff = (d->surface_displacement() - f->surface_displacement()).rowwise().norm().maxCoeff();
  EXPECT_GT(umax, 1e-3);
  EXPECT_LT(diff, 1e-4 * umax);
  RecordProperty("relative_difference", ::testing::PrintToString(diff / umax));
  EXPECT_EQ(f->report()["precision"], "single");
}

TEST(PbdSolver, RigidTranslationOfControlPointsMovesTheSurfaceRigidly) {
  // Free surface (nothing clamped), every 7th vertex a control point pinned at
  // rest + t: at steady state every vertex is at rest + t (the constraints are
  // invariant under translation).
  const SurfaceMesh& s = cube().fine_surface;
  std::vector<char> fixed(static_cast<size_t>(s.V.rows()), 0);
  std::vector<int> pinned;
  for (int v = 0; v < s.V.rows(); v += 7) {
    pinned.push_back(v);
    fixed[static_cast<size_t>(v)] = 1;
  }
  pbd::Settings settings;
  pbd::Solver solver(s, pbd::inverse_masses(s, 1000, fixed), settings);
  const Eigen::RowVector3d t(0.003, -0.002, 0.001);
  Points targets(static_cast<Eigen::Index>(pinned.size()), 3);
  for (size_t k = 0; k < pinned.size(); ++k) targets.row(static_cast<Eigen::Index>(k)) = s.V.row(pinned[k]) + t;
  for (int f = 0; f < 3000; ++f) solver.step({}, pinned, targets);
  const Points moved = solver.positions().rowwise() - t;
  EXPECT_LT((moved - s.V).cwiseAbs().maxCoeff(), 1e-9);
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

std::string logic_error_of(const std::vector<ModelInfo>& models) {
  try {
    validate_registry(models);
  } catch (const std::logic_error& e) {
    return e.what();
  }
  return "no error";
}

TEST(Registry, NamesAreCheckedAtRegistration) {
  EXPECT_NO_THROW(validate_registry(registered_models()));
  ModelInfo a, b;
  a.name = "my-model";  // a hyphen: names folders and test cases, which GoogleTest refuses
  EXPECT_NE(logic_error_of({a}).find("model name 'my-model'"), std::string::npos) << logic_error_of({a});
  a.name = "Fem";
  EXPECT_NE(logic_error_of({a}).find("lower-case letters, digits and '_'"), std::string::npos);
  a.name = "";
  EXPECT_NE(logic_error_of({a}).find("model name ''"), std::string::npos);
  a.name = b.name = "twin_2";
  EXPECT_NE(logic_error_of({a, b}).find("registered twice"), std::string::npos) << logic_error_of({a, b});
}

TEST(Registry, AnUnsupportedLoadIsOneErrorNamingModelKindAndKey) {
  LoadCase c{testing::kCubeBottom, {Load::point_force({0, 0, 0.1}), Load::body_force("loads[1]")}, {}};
  EXPECT_NO_THROW(check_supported(find_model("fem"), c));
  // Every registered model takes every load kind: a model described here refuses one.
  ModelInfo no_gravity;
  no_gravity.name = "no_gravity";
  no_gravity.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction};
  try {
    check_supported(no_gravity, c);
    FAIL() << "no_gravity takes no body force";
  } catch (const std::invalid_argument& e) {
    EXPECT_EQ(std::string(e.what()),
              "model 'no_gravity' does not take body_force loads (loads[1]); it takes point_force, "
              "surface_traction");
  }
  for (const ModelInfo& m : registered_models()) EXPECT_TRUE(m.takes(LoadKind::PointForce)) << m.name;
}

TEST(FemModel, TwoLevelPreconditionerWithoutACoarseMeshIsAnError) {
  HybridMesh no_coarse = cube();
  no_coarse.coarse_volume = TetMesh{};
  const ModelInfo& fem = find_model("fem");
  Problem p{&no_coarse, Material{}, LoadCase{testing::kCubeBottom, testing::kCubePull.loads(), {}},
            resolve_parameters(fem.parameters, {{"solver", "iterative"}, {"preconditioner", "two_level"}}, "fem"), Points()};
  auto m = fem.create();
  try {
    m->setup(p);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("two_level needs the scenario's coarse volume mesh"), std::string::npos)
        << e.what();
  }
  EXPECT_THROW(resolve_parameters(fem.parameters, {{"preconditioner", "amg"}}, "fem"), std::invalid_argument);
}

}  // namespace
}  // namespace tb
