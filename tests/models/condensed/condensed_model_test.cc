// The condensed (precomputed-response) FEM is the fine FEM with the direct solver,
// to round-off, on the cube and the liver, whichever way its columns are made, and
// under tools (a grasp, bonded and sliding plates) with their reactions and probes.
#include <gtest/gtest.h>

#include "model.h"
#include "tool_placement.h"
#include "test_support.h"

namespace tb {
namespace {

std::unique_ptr<Model> make(const std::string& name, const HybridMesh& mesh, const SupportBox& support,
                            const nlohmann::json& params = {},
                            const std::vector<Load>& loads = testing::kCubePull.loads()) {
  return testing::set_up_model(name, mesh, support, params, loads);
}

struct Case {
  std::string scenario;
  SupportBox support;
  testing::PointForce load;
};
void PrintTo(const Case& c, std::ostream* os) { *os << c.scenario; }

// Support and load as in experiments/scenarios/{cube,liver}-pull.json.
const Case kCube{"cube-pull", {{-1, -1, -1e-9}, {1, 1, 1e-9}}, {{0, 0, 0.1}, {0, 0, 1}}};
const Case kLiver{"liver-pull", {{-1, -1, -1}, {1, 1, -0.0101}}, {{-0.01731, 0.02453, 0.0253}, {0, 0, 0.1}}};

class CondensedEqualsFem : public ::testing::TestWithParam<std::tuple<Case, std::string>> {};

TEST_P(CondensedEqualsFem, ToRoundOff) {
  const auto& [c, precompute] = GetParam();
  const HybridMesh& mesh = testing::scenario_mesh(c.scenario);
  auto fem = make("fem", mesh, c.support, {{"solver", "direct"}}, c.load.loads());
  auto condensed = make("condensed", mesh, c.support, {{"precompute", precompute}}, c.load.loads());
  // Two load levels (the runner ramps the load) and the reversed load.
  for (double scale : {0.3, 1.0, -1.0}) {
    const FrameLoads load = c.load.scaled(scale).frame();
    fem->step(load);
    condensed->step(load);
    const Displacements& a = fem->surface_displacement();
    const Displacements& b = condensed->surface_displacement();
    ASSERT_GT(a.norm(), 0);
    EXPECT_LT((a - b).norm(), 1e-10 * a.norm()) << c.scenario << " " << precompute << " scale " << scale;
  }
  const nlohmann::json r = condensed->report();
  const double n = static_cast<double>(mesh.fine_surface.V.rows());
  if (precompute == "surface_vertices") {
    // Every surface vertex's columns, plus any interior node the load's tet reaches;
    // each with 9 doubles per output and for the support's reaction.
    EXPECT_GE(r["loaded_nodes_precomputed"].get<double>(), n);
    EXPECT_NEAR(r["response_memory_mib"].get<double>(),
                9 * (n + 1) * r["loaded_nodes_precomputed"].get<double>() * 8 / (1024.0 * 1024.0), 1e-9);
  } else {
    EXPECT_LE(r["loaded_nodes_precomputed"].get<int>(), 4);  // the load's tet only
  }
}

INSTANTIATE_TEST_SUITE_P(CubeAndLiver, CondensedEqualsFem,
                         ::testing::Combine(::testing::Values(kCube, kLiver),
                                            ::testing::Values("surface_vertices", "on_demand")),
                         [](const auto& info) {
                           const std::string& s = std::get<0>(info.param).scenario;
                           return s.substr(0, s.find('-')) + "_" + std::get<1>(info.param);
                         });

/// Tools are Dirichlet values whose responses superpose: under a grasp, a bonded
/// and a sliding plate, a point force and gravity, at two frames and with the tools
/// at rest, the condensed model's surface, reactions and probes are the direct fine
/// FEM's to round-off.
TEST(CondensedModel, UnderToolsItIsTheFemWithItsReactionsAndProbes) {
  const HybridMesh& mesh = testing::scenario_mesh("cube-pull");
  const std::vector<Tool> tools = {Tool::grasp({-0.02, 0.01, 0.1}, 0.012, "tools[0]"),
                                   Tool::plate({{-1, 0.0499, 0.03}, {1, 1, 0.07}}, false, 2, "tools[1]"),
                                   Tool::plate({{0.0499, -0.04, 0.03}, {1, 0.04, 0.07}}, true, 0, "tools[2]")};
  const std::vector<Load> loads = {Load::point_force({0.02, 0, 0.1}, "loads[0]"), Load::body_force("loads[1]")};
  Points probes(2, 3);
  probes << 0.01, -0.013, 0.04, -0.02, 0.02, 0.07;
  std::unique_ptr<Model> models[2];
  const char* names[2] = {"fem", "condensed"};
  for (int k = 0; k < 2; ++k) {
    const ModelInfo& info = find_model(names[k]);
    const nlohmann::json given = k == 0 ? nlohmann::json{{"solver", "direct"}} : nlohmann::json::object();
    Problem p{&mesh, Material{}, LoadCase{testing::kCubeBottom, loads, tools},
              resolve_parameters(info.parameters, given, info.name), probes};
    models[k] = info.create();
    models[k]->setup(p);
  }
  for (const FrameLoads& frame :
       {FrameLoads{{{0, 0, 0.2}, {0, 0, -9.81}}, {{0, 0, 0.004}, {0, -0.002, 0}, {-0.001, 0, 0}}},
        FrameLoads{{{0.1, 0, -0.3}, {0, 0, -9.81}}, {{0.002, 0, -0.003}, {0, 0.001, 0}, {0.002, 0, 0}}},
        FrameLoads{{{0, 0, 0.2}, {0, 0, 0}}, {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}}}}) {
    for (auto& m : models) m->step(frame);
    const Displacements& a = models[0]->surface_displacement();
    EXPECT_LT((a - models[1]->surface_displacement()).norm(), 1e-10 * a.norm());
    const std::vector<Eigen::Vector3d>& ra = *models[0]->reaction_forces();
    const std::vector<Eigen::Vector3d>* rb = models[1]->reaction_forces();
    ASSERT_NE(rb, nullptr);
    ASSERT_EQ(rb->size(), 4u);
    double scale = 0;
    for (const Eigen::Vector3d& f : ra) scale += f.norm();
    for (size_t t = 0; t < ra.size(); ++t) EXPECT_LT((ra[t] - (*rb)[t]).norm(), 1e-9 * scale) << t;
    const Points* pa = models[0]->probe_displacements();
    const Points* pb = models[1]->probe_displacements();
    ASSERT_NE(pb, nullptr);
    EXPECT_LT((*pa - *pb).norm(), 1e-10 * pa->norm());
  }
  const double n_out = static_cast<double>(mesh.fine_surface.V.rows() + 8);
  const nlohmann::json r = models[1]->report();
  // Per column block: 9 doubles for each output and for each reaction (3 tools, the support).
  EXPECT_NEAR(r["response_memory_mib"].get<double>(),
              9 * (n_out + 4) * (r["loaded_nodes_precomputed"].get<double>() + 1 + 3) * 8 / (1024.0 * 1024.0), 1e-9)
      << "node columns, gravity's own, one per tool";
}

TEST(CondensedModel, NoFineVolumeIsAClearError) {
  HybridMesh no_volume = testing::scenario_mesh("cube-pull");
  no_volume.fine_volume = TetMesh{};
  try {
    make("condensed", no_volume, kCube.support);
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("condensed: the scenario provides no fine volume mesh"), std::string::npos);
  }
}

}  // namespace
}  // namespace tb
