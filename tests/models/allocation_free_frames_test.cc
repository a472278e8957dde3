// A frame (FEM solve, PBD or hybrid step) does not touch the heap once the model
// is set up, so a simulator's frame time has no allocator in it: the rule of
// Model::step (docs/extending.md). Counted by replacing malloc and friends
// (tests/allocation_counter.cc).
#include <gtest/gtest.h>

#include <ostream>

#include "allocation_counter.h"
#include "elastic_body.h"
#include "model.h"
#include "test_support.h"

namespace tb {
namespace {

struct Case {
  std::string model;
  nlohmann::json parameters;
  /// Every load kind the model takes at once (a point force, a disc traction and
  /// gravity), instead of the point force alone.
  bool every_load_kind = false;
};
void PrintTo(const Case& c, std::ostream* os) {
  *os << c.model << " " << c.parameters.dump() << (c.every_load_kind ? " every load kind" : "");
}

class AllocationFreeFrame : public ::testing::TestWithParam<Case> {};

TEST_P(AllocationFreeFrame, StepAllocatesNothingAfterTheFirstFrame) {
  const ModelInfo& info = find_model(GetParam().model);
  std::vector<Load> loads = {Load::point_force({0, 0, 0.1})};
  if (GetParam().every_load_kind) {
    ASSERT_TRUE(info.takes(LoadKind::SurfaceTraction) && info.takes(LoadKind::BodyForce)) << info.name;
    loads.push_back(Load::surface_traction({0.01, 0, 0.1}, 0.005, "loads[1]"));
    loads.push_back(Load::body_force("loads[2]"));
  }
  Problem p{&testing::scenario_mesh("cube-pull"), Material{}, LoadCase{testing::kCubeBottom, loads, {}},
            resolve_parameters(info.parameters, GetParam().parameters, GetParam().model), Points()};
  auto model = info.create();
  model->setup(p);
  FrameLoads frame;
  frame.values.assign(loads.size(), Eigen::Vector3d(0, 0, 0.02));
  model->step(frame);  // the first frame may size work arrays (warm start)
  // The counter itself is checked: building a vector does allocate.
  ASSERT_GT(testing::allocations_during([] { std::vector<double> v(100); }), 0);
  const long count = testing::allocations_during([&] {
    for (int f = 2; f <= 20; ++f) {  // a ramp, as the runner does
      for (Eigen::Vector3d& v : frame.values) v = Eigen::Vector3d(0.0, 0.0, 0.02 * f);
      model->step(frame);
    }
  });
  EXPECT_EQ(count, 0) << GetParam().model << " " << GetParam().parameters.dump();
}

/// The reference solves, not real-time models: fem_distributed (MPI; its Trilinos
/// vectors and Newton state are allocated per solve) and fem_dynamic (a CHOLMOD
/// factorisation of the tangent per Newton iteration), as the fem model's
/// `solver newton`, which the list below leaves out too.
bool reference_solve(const ModelInfo& m) { return m.name == "fem_distributed" || m.name == "fem_dynamic"; }

/// Every registered model with its defaults, and the non-default solvers; not the
/// reference solves.
std::vector<Case> every_model() {
  std::vector<Case> cases;
  for (const ModelInfo& m : registered_models())
    if (!reference_solve(m)) cases.push_back({m.name, nlohmann::json::object()});
  cases.push_back({"fem", {{"solver", "iterative"}}});
  cases.push_back({"hybrid", {{"coarse_solver", "iterative"}}});
  cases.push_back({"fem", {{"solver", "corotational"}}});
  cases.push_back({"hybrid", {{"coarse_solver", "corotational"}}});
  cases.push_back({"fem", {{"solver", "corotational"}, {"corotational_update", "per_frame"}}});
  cases.push_back({"hybrid", {{"control_points", "exact_fine_fem"}}});
  cases.push_back({"pbd", {{"threads", 2}}});
  cases.push_back({"hybrid", {{"threads", 2}}});
  cases.push_back({"pbd", {{"domains", 2}, {"threads", 2}}});  // positions copied in and out in domain order
  cases.push_back({"hybrid", {{"domains", 2}, {"threads", 2}, {"precision", "single"}}});
  cases.push_back({"pbd", {{"substeps", 3}}});
  cases.push_back({"hybrid", {{"substeps", 2}, {"surface_support", "coarse_fem"}}});
  cases.push_back({"pbd", {{"kernels", "reference"}}});
  cases.push_back({"pbd", {{"precision", "single"}}});
  cases.push_back({"hybrid", {{"load_spread", "surface_triangle"}}});
  cases.push_back({"pbd", {{"constraint_solve", "xpbd"}, {"kernels", "reference"}, {"bending_angle", "signed"}}});
  cases.push_back({"hybrid", {{"constraint_solve", "xpbd"}, {"kernels", "reference"}, {"bending_angle", "signed"}}});
  cases.push_back({"pd", {{"solve", "local_global"}, {"material_law", "arap_volume"}}});
  cases.push_back({"pd", {{"threads", 2}, {"weight", "shear"}}});  // halvings in the line search
  cases.push_back({"vbd", {{"threads", 2}}});  // the positivity check of a frame's start on the thread team
  for (const ModelInfo& m : registered_models())
    if (!reference_solve(m) && m.takes(LoadKind::SurfaceTraction) && m.takes(LoadKind::BodyForce))
      cases.push_back({m.name, nlohmann::json::object(), true});
  // The real-time steppers on the coarse mesh with the fine surface embedded.
  for (const char* m : {"vbd", "xpbd_neo", "pd"}) {
    cases.push_back({m, {{"volume", "coarse_embedded"}}});
    cases.push_back({m, {{"volume", "coarse_embedded"}}, true});
  }
  cases.push_back({"condensed", {{"precompute", "on_demand"}}, true});
  cases.push_back({"hybrid", {{"control_points", "exact_fine_fem"}}, true});
  return cases;
}

INSTANTIATE_TEST_SUITE_P(Models, AllocationFreeFrame, ::testing::ValuesIn(every_model()),
                         [](const ::testing::TestParamInfo<Case>& i) {
                           std::string name = i.param.model;
                           for (const auto& [key, value] : i.param.parameters.items())
                             name += "_" + (value.is_string() ? value.get<std::string>() : key + value.dump());
                           return name + (i.param.every_load_kind ? "_every_load_kind" : "");
                         });

/// A frame with a rigid sphere held pressed into the cube's top allocates nothing once
/// the contact set holds: in every dynamic model that takes a sphere. Not the static
/// FEM's: its active-set solve (models/numerics/contact/sphere_contact.cc) builds its
/// candidates' vectors and Schur complement per iteration (measured: 910 allocations
/// in 10 held frames of the linear `fem`), as Newton's contact does. Projective
/// dynamics keeps its Schur complement's storage from one constrained step to the
/// next, so a step whose contact set has the last step's size allocates nothing and
/// one whose set changed size does; the counted frames (41-50) come after its set has
/// settled (9 nodes from frame 30 at 50 ms steps: sphere_contact_test.cc), and the
/// nodes in contact at each frame's end are checked unchanged over them (a change of
/// the set within a frame would show in the count). The tet steppers take 50 ms
/// steps; tested on this cube with one sphere only.
TEST(AllocationFreeContactFrame, AHeldSphereAllocatesNothingOnceTheContactSetHolds) {
  // OpenBLAS on one thread, as the runner has it (experiments/tissuebench_main.cc):
  // pd's blocked contact solve (dtrsm, dgemm) allocates buffers on OpenBLAS's
  // threaded path, and no reported frame takes that path.
  use_one_thread();
  const double R = 0.03;
  const Eigen::Vector3d above(0, 0, 0.1 + R), pressed(0, 0, 0.1 + R - 0.01);
  int models = 0;
  for (const ModelInfo& info : registered_models()) {
    if (!info.takes(ToolKind::Sphere) || !info.dynamic || reference_solve(info)) continue;
    ++models;
    const bool tet_stepper = info.name == "vbd" || info.name == "xpbd_neo" || info.name == "pd";
    const nlohmann::json given = tet_stepper ? nlohmann::json{{"time_step", 0.05}} : nlohmann::json::object();
    Problem p{&testing::scenario_mesh("cube-pull"), Material{},
              LoadCase{testing::kCubeBottom, {}, {Tool::sphere(above, R, "tools[0]")}},
              resolve_parameters(info.parameters, given, info.name), Points()};
    auto model = info.create();
    model->setup(p);
    const FrameLoads frame{{}, {pressed}};
    for (int f = 0; f < 40; ++f) model->step(frame);
    const int points = (*model->tool_contacts())[0].points;
    ASSERT_GT(points, 0) << info.name;
    bool same_set_size = true;
    const long count = testing::allocations_during([&] {
      for (int f = 0; f < 10; ++f) {
        model->step(frame);
        same_set_size = same_set_size && (*model->tool_contacts())[0].points == points;
      }
    });
    EXPECT_EQ(count, 0) << info.name;
    if (info.name == "pd") {
      EXPECT_TRUE(same_set_size) << "pd: its contact set changed size while counted";
    }
  }
  EXPECT_EQ(models, 5) << "pbd, hybrid, vbd, xpbd_neo, pd";
}

}  // namespace
}  // namespace tb
