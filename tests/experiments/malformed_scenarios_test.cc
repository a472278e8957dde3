// Scenario and experiment files the fuzz target of the loader (tests/fuzz/
// scenario_target.cc, docs/robustness.md) found or aimed at: each is now refused
// with one line naming the file, where before it overflowed the stack, escaped as an
// exception without the file's name, or expanded into more scenarios than memory holds.
#include <gtest/gtest.h>

#include <fstream>

#include "scenario_fixture.h"
#include "truth_cube.h"

namespace tb {
namespace {

class MalformedScenarios : public Scenarios {
 protected:
  /// load_experiment of `text` as bad.json throws one line naming the file and `message`.
  void expect_refused(const std::string& text, const std::string& message) {
    const std::string p = (dir / "bad.json").string();
    std::ofstream(p, std::ios::binary) << text;
    try {
      load_experiment(p);
      ADD_FAILURE() << "accepted: " << text.substr(0, 80);
    } catch (const ScenarioError& e) {
      const std::string m = e.what();
      EXPECT_NE(m.find("bad.json"), std::string::npos) << m;
      EXPECT_NE(m.find(message), std::string::npos) << m;
      EXPECT_EQ(m.find_first_of("\n\r"), std::string::npos) << m;
    }
  }
};

TEST_F(MalformedScenarios, DeepNestingIsRefusedBeforeTheStackOverflows) {
  // nlohmann's dump() and destructor recurse once per level: 10^5 levels overflowed the stack.
  expect_refused("{\"name\": " + std::string(100000, '[') + std::string(100000, ']') + "}",
                 "JSON nested deeper than 64 levels");
}

TEST_F(MalformedScenarios, ANumberBeyondDoubleIsAMalformedJsonError) {
  // nlohmann throws out_of_range (not parse_error) for 1e400: it escaped uncaught.
  expect_refused(R"({"name": "x", "frames": {"max": 1e400}})", "malformed JSON");
}

TEST_F(MalformedScenarios, AMultiLineValueIsQuotedOnOneLine) {
  nlohmann::json j = small_cube();
  j["observe"] = {{"vertices", {{"a\nb", 1}}}};
  expect_refused(j.dump(), "observe.vertices: must be a string, found {\"a\\nb\":1}");
}

TEST_F(MalformedScenarios, AnExperimentEntryThatIsNoFileIsNamed) {
  expect_refused(R"({"name": "e", "scenarios": ["."]})", "'.': no such scenario file");
  expect_refused(R"({"name": "e", "scenarios": ["absent.json"]})", "'absent.json': no such scenario file");
}

// Experiment, scenario and case names become folders of the results tree (and a case
// not run has its folder removed): each must be one folder name.
TEST_F(MalformedScenarios, NamesThatAreNoSingleFolderAreRefused) {
  for (const char* bad : {"", ".", "..", "a/b"}) {
    nlohmann::json scenario = small_cube();
    scenario["name"] = bad;
    expect_refused(scenario.dump(), "name: must be a folder name (not empty, '.' or '..', no '/')");
    nlohmann::json experiment = {{"name", bad}, {"reference", "fem-direct"}, {"scenarios", {"small.json"}}};
    write("small.json", small_cube());
    expect_refused(experiment.dump(), "name: must be a folder name (not empty, '.' or '..', no '/')");
  }
  for (const char* bad : {"", ".", "..", "../escape", "mesh"}) {
    nlohmann::json scenario = small_cube();
    scenario["models"][0]["name"] = bad;
    expect_refused(scenario.dump(), "'" + std::string(bad) + "' must be a folder name (not empty, '.', '..' or 'mesh', no '/')");
  }
}

TEST_F(MalformedScenarios, ASweepMakingTooManyScenariosIsRefusedBeforeExpanding) {
  write("small.json", small_cube());
  nlohmann::json values = nlohmann::json::array();
  for (int i = 1; i <= 30; ++i) values.push_back(i);
  nlohmann::json factors = nlohmann::json::array();
  for (const char* key : {"mesh.nx", "mesh.ny", "mesh.nz"}) factors.push_back({{"key", key}, {"values", values}});
  const nlohmann::json experiment = {
      {"name", "e"}, {"scenarios", {"small.json"}}, {"sweep", {{"mode", "grid"}, {"factors", factors}}}};
  expect_refused(experiment.dump(), "would make 2.7e+04 scenarios, more than 10000");
}

TEST_F(MalformedScenarios, ASweptScenarioWithoutModelsIsNamed) {
  nlohmann::json base = small_cube();
  base["models"] = 3;
  write("small.json", base);
  const nlohmann::json experiment = {
      {"name", "e"},
      {"scenarios", {"small.json"}},
      {"sweep", {{"cases", {"fem-direct"}}, {"factors", {{{"key", "mesh.nx"}, {"values", {3}}}}}}}};
  expect_refused(experiment.dump(), "the scenario swept has no \"models\" array");
}

TEST_F(MalformedScenarios, ATruthCubeTableQuotedInAMessageStaysOnOneLine) {
  // Found by the truth_cube_csv fuzz target: a carriage return in the strain labels.
  const std::string p = (dir / "beads.csv").string();
  std::ofstream(p, std::ios::binary) << std::string(5, '\n') << "bead nominal location,,,no strain,,,5% st\rrain\n";
  try {
    read_truth_cube_table(p);
    ADD_FAILURE() << "accepted";
  } catch (const std::runtime_error& e) {
    const std::string m = e.what();
    EXPECT_EQ(m.rfind(p + ": line 6: expected 'no strain'", 0), 0u) << m;
    EXPECT_NE(m.find("5% st\\rrain"), std::string::npos) << m;
    EXPECT_EQ(m.find_first_of("\n\r"), std::string::npos) << m;
  }
}

}  // namespace
}  // namespace tb
