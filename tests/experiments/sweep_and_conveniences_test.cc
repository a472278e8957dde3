// Sweep declarations, and scenarios stated relative to their mesh:
// support as the lowest fraction of the height, load at the highest
// or nearest surface vertex; supports that cannot hold; a static solve far outside
// its range.
#include <gtest/gtest.h>

#include <fstream>

#include "atomic_file.h"
#include "scenario_fixture.h"

namespace tb {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> names(const Experiment& e) {
  std::vector<std::string> out;
  for (const auto& s : e.scenarios) out.push_back(s.name);
  return out;
}

class Sweeps : public Scenarios {
 protected:
  Experiment sweep(const nlohmann::json& declaration, const std::string& reference = "fem-direct") {
    write("small.json", small_cube());
    return load_experiment(
        write("sweep.json",
              {{"name", "study"}, {"reference", reference}, {"scenarios", {"small.json"}}, {"sweep", declaration}}));
  }
};

TEST_F(Sweeps, OneAtATimeRunsTheBaseOnceAndEachOtherLevel) {
  const Experiment e = sweep(nlohmann::json::parse(R"({"factors": [
      {"key": "models.*.parameters.iterations", "values": [5, 20]},
      {"key": "models.hybrid.parameters.bending_angle", "values": ["unsigned", "signed"], "label": "angle"}]})"));
  // "unsigned" is the default, which the base does not state: it is the base, run once.
  EXPECT_EQ(names(e),
            (std::vector<std::string>{"small", "small__iterations=5", "small__iterations=20", "small__angle=signed"}));
  const Scenario& s = e.scenarios[2];
  EXPECT_EQ(s.sweep_base, "small");
  EXPECT_EQ(s.sweep_values["iterations"], 20);
  for (const ModelRun& run : s.models)
    if (run.model != "fem") {
      EXPECT_EQ(run.parameters.integer("iterations"), 20) << run.case_name;
    }
  EXPECT_EQ(e.scenarios[3].models[2].parameters.choice("bending_angle"), "signed");
  EXPECT_EQ(e.scenarios[3].models[1].parameters.choice("bending_angle"), "unsigned");  // pbd untouched
  // The experiment index tells the analysis what each point set.
  const nlohmann::json index = e.to_json();
  EXPECT_EQ(index["scenarios"][1]["sweep"]["values"]["iterations"], 5);
  EXPECT_EQ(index["scenarios"][1]["sweep"]["keys"]["iterations"], "models.*.parameters.iterations");
}

TEST_F(Sweeps, GridIsEveryCombinationAndCasesCanBeKept) {
  const Experiment e = sweep(nlohmann::json::parse(R"({"mode": "grid", "cases": ["fem-direct", "hybrid"],
      "factors": [{"key": "mesh.coarse_selection.target_nodes", "values": [20, 40]},
                  {"key": "models.hybrid.parameters.iterations", "values": [5, 10, 15]}]})"));
  ASSERT_EQ(e.scenarios.size(), 6u);
  EXPECT_EQ(e.scenarios[5].name, "small__target_nodes=40__iterations=15");
  EXPECT_EQ(e.scenarios[5].mesh.build.target_coarse_nodes, 40);
  for (const auto& s : e.scenarios) ASSERT_EQ(s.models.size(), 2u);
}

TEST_F(Sweeps, ArrayValuesAreNamedByValueNames) {
  const Experiment e = sweep(nlohmann::json::parse(R"({"factors": [{"key": "mesh.coarse_selection.include_points",
      "values": [[], [[0, 0, 0.1]]], "value_names": ["none", "load_point"], "label": "coarse_node_at"}]})"));
  ASSERT_EQ(e.scenarios.size(), 2u);  // "none" resolves to the base
  EXPECT_EQ(e.scenarios[1].name, "small__coarse_node_at=load_point");
  ASSERT_EQ(e.scenarios[1].mesh.build.include_points.size(), 1u);
  EXPECT_EQ(e.scenarios[1].mesh.build.include_points[0], Eigen::Vector3d(0, 0, 0.1));
}

