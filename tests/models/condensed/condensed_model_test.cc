// The condensed (precomputed-response) FEM is the fine FEM with the direct solver,
// to round-off, on the cube and the liver, whichever way its columns are made.
#include <gtest/gtest.h>

#include "model.h"
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
    // Every surface vertex's columns, plus any interior node the load's tet reaches.
    EXPECT_GE(r["loaded_nodes_precomputed"].get<double>(), n);
    EXPECT_NEAR(r["response_memory_mib"].get<double>(),
                9 * n * r["loaded_nodes_precomputed"].get<double>() * 8 / (1024.0 * 1024.0), 1e-9);
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
