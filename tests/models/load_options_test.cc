// Issue 13's options at the model boundary: the disc load on models without it,
// element degree and material law of fem_distributed, and the scenario's
// disc_radius key. Each is a clear std::invalid_argument (or ScenarioError)
// naming the option, never a silent fallback.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>

#include "model.h"
#include "scenario.h"
#include "strict_json.h"
#include "test_support.h"

namespace tb {
namespace {

std::unique_ptr<Model> set_up(const std::string& name, const nlohmann::json& parameters) {
  return testing::set_up_model(name, testing::scenario_mesh("cube-pull"), testing::kCubeBottom, parameters);
}

std::string step_error(Model& model, double disc_radius) {
  try {
    model.step({{0, 0, 0.1}, {0, 0, 0.1}, disc_radius});
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(LoadOptions, ModelsWithoutDiscLoadsRefuseThemNamingTheOption) {
  for (const std::string name : {"pbd", "hybrid", "embedded"}) {
    auto model = set_up(name, nlohmann::json::object());
    for (double r : {0.005, std::nan("")}) {
      const std::string e = step_error(*model, r);
      EXPECT_NE(e.find("load.disc_radius"), std::string::npos) << name << ": " << e;
      EXPECT_EQ(e.rfind(name, 0), 0u) << "names the model: " << e;
    }
    EXPECT_EQ(step_error(*model, 0), "no error") << name << ": the point load still works";
  }
  auto fem = set_up("fem", {{"solver", "direct"}});
  const std::string e = step_error(*fem, 0.005);
  EXPECT_NE(e.find("load.disc_radius"), std::string::npos) << e;
  EXPECT_NE(e.find("fem_distributed"), std::string::npos) << e;
}

TEST(LoadOptions, DegreeAndMaterialLawOutOfRangeAreErrors) {
  const ModelInfo& fem = find_model("fem_distributed");
  for (const nlohmann::json& degree : {nlohmann::json(0), nlohmann::json(3), nlohmann::json(1.5)})
    EXPECT_THROW(resolve_parameters(fem.parameters, {{"degree", degree}}, "fem_distributed"), std::invalid_argument)
        << degree.dump();
  EXPECT_THROW(resolve_parameters(fem.parameters, {{"material_law", "hyperelastic"}}, "fem_distributed"),
               std::invalid_argument);
  // The serial FEM has neither: its parameters say so rather than ignore them.
  EXPECT_THROW(resolve_parameters(find_model("fem").parameters, {{"degree", 2}}, "fem"), std::invalid_argument);
}

TEST(LoadOptions, ScenarioDiscRadiusIsReadAndANegativeOneIsAnError) {
  const testing::TempFolder dir("load-options");
  std::ifstream in(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/cube-pull.json");
  nlohmann::json j = nlohmann::json::parse(in);
  j["load"]["disc_radius"] = 0.005;
  std::ofstream(dir / "disc.json") << j.dump();
  EXPECT_EQ(load_experiment(dir / "disc.json").scenarios.at(0).load.disc_radius, 0.005);
  EXPECT_EQ(load_experiment(dir / "disc.json").scenarios.at(0).load_at(3).disc_radius, 0.005) << "kept by the ramp";
  for (const nlohmann::json& bad : {nlohmann::json(-0.001), nlohmann::json("5 mm")}) {
    j["load"]["disc_radius"] = bad;
    std::ofstream(dir / "bad.json") << j.dump();
    try {
      load_experiment(dir / "bad.json");
      ADD_FAILURE() << bad.dump() << " accepted";
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("load.disc_radius"), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace tb