TEST_F(Sweeps, ReferenceFactorKeepsOnlyTheReferenceCase) {
  const Experiment e = sweep(nlohmann::json::parse(R"({"factors": [
      {"key": "mesh.fine_tetgen.max_volume", "values": [2e-6, 5e-7], "role": "reference"}]})"));
  ASSERT_EQ(e.scenarios.size(), 2u);  // 2e-6 is the base's own value
  EXPECT_EQ(e.scenarios[0].models.size(), 3u);
  ASSERT_EQ(e.scenarios[1].models.size(), 1u);
  EXPECT_EQ(e.scenarios[1].models[0].case_name, "fem-direct");
}

TEST_F(Sweeps, BadDeclarationsAreErrorsNamingTheKey) {
  auto expect_sweep_error = [&](const std::string& declaration, const std::string& message) {
    try {
      sweep(nlohmann::json::parse(declaration));
      FAIL() << "accepted " << declaration;
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("sweep.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  };
  expect_sweep_error(R"({"factors": [{"key": "models.nope.parameters.iterations", "values": [1]}]})",
                     "no case matches 'nope'");
  expect_sweep_error(R"({"factors": []})", "factors: must be a non-empty array");
  expect_sweep_error(R"({"factors": [{"key": "models.*.parameters.iterations", "values": [0]}]})",
                     "iterations: 0 is outside");
  expect_sweep_error(R"({"factors": [{"key": "a.b", "values": [[1, 2]]}]})", "value_names: needed");
  expect_sweep_error(R"({"factors": [{"key": "a.b", "values": [1], "value_names": ["a b"]}]})",
                     "cannot be part of a folder name");
  expect_sweep_error(R"({"mode": "random", "factors": [{"key": "a.b", "values": [1]}]})", "mode");
  expect_sweep_error(R"({"cases": ["ghost"], "factors": [{"key": "a.b", "values": [1]}]})",
                     "names a case the base scenario does not have");
  expect_sweep_error(R"({"factors": [{"key": "frames.max", "values": [10]}, {"key": "x.max", "values": [2]}]})",
                     "'max' is used by two factors");
}

// A suite lists every model once: with "unsupported_cases": "skip" a case runs only
// where its model takes the scenario's tools; the others are listed with the reason.
// (pbd takes no sliding plate.)
TEST_F(Scenarios, UnsupportedCasesAreLeftOutWithTheirReasonWhenTheExperimentSaysSkip) {
  write_loaded_and_pressed();
  nlohmann::json experiment = {{"name", "suite"},
                               {"reference", "fem-direct"},
                               {"unsupported_cases", "skip"},
                               {"scenarios", {"small.json", "pressed.json"}},
                               {"models", {{{"name", "condensed"}, {"model", "condensed"}}, {{"model", "pbd"}}}}};
  const Experiment e = load_experiment(write("suite.json", experiment));
  ASSERT_EQ(e.scenarios.size(), 2u);
  EXPECT_EQ(e.scenarios[0].models.size(), 3u);  // the point load: every model takes it
  EXPECT_TRUE(e.scenarios[0].not_run.empty());
  ASSERT_EQ(e.scenarios[1].models.size(), 2u);  // the sliding plate: pbd takes none
  EXPECT_EQ(e.scenarios[1].models[0].case_name, "condensed");
  ASSERT_EQ(e.scenarios[1].not_run.size(), 1u);
  EXPECT_EQ(e.scenarios[1].not_run[0].first, "pbd");
  EXPECT_NE(e.scenarios[1].not_run[0].second.find("does not take sliding_plate"), std::string::npos)
      << e.scenarios[1].not_run[0].second;
  const nlohmann::json index = e.to_json();
  EXPECT_EQ(index["scenarios"][1]["not_run"][0]["case"], "pbd");
  EXPECT_FALSE(index["scenarios"][0].contains("not_run"));
  // Without the key, an unsupported case stays in and fails when it runs (the default).
  experiment.erase("unsupported_cases");
  EXPECT_EQ(load_experiment(write("suite.json", experiment)).scenarios[1].models.size(), 3u);
  // The reference may not be left out.
  experiment["unsupported_cases"] = "skip";
  experiment["reference"] = "pbd";
  experiment["scenarios"] = {"pressed.json"};
  try {
    load_experiment(write("suite.json", experiment));
    FAIL() << "a reference that cannot run a scenario was left out";
  } catch (const ScenarioError& err) {
    EXPECT_NE(std::string(err.what()).find("reference case 'pbd' cannot run it"), std::string::npos)
        << err.what();
  }
  experiment["unsupported_cases"] = "sometimes";
  expect_error_in(experiment, "suite.json", "unsupported_cases");
}

// An experiment's law_references: the reference under other material laws, recorded
// in experiment.json for the analysis (never ranked); each must name a case of some
// scenario, once, and be neither reference.
TEST_F(Scenarios, LawReferencesAreRecordedAndMustNameCasesOnce) {
  write("small.json", small_cube());
  nlohmann::json experiment = {{"name", "suite"},
                               {"reference", "fem-direct"},
                               {"law_references", {"pbd"}},
                               {"scenarios", {"small.json"}}};
  EXPECT_EQ(load_experiment(write("suite.json", experiment)).to_json()["law_references"],
            nlohmann::json::array({"pbd"}));
  experiment.erase("law_references");
  EXPECT_FALSE(load_experiment(write("suite.json", experiment)).to_json().contains("law_references"));
  for (const auto& [value, message] : std::vector<std::pair<nlohmann::json, std::string>>{
           {nlohmann::json::array(), "must be a non-empty array"},
           {"pbd", "must be a non-empty array"},
           {{1}, "entries must be case names"},
           {{"pbd", "pbd"}, "'pbd' is listed twice"},
           {{"fem-direct"}, "'fem-direct' is the experiment's reference"},
           {{"ghost"}, "no scenario has a case named 'ghost'"}}) {
    experiment["law_references"] = value;
    expect_error_in(experiment, "suite.json", "law_references: " + message);
  }
}

// tissuebench run SUITE --model NAME, NAME a registered model no case runs: a case of
// it (its defaults) joins every scenario that takes it.
TEST_F(Scenarios, AModelNoCaseRunsIsAddedToEveryScenarioThatTakesIt) {
  write_loaded_and_pressed();
  const std::string path = write("suite.json", {{"name", "suite"},
                                                {"reference", "fem-direct"},
                                                {"unsupported_cases", "skip"},
                                                {"scenarios", {"small.json", "pressed.json"}}});
  Experiment e = load_experiment(path);
  EXPECT_FALSE(add_model_everywhere(e, "fem"));      // a case runs it already
  EXPECT_FALSE(add_model_everywhere(e, "no_such"));  // not a model: the runner says no case matches
  ASSERT_TRUE(add_model_everywhere(e, "pbd"));
  EXPECT_EQ(e.scenarios[0].models.back().case_name, "pbd");
  EXPECT_EQ(e.scenarios[0].models.back().parameters.integer("iterations"), 10);  // its default
  ASSERT_EQ(e.scenarios[1].not_run.size(), 1u);  // it takes no sliding plate
  EXPECT_EQ(e.scenarios[1].not_run[0].first, "pbd");
  EXPECT_EQ(e.scenarios[1].models.size(), 1u);
}

// A refusal that depends on a case's parameters (the corotational solver has no
// contact; a real-time stepper on the coarse volume has none either) is made before
// setup too: the suite lists the case as not run, with the model's reason, not as a
// failed case; the same models with other parameters run. (A budgeted Newton frame
// has no contact set; the hybrid's exact_fine_fem ablation takes no tools.)
TEST_F(Scenarios, CasesRefusedByTheirParametersAreLeftOutBeforeSetup) {
  nlohmann::json palpated = small_cube();
  palpated["name"] = "palpated";
  palpated.erase("load");
  palpated["tools"] = nlohmann::json::parse(R"([{"type": "sphere", "radius": 0.01, "path": [[0, 0, 0, 0.11]]}])");
  palpated["models"] = {{{"name", "fem-direct"}, {"model", "fem"}}};
  write("palpated.json", palpated);
  const nlohmann::json experiment = {
      {"name", "suite"},
      {"reference", "fem-direct"},
      {"unsupported_cases", "skip"},
      {"scenarios", {"palpated.json"}},
      {"models",
       {{{"name", "fem-corotational"}, {"model", "fem"}, {"parameters", {{"solver", "corotational"}}}},
        {{"name", "fem-newton"}, {"model", "fem"}, {"parameters", {{"solver", "newton"}}}},
        {{"name", "fem-newton-1"},
         {"model", "fem"},
         {"parameters", {{"solver", "newton"}, {"newton_max_iterations_per_frame", 1}}}},
        {{"name", "vbd-embedded"}, {"model", "vbd"}, {"parameters", {{"volume", "coarse_embedded"}}}},
        {{"name", "vbd"}, {"model", "vbd"}},
        {{"name", "hybrid-exact"}, {"model", "hybrid"}, {"parameters", {{"control_points", "exact_fine_fem"}}}}}}};
  const Experiment e = load_experiment(write("suite.json", experiment));
  ASSERT_EQ(e.scenarios.size(), 1u);
  std::vector<std::string> kept;
  for (const ModelRun& run : e.scenarios[0].models) kept.push_back(run.case_name);
  EXPECT_EQ(kept, (std::vector<std::string>{"fem-newton", "vbd", "fem-direct"}));  // the experiment's, then the scenario's
  ASSERT_EQ(e.scenarios[0].not_run.size(), 4u);
  EXPECT_EQ(e.scenarios[0].not_run[0].first, "fem-corotational");
  EXPECT_EQ(e.scenarios[0].not_run[0].second,
            "fem: tools[0] (sphere): the corotational solver has no contact; use solver direct, iterative or newton");
  EXPECT_EQ(e.scenarios[0].not_run[1].first, "fem-newton-1");
  EXPECT_EQ(e.scenarios[0].not_run[1].second,
            "fem: tools[0] (sphere): the newton solver has no contact set in a budgeted frame "
            "(newton_max_iterations_per_frame 1; 0, to convergence, has); use solver direct or iterative");
  EXPECT_EQ(e.scenarios[0].not_run[2].first, "vbd-embedded");
  EXPECT_EQ(e.scenarios[0].not_run[2].second.rfind("vbd: tools[0] (sphere): volume coarse_embedded has no contact", 0),
            0u)
      << e.scenarios[0].not_run[2].second;
  EXPECT_EQ(e.scenarios[0].not_run[3].first, "hybrid-exact");
  EXPECT_EQ(e.scenarios[0].not_run[3].second,
            "hybrid: tools[0] (sphere): control_points exact_fine_fem takes no tools; use control_points coarse_fem");

  // What an earlier run left of a case now not run (its results, its failure) goes;
  // a case that can run but is not selected this time (vbd) keeps its results.
  const fs::path scenario_dir = dir / "out" / "suite" / "palpated";
  fs::create_directories(scenario_dir / "fem-corotational");
  fs::create_directories(scenario_dir / "vbd");
  for (const char* stale :
       {"fem-corotational/run.json", "fem-corotational.failed.json", "vbd-embedded.failed.json", "vbd/run.json"})
    std::ofstream(scenario_dir / stale) << "{}";
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.only_case = "fem-direct";
  for (const CaseOutcome& c : run_experiment(e, o)) EXPECT_TRUE(c.ok) << c.case_name << ": " << c.error;
  EXPECT_FALSE(fs::exists(scenario_dir / "fem-corotational"));
  EXPECT_FALSE(fs::exists(scenario_dir / "fem-corotational.failed.json"));
  EXPECT_FALSE(fs::exists(scenario_dir / "vbd-embedded.failed.json"));
  EXPECT_TRUE(fs::exists(scenario_dir / "fem-direct" / "run.json"));
  EXPECT_TRUE(fs::exists(scenario_dir / "vbd" / "run.json"));
}

// tissuebench run --skip-scenario NAME: that scenario left out, the others kept in
// order; a name the experiment does not have, or leaving none, is a one-line error.
TEST_F(Scenarios, SkippedScenariosAreLeftOutAndAnUnknownNameIsAnError) {
  write_loaded_and_pressed();
  const std::string path =
      write("suite.json", {{"name", "suite"}, {"reference", "fem-direct"}, {"scenarios", {"small.json", "pressed.json"}}});
  Experiment e = load_experiment(path);
  leave_out_scenarios(e, {"small", "small"});  // given twice: left out once
  ASSERT_EQ(e.scenarios.size(), 1u);
  EXPECT_EQ(e.scenarios[0].name, "pressed");
  for (const auto& [names, message] :
       std::vector<std::pair<std::vector<std::string>, std::string>>{
           {{"ghost"}, "--skip-scenario ghost: no scenario of experiment 'suite' has that name"},
           {{"small", "pressed"}, "--skip-scenario: no scenario of experiment 'suite' is left"}}) {
    Experiment fresh = load_experiment(path);
    try {
      leave_out_scenarios(fresh, names);
      FAIL() << "accepted " << message;
    } catch (const ScenarioError& err) {
      EXPECT_EQ(std::string(err.what()), message);
    }
  }
}

// tissuebench run --set: one value set in every scenario, as a sweep factor would,
// recorded in experiment.json; a key the loader does not know is an error naming it.
TEST_F(Scenarios, OverridesSetAKeyInEveryScenarioAndAreRecorded) {
  write("small.json", small_cube());
  nlohmann::json second = small_cube();
  second["name"] = "second";
  write("second.json", second);
  const std::string path = write("two.json", {{"name", "two"}, {"scenarios", {"small.json", "second.json"}}});
  const nlohmann::json overrides =
      nlohmann::json::parse(R"([["frames.max", 7], ["models.pbd.parameters.iterations", 3]])");
  const Experiment e = load_experiment(path, data_dir(), overrides);
  for (const Scenario& s : e.scenarios) {
    EXPECT_EQ(s.max_frames, 7) << s.name;
    EXPECT_EQ(s.models[1].parameters.integer("iterations"), 3) << s.name;
    EXPECT_EQ(s.models[2].parameters.integer("iterations"), 10) << s.name;  // the hybrid keeps its default
  }
  EXPECT_EQ(e.to_json()["overrides"], overrides);
  EXPECT_FALSE(load_experiment(path).to_json().contains("overrides"));
  try {
    load_experiment(path, data_dir(), nlohmann::json::parse(R"([["frames.bogus", 1]])"));
    FAIL() << "an unknown key was accepted";
  } catch (const ScenarioError& err) {
    EXPECT_NE(std::string(err.what()).find("unknown key 'bogus' (set in --set frames.bogus)"), std::string::npos)
        << err.what();
  }
  EXPECT_THROW(load_experiment(path, data_dir(), nlohmann::json::parse(R"([["models.nope.parameters.x", 1]])")),
               ScenarioError);
}

TEST_F(Scenarios, SupportAsLowestFractionAndLoadAtTheHighestVertex) {
  auto j = small_cube();
  j["support"] = {{"lowest_fraction", 0.25}};
  j["load"] = {{"at", "highest_surface_vertex"}, {"force", {0, 0, 0.1}}, {"ramp_frames", 5}};
  Experiment e = load_experiment(write("s.json", j));
  SurfaceMesh surface;
  surface.V.resize(3, 3);
  surface.V << 0, 0, -1, 1, 0, 3, 2, 0, 1;
  Scenario s = e.scenarios[0];
  resolve_on_mesh(s, surface);
  EXPECT_DOUBLE_EQ(s.support.max.z(), -1 + 0.25 * 4);
  EXPECT_TRUE(std::isinf(s.support.min.x()));
  EXPECT_EQ(s.load.point, Eigen::Vector3d(1, 0, 3));
  j["load"] = {{"at", "nearest_surface_vertex"}, {"point", {1.9, 0, 0.8}}, {"force", {0, 0, 0.1}}};
  s = load_experiment(write("s.json", j)).scenarios[0];
  resolve_on_mesh(s, surface);
  EXPECT_EQ(s.load.point, Eigen::Vector3d(2, 0, 1));
  EXPECT_EQ(s.to_json()["load"]["point_given"], nlohmann::json({1.9, 0, 0.8}));

  j["support"] = {{"lowest_fraction", 0.25}, {"min", {0, 0, 0}}};
  expect_error(j, "give either min/max or lowest_fraction");
  j["support"] = {{"lowest_fraction", 1.5}};
  expect_error(j, "support.lowest_fraction: 1.5 is out of range");
  j = small_cube();
  j["load"] = {{"at", "highest_surface_vertex"}, {"point", {0, 0, 0}}, {"force", {0, 0, 1}}};
  expect_error(j, "load.point: not used with at = highest_surface_vertex");
}

TEST_F(Scenarios, ConveniencesRunEndToEndAndRunJsonRecordsTheResolvedValues) {
  auto j = small_cube();
  j["support"] = {{"lowest_fraction", 0.01}};
  j["load"] = {{"at", "highest_surface_vertex"}, {"force", {0, 0, 0.1}}, {"ramp_frames", 5}};
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  for (const auto& c : run_experiment(load_experiment(write("s.json", j)), o))
    EXPECT_TRUE(c.ok) << c.case_name << ": " << c.error;
  const auto run = nlohmann::json::parse(read_file((dir / "out" / "small" / "small" / "hybrid" / "run.json").string()));
  EXPECT_EQ(run["scenario_resolved"]["load"]["at"], "highest_surface_vertex");
  EXPECT_DOUBLE_EQ(run["scenario_resolved"]["load"]["point"][2].get<double>(), 0.1);
  EXPECT_DOUBLE_EQ(run["scenario_resolved"]["support"]["max"][2].get<double>(), 0.001);
}

TEST_F(Scenarios, ASupportThatCannotHoldIsAnErrorNamingBoxAndCounts) {
  auto j = small_cube();
  // One bottom corner only: a single node of every mesh.
  j["support"] = {{"min", {-0.051, -0.051, -1e-9}}, {"max", {-0.049, -0.049, 1e-9}}};
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  const auto out = run_experiment(load_experiment(write("s.json", j)), o);
  ASSERT_EQ(out.size(), 3u);
  for (const auto& c : out) {
    EXPECT_FALSE(c.ok) << c.case_name;
    EXPECT_NE(c.error.find("clamps 1 of the"), std::string::npos) << c.error;
    EXPECT_NE(c.error.find("at least three nodes not on one line"), std::string::npos) << c.error;
    EXPECT_NE(c.error.find("support box (-0.051, -0.051, -1e-09) to (-0.049, -0.049, 1e-09)"), std::string::npos)
        << c.error;
  }
  // A bottom edge: many nodes, all on one line.
  j["support"] = {{"min", {-1, -0.051, -1e-9}}, {"max", {1, -0.049, 1e-9}}};
  for (const auto& c : run_experiment(load_experiment(write("s.json", j)), o)) {
    EXPECT_FALSE(c.ok) << c.case_name;
    EXPECT_NE(c.error.find("all on one line"), std::string::npos) << c.error;
  }
}

TEST_F(Scenarios, AStaticSolveFarOutsideItsRangeSaysSo) {
  auto j = small_cube();
  j["load"]["force"] = {0, 0, 1e6};
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.only_case = "fem-direct";
  const auto out = run_experiment(load_experiment(write("s.json", j)), o);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].ok);
  EXPECT_NE(out[0].error.find("a linear small-strain solution far outside its range"), std::string::npos)
      << out[0].error;
  EXPECT_EQ(out[0].error.find("diverged"), std::string::npos) << out[0].error;
}

}  // namespace
}  // namespace tb

