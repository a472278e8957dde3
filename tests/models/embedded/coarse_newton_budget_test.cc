// The coarse Newton solve with a budget of iterations a frame in the models that
// have a coarse FEM (parameter coarse_newton_max_iterations_per_frame): the embedded
// model reaches the converged neo-Hookean answer under a constant load, its residual
// reported every frame; the hybrid's coarse solve takes the same parameter and moves
// its control points as the embedded model's does, frame by frame; a bad combination
// is a one-line error naming the model and the parameter. On the paper's cube.
#include <gtest/gtest.h>

#include "model.h"
#include "test_support.h"

namespace tb {
namespace {

const nlohmann::json kNeo = {{"coarse_solver", "newton"}, {"coarse_material_law", "neo_hookean"}};

nlohmann::json with_budget(int k) {
  nlohmann::json p = kNeo;
  p["coarse_newton_max_iterations_per_frame"] = k;
  return p;
}

nlohmann::json coarse_report(const Model& m) { return m.report().at("coarse_solve"); }

TEST(CoarseNewtonBudget, TheEmbeddedModelReachesTheConvergedAnswerReportingItsResidual) {
  const HybridMesh& h = testing::scenario_mesh("cube-pull", false);
  const FrameLoads pull = testing::kCubePull.frame();
  auto converged = testing::set_up_model("embedded", h, testing::kCubeBottom, kNeo);
  converged->step(pull);
  auto budget = testing::set_up_model("embedded", h, testing::kCubeBottom, with_budget(2));
  double last = std::numeric_limits<double>::infinity();
  int frames = 0;
  for (; frames < 20; ++frames) {
    budget->step(pull);
    const nlohmann::json r = coarse_report(*budget);
    EXPECT_LE(r.at("newton_iterations_last_solve").get<int>(), 2);
    EXPECT_LT(r.at("relative_residual_last_solve").get<double>(), last);
    last = r.at("relative_residual_last_solve").get<double>();
    if (r.at("converged_last_solve").get<bool>()) break;
  }
  EXPECT_LE(last, 1e-10);
  const Displacements& u = budget->surface_displacement();
  const Displacements& expected = converged->surface_displacement();
  EXPECT_LT((u - expected).norm(), 1e-10 * expected.norm());
  EXPECT_EQ(coarse_report(*budget).at("newton_max_iterations_per_frame"), 2);
  RecordProperty("frames_to_convergence_budget_2", frames + 1);
}

TEST(CoarseNewtonBudget, TheHybridsCoarseSolveTakesItAndMovesControlPointsAsTheEmbeddedModel) {
  const HybridMesh& h = testing::scenario_mesh("cube-pull");
  const FrameLoads pull = testing::kCubePull.frame();
  auto embedded = testing::set_up_model("embedded", h, testing::kCubeBottom, with_budget(1));
  nlohmann::json hybrid_parameters = with_budget(1);
  hybrid_parameters["surface_force"] = "none";
  auto hybrid = testing::set_up_model("hybrid", h, testing::kCubeBottom, hybrid_parameters);
  for (int frame = 0; frame < 3; ++frame) {
    embedded->step(pull);
    hybrid->step(pull);
    double worst = 0, largest = 0;
    for (const ControlPoint& cp : h.control_points) {
      worst = std::max(worst, (embedded->surface_displacement().row(cp.surface_vertex) -
                               hybrid->surface_displacement().row(cp.surface_vertex))
                                  .norm());
      largest = std::max(largest, embedded->surface_displacement().row(cp.surface_vertex).norm());
    }
    EXPECT_LT(worst, 1e-14 * largest) << "frame " << frame;
    EXPECT_EQ(coarse_report(*hybrid).at("newton_iterations_last_solve"), 1);
    EXPECT_EQ(coarse_report(*hybrid).at("relative_residual_last_solve"),
              coarse_report(*embedded).at("relative_residual_last_solve"));
  }
}

TEST(CoarseNewtonBudget, ABudgetWithLoadIncrementsIsAOneLineErrorNamingTheModel) {
  const HybridMesh& h = testing::scenario_mesh("cube-pull");
  for (const std::string model : {"embedded", "hybrid"}) {
    nlohmann::json p = with_budget(2);
    p["coarse_newton_load_steps"] = 3;
    std::string what = "(accepted)";
    try {
      testing::set_up_model(model, h, testing::kCubeBottom, p);
    } catch (const std::invalid_argument& e) {
      what = e.what();
    }
    EXPECT_EQ(what, model +
                        ": coarse mesh: coarse_newton_max_iterations_per_frame 2: a budgeted frame takes the whole "
                        "load at once, so coarse_newton_load_steps must be 1, not 3");
  }
}

}  // namespace
}  // namespace tb