namespace tb {
namespace {

TEST_F(Scenarios, ADynamicCaseWritesAParaViewTimeSeriesWhenAsked) {
  auto j = small_cube();
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.only_case = "pbd";
  ASSERT_TRUE(run_experiment(load_experiment(write("s.json", j)), o).at(0).ok);
  const fs::path pbd = dir / "out" / "small" / "small" / "pbd";
  EXPECT_FALSE(fs::exists(pbd / "series")) << "off by default";
  EXPECT_FALSE(fs::exists(pbd / "surface_series.pvd"));

  j["output"] = {{"series_every", 7}};
  const auto outcome = run_experiment(load_experiment(write("s.json", j)), o).at(0);
  ASSERT_TRUE(outcome.ok) << outcome.error;
  const std::string pvd = read_file((pbd / "surface_series.pvd").string());
  // Frames 0, 7, 14, ... and the last (steady) frame, each a file that exists.
  size_t datasets = 0, at = 0;
  while ((at = pvd.find("<DataSet timestep=", at)) != std::string::npos) {
    const size_t file = pvd.find("file=\"", at) + 6;
    const std::string name = pvd.substr(file, pvd.find('"', file) - file);
    EXPECT_TRUE(fs::exists(pbd / name)) << name;
    ++datasets;
    ++at;
  }
  EXPECT_EQ(datasets, static_cast<size_t>((outcome.frames - 1) / 7 + 1 + ((outcome.frames - 1) % 7 != 0)));
  EXPECT_NE(pvd.find("timestep=\"0\" file=\"series/surface_000000.vtu\""), std::string::npos) << pvd;
  j["output"] = {{"series_every", -1}};
  expect_error(j, "output.series_every");
}

TEST_F(Scenarios, ADynamicCaseRecordsItsFirstFramesAtTrackedVerticesAndMayStopEarly) {
  auto j = small_cube();
  j["models"] = nlohmann::json::parse(R"([{"model": "pbd", "max_frames": 7}, {"name": "long", "model": "pbd",
      "max_frames": 100000}, {"name": "fem-direct", "model": "fem"}])");
  j["frames"]["max"] = 12;
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  const auto outcomes = run_experiment(load_experiment(write("s.json", j)), o);
  ASSERT_EQ(outcomes.size(), 3u);
  EXPECT_EQ(outcomes[0].frames, 7) << "its own budget";
  EXPECT_EQ(outcomes[1].frames, 12) << "never beyond frames.max";
  const fs::path folder = dir / "out" / "small" / "small";
  const nlohmann::json run = nlohmann::json::parse(read_file((folder / "pbd" / "run.json").string()));
  const std::vector<int> tracked = run["trajectory"]["vertices"];
  // The vertex nearest the load point first, then spread observed vertices.
  ASSERT_GE(tracked.size(), 2u);
  std::istringstream csv(read_file((folder / "pbd" / "trajectory.csv").string()));
  std::string header, line, last_row;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("frame,v" + std::to_string(tracked[0]) + "_ux,", 0), 0u) << header;
  int rows = 0;
  while (std::getline(csv, line)) ++rows, last_row = line;
  EXPECT_EQ(rows, 7);
  // The surface the case ends on is its trajectory's last row.
  const std::string last = last_row.substr(last_row.find(',') + 1);
  const std::string surface = read_file((folder / "pbd" / "surface.csv").string());
  const size_t row = surface.find("\n" + std::to_string(tracked[0]) + ",");
  ASSERT_NE(row, std::string::npos);
  std::istringstream fields(surface.substr(row + 1));
  std::string value;
  std::vector<double> at_tracked;
  for (int k = 0; k < 7 && std::getline(fields, value, ','); ++k)
    if (k >= 4) at_tracked.push_back(std::stod(value));
  std::istringstream first(last);
  for (double u : at_tracked) {
    std::getline(first, value, ',');
    EXPECT_NEAR(std::stod(value), u, 1e-7 * std::abs(u) + 1e-15);
  }
  EXPECT_FALSE(fs::exists(folder / "fem-direct" / "trajectory.csv")) << "a static case has no transient";
  j["models"][0]["max_frames"] = -1;
  expect_error(j, "max_frames");
}

}  // namespace
}  // namespace tb
