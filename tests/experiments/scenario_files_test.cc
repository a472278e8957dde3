// Scenario files that extend others, experiment-level model lists and roles, and
// third-party data read through the data directory (docs/scenario_schema.md,
// README "Data").
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include "atomic_file.h"
#include "cli_run.h"
#include "file_schema.h"
#include "mesh_io.h"
#include "scenario_fixture.h"

namespace tb {
namespace {
namespace fs = std::filesystem;

std::vector<std::string> cases(const Scenario& s) {
  std::vector<std::string> out;
  for (const auto& m : s.models) out.push_back(m.case_name);
  return out;
}

class ScenarioFiles : public Scenarios {
 protected:
  /// load_experiment(file) must fail with a message holding every one of `parts`.
  void expect_load_error(const std::string& file, const std::vector<std::string>& parts) {
    try {
      load_experiment(file);
      FAIL() << "accepted: " << file;
    } catch (const ScenarioError& e) {
      const std::string what = e.what();
      EXPECT_EQ(what.find('\n'), std::string::npos) << what;
      for (const auto& part : parts) EXPECT_NE(what.find(part), std::string::npos) << what;
    }
  }
};

TEST_F(ScenarioFiles, ExtendsOverridesScalarsAndArraysAndMergesObjects) {
  auto base = small_cube();
  base["material"] = {{"youngs_modulus", 4000}, {"density", 900}};
  write("base.json", base);
  const std::string ext = write("ext.json", nlohmann::json::parse(R"({
    "extends": "base.json", "name": "ext",
    "material": {"poisson_ratio": 0.3},
    "load": {"force": [0, 0, -0.1]},
    "frames": {"steady_tolerance": null},
    "models": [{"model": "pbd", "parameters": {"iterations": 5}}]
  })"));
  const Scenario s = load_experiment(ext).scenarios.at(0);
  EXPECT_EQ(s.name, "ext");
  EXPECT_EQ(s.file, ext);
  EXPECT_EQ(s.material.youngs_modulus, 4000);  // the base's, kept by the object merge
  EXPECT_EQ(s.material.density, 900);
  EXPECT_EQ(s.material.poisson_ratio, 0.3);  // the extending file's
  EXPECT_EQ(s.load.force.z(), -0.1);         // an array replaces
  EXPECT_EQ(s.load.point.z(), 0.1);          // its sibling kept
  EXPECT_EQ(s.ramp_frames, 5);
  const Scenario defaults;
  EXPECT_EQ(s.steady_tolerance, defaults.steady_tolerance);  // null removed the base's value: the default
  EXPECT_EQ(s.max_frames, 300);
  EXPECT_EQ(cases(s), std::vector<std::string>{"pbd"});  // the model list replaced, not appended
  EXPECT_EQ(s.mesh.to_json(), load_experiment(dir / "base.json").scenarios.at(0).mesh.to_json());
}

TEST_F(ScenarioFiles, ExtendsIsRecursiveAndBasePathsAreRelativeToTheFileThatStatesThem) {
  fs::create_directories(dir / "family");
  auto base = small_cube();
  base["mesh"] = {{"type", "files"}, {"surface", "surface.obj"}};  // a path, relative to family/
  write("family/base.json", base);
  write("family/middle.json", {{"extends", "base.json"}, {"name", "middle"}, {"material", {{"density", 800}}}});
  const std::string top = write("top.json", {{"extends", "family/middle.json"}, {"name", "top"}});
  const Scenario s = load_experiment(top).scenarios.at(0);
  EXPECT_EQ(s.name, "top");
  EXPECT_EQ(s.material.density, 800);
  EXPECT_EQ(s.mesh.surface_file, (dir / "family" / "surface.obj").string());
}

TEST_F(ScenarioFiles, ExtendsErrorsNameTheFiles) {
  write("a.json", {{"extends", "b.json"}, {"name", "a"}});
  write("b.json", {{"extends", "a.json"}, {"name", "b"}});
  expect_load_error((dir / "a.json").string(), {"a.json.extends: a cycle: a.json -> b.json -> a.json"});
  write("self.json", {{"extends", "self.json"}});
  expect_load_error((dir / "self.json").string(), {"a cycle: self.json -> self.json"});

  write("orphan.json", {{"extends", "nowhere.json"}, {"name", "orphan"}});
  expect_load_error((dir / "orphan.json").string(), {"orphan.json.extends: 'nowhere.json': no such file"});
  write("number.json", {{"extends", 3}});
  expect_load_error((dir / "number.json").string(), {"number.json.extends: must be the path of a scenario file"});

  // An unknown key is an error as in a single file, naming the file that set it.
  write("base.json", small_cube());
  write("typo.json", {{"extends", "base.json"}, {"name", "typo"}, {"material", {{"densty", 900}}}});
  expect_load_error((dir / "typo.json").string(), {"typo.json.material: unknown key 'densty' (expected"});
  auto bad_base = small_cube();
  bad_base["observe"] = {{"vertex", "all"}};
  write("bad_base.json", bad_base);
  write("child.json", {{"extends", "bad_base.json"}, {"name", "child"}});
  expect_load_error((dir / "child.json").string(),
                    {"child.json.observe: unknown key 'vertex' (set in bad_base.json) (expected one of"});
  // An out-of-range value set by the base names the base too.
  auto soft = small_cube();
  soft["material"] = {{"poisson_ratio", 0.5}};
  write("soft.json", soft);
  write("soft_child.json", {{"extends", "soft.json"}, {"name", "soft-child"}});
  expect_load_error((dir / "soft_child.json").string(),
                    {"soft_child.json.material.poisson_ratio (set in soft.json): 0.5 is out of range"});
}

TEST_F(ScenarioFiles, ExperimentModelsComeFirstThenTheScenariosThenItsAdditions) {
  auto a = small_cube();
  a["models"] = {{{"model", "pbd"}}};
  write("a.json", a);
  auto b = small_cube();
  b["name"] = "b";
  b.erase("models");  // its cases all come from the experiment
  write("b.json", b);
  const nlohmann::json experiment = nlohmann::json::parse(R"({
    "name": "study", "reference": "fem-direct",
    "models": [{"name": "fem-direct", "model": "fem"}, {"name": "hybrid-5", "model": "hybrid",
                                                       "parameters": {"iterations": 5}}],
    "scenarios": [{"file": "a.json", "role": "cube_pull", "models_add": [{"name": "embedded", "model": "embedded"}]},
                  "b.json"]
  })");
  const Experiment e = load_experiment(write("study.json", experiment));
  ASSERT_EQ(e.scenarios.size(), 2u);
  EXPECT_EQ(cases(e.scenarios[0]), (std::vector<std::string>{"fem-direct", "hybrid-5", "pbd", "embedded"}));
  EXPECT_EQ(cases(e.scenarios[1]), (std::vector<std::string>{"fem-direct", "hybrid-5"}));
  EXPECT_EQ(e.scenarios[0].models[1].parameters.number("iterations"), 5);
  EXPECT_EQ(e.scenarios[0].role, "cube_pull");
  EXPECT_EQ(e.scenarios[1].role, "");
  // experiment.json records the role and the cases in the order they run.
  const nlohmann::json index = e.to_json();
  EXPECT_EQ(index["scenarios"][0]["role"], "cube_pull");
  EXPECT_FALSE(index["scenarios"][1].contains("role"));
  EXPECT_EQ(index["scenarios"][0]["cases"], nlohmann::json({"fem-direct", "hybrid-5", "pbd", "embedded"}));

  // A case name given twice is an error naming both places.
  auto twice = experiment;
  twice["scenarios"][0]["models_add"] = {{{"model", "pbd"}}};
  write("twice.json", twice);
  expect_load_error((dir / "twice.json").string(),
                    {"twice.json.scenarios[0]: case 'pbd' is given twice: by a.json models and by "
                     "twice.json.scenarios[0].models_add"});
  twice = experiment;
  twice["models"].push_back({{"model", "pbd"}});
  write("twice.json", twice);
  expect_load_error((dir / "twice.json").string(), {"case 'pbd' is given twice: by twice.json models and by a.json"});
  // A bad value in an experiment-level case names the experiment file.
  auto bad = experiment;
  bad["models"][1]["parameters"]["iterations"] = -1;
  write("bad_models.json", bad);
  expect_load_error((dir / "bad_models.json").string(),
                    {"a.json.models[1].parameters.iterations", "(set in bad_models.json)"});
}

TEST_F(ScenarioFiles, RolesAndEntriesAreStrict) {
  write("a.json", small_cube());
  auto b = small_cube();
  b["name"] = "b";
  write("b.json", b);
  auto experiment = [](const nlohmann::json& entries) {
    return nlohmann::json{{"name", "study"}, {"scenarios", entries}};
  };
  write("bad.json", experiment({{{"file", "a.json"}, {"role", "pull"}}, {{"file", "b.json"}, {"role", "pull"}}}));
  expect_load_error((dir / "bad.json").string(), {"bad.json.scenarios[1].role: 'pull' is given to two scenarios"});
  write("bad.json", experiment({{{"file", "a.json"}, {"role", "Cube-Pull"}}}));
  expect_load_error((dir / "bad.json").string(), {"scenarios[0].role: 'Cube-Pull' must be lower case letters"});
  write("bad.json", experiment({{{"file", "a.json"}, {"roles", "pull"}}}));
  expect_load_error((dir / "bad.json").string(), {"bad.json.scenarios[0]: unknown key 'roles'"});
  write("bad.json", experiment({{{"role", "pull"}}}));
  expect_load_error((dir / "bad.json").string(), {"bad.json.scenarios[0].file: missing (required)"});
  write("bad.json", experiment({3}));
  expect_load_error((dir / "bad.json").string(), {"bad.json.scenarios: entries must be file paths or"});
  write("bad.json", {{"name", "study"}, {"models", nlohmann::json::array()}, {"scenarios", {"a.json"}}});
  expect_load_error((dir / "bad.json").string(), {"bad.json.models: must be a non-empty array"});
  // A sweep's points take the role of their base scenario.
  const Experiment e = load_experiment(write(
      "sweep.json", {{"name", "study"},
                     {"scenarios", {{{"file", "a.json"}, {"role", "pull"}}}},
                     {"sweep", {{"factors", {{{"key", "models.*.parameters.iterations"}, {"values", {5, 20}}}}}}}}));
  ASSERT_EQ(e.scenarios.size(), 3u);
  for (const auto& s : e.scenarios) EXPECT_EQ(s.role, "pull") << s.name;
}

TEST_F(ScenarioFiles, IndexOnlyWritesExperimentJsonAndNothingElse) {
  write("a.json", small_cube());
  const std::string file =
      write("study.json", {{"name", "study"}, {"scenarios", {{{"file", "a.json"}, {"role", "cube_pull"}}}}});
  std::string out;
  ASSERT_EQ(testing::run_tissuebench("run " + file + " --index-only --quiet --out " + (dir / "out").string(), out), 0)
      << out;
  std::vector<std::string> written;
  for (const auto& entry : fs::recursive_directory_iterator(dir / "out"))
    written.push_back(fs::relative(entry.path(), dir / "out").string());
  EXPECT_EQ(written, (std::vector<std::string>{"study", "study/experiment.json"}));
  const auto index = nlohmann::json::parse(read_file((dir / "out/study/experiment.json").string()));
  EXPECT_EQ(index["scenarios"][0]["role"], "cube_pull");
}

// ---- the data directory ----

/// A scenario whose surface is a data reference, with a surface file in `data`/meshes/.
class DataFiles : public ScenarioFiles {
 protected:
  std::string scenario_with_data_surface(bool create_file) {
    fs::create_directories(dir / "data" / "meshes");
    if (create_file) std::ofstream(dir / "data/meshes/tet.obj") << "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\n";
    auto j = small_cube();
    j["mesh"] = {{"type", "files"}, {"surface", "data:meshes/tet.obj"}};
    return write("s.json", j);
  }
};

TEST_F(DataFiles, AMissingDataFileIsOneLineNamingTheFileAndTheDataDirectoryAndNothingIsWritten) {
  const std::string file = scenario_with_data_surface(false);
  const std::string data = (dir / "data").string(), out_dir = (dir / "out").string();
  std::string out;
  EXPECT_NE(testing::run_tissuebench("run " + file + " --data-dir " + data + " --out " + out_dir, out), 0);
  EXPECT_EQ(std::count(out.begin(), out.end(), '\n'), 1) << out;
  for (const std::string& part : {"s.json.mesh.surface: meshes/tet.obj: not found in data directory " + data,
                                  std::string("(--data-dir;"), std::string("README 'Data'")})
    EXPECT_NE(out.find(part), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(out_dir)) << "a run that cannot read its data writes nothing";

  // The loader says the same, naming how the directory was chosen.
  try {
    load_experiment(file, data_dir(data));
    FAIL();
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("not found in data directory " + data), std::string::npos) << e.what();
  }
  // A reference leaving the directory is malformed.
  auto j = small_cube();
  j["mesh"] = {{"type", "files"}, {"surface", "data:../tet.obj"}};
  write("up.json", j);
  expect_load_error((dir / "up.json").string(), {"up.json.mesh.surface: 'data:../tet.obj' must be data:<relative"});
}

TEST_F(DataFiles, TheFlagWinsOverTheEnvironmentWhichWinsOverTheDefault) {
  const std::string file = scenario_with_data_surface(true);
  const std::string data = (dir / "data").string(), elsewhere = (dir / "elsewhere").string();
  std::string out;
  // TISSUEBENCH_DATA alone: read from there; resolve records the reference as written.
  ASSERT_EQ(testing::run_tissuebench("resolve " + file, out, "TISSUEBENCH_DATA=" + data), 0) << out;
  const auto resolved = nlohmann::json::parse(out);
  EXPECT_EQ(resolved["scenarios_resolved"][0]["mesh"]["surface"], "data:meshes/tet.obj");
  // TISSUEBENCH_DATA elsewhere: not found there, and the message says which variable chose it.
  EXPECT_NE(testing::run_tissuebench("resolve " + file, out, "TISSUEBENCH_DATA=" + elsewhere), 0);
  EXPECT_NE(out.find("not found in data directory " + elsewhere + " (TISSUEBENCH_DATA;"), std::string::npos) << out;
  // --data-dir wins over TISSUEBENCH_DATA, both ways.
  EXPECT_EQ(testing::run_tissuebench("resolve " + file + " --data-dir " + data, out, "TISSUEBENCH_DATA=" + elsewhere),
            0)
      << out;
  EXPECT_NE(testing::run_tissuebench("resolve " + file + " --data-dir " + elsewhere, out, "TISSUEBENCH_DATA=" + data),
            0);
  EXPECT_NE(out.find("not found in data directory " + elsewhere + " (--data-dir;"), std::string::npos) << out;
  // In the library: the flag, then the variable.
  ::setenv("TISSUEBENCH_DATA", elsewhere.c_str(), 1);
  EXPECT_EQ(data_dir().path, elsewhere);
  EXPECT_EQ(data_dir().chosen_by, "TISSUEBENCH_DATA");
  EXPECT_EQ(data_dir(data).path, data);
  EXPECT_EQ(load_experiment(file, data_dir(data)).scenarios.at(0).mesh.surface_file, data + "/meshes/tet.obj");
  ::unsetenv("TISSUEBENCH_DATA");
}

TEST_F(DataFiles, ACaseOnADataMeshWritesDisplacementsWithoutTheFilesCoordinates) {
  // The small cube's fine surface, written by a run of it, stands for a third-party mesh.
  auto own = small_cube();
  own["models"] = nlohmann::json::array({{{"name", "fem-direct"}, {"model", "fem"}}});
  RunOptions o;
  o.progress = false;
  o.out_dir = (dir / "own").string();
  ASSERT_TRUE(run_experiment(load_experiment(write("own.json", own)), o).at(0).ok);
  const fs::path own_case = dir / "own/small/small/fem-direct";
  fs::create_directories(dir / "data/meshes");
  fs::copy_file(dir / "own/small/small/mesh/fine_surface.obj", dir / "data/meshes/box.obj");

  auto j = own;
  j["name"] = "from-data";
  j["mesh"] = {{"type", "files"},
               {"surface", "data:meshes/box.obj"},
               {"fine_tetgen", {{"max_volume", 2e-6}}},
               {"coarse_selection", {{"target_nodes", 30}}}};
  o.out_dir = (dir / "data-run").string();
  const std::string file = write("from-data.json", j);
  ASSERT_TRUE(run_experiment(load_experiment(file, data_dir((dir / "data").string())), o).at(0).ok);
  const fs::path data_case = dir / "data-run/from-data/from-data/fem-direct";

  auto header = [](const fs::path& csv) {
    return read_file(csv.string()).substr(0, read_file(csv.string()).find('\n'));
  };
  for (const char* f : {"top_surface.csv", "surface.csv"}) {
    EXPECT_EQ(header(own_case / f), "vertex,x,y,z,ux,uy,uz") << f;  // the project's own geometry
    EXPECT_EQ(header(data_case / f), "vertex,ux,uy,uz") << f;
  }
  const auto own_run = nlohmann::json::parse(read_file((own_case / "run.json").string()));
  const auto data_run = nlohmann::json::parse(read_file((data_case / "run.json").string()));
  EXPECT_TRUE(own_run["observed_coordinates"].get<bool>());
  EXPECT_FALSE(data_run["observed_coordinates"].get<bool>());
  // The vertex the analysis takes as the load's: the observed (top) vertex nearest
  // the load point, found here from the surface the run wrote into its mesh folder.
  const SurfaceMesh surface = read_surface((dir / "data-run/from-data/from-data/mesh/fine_surface.vtu").string());
  const Eigen::Vector3d load(0, 0, 0.1);
  const double top = surface.V.col(2).maxCoeff();
  int nearest = -1;
  for (Eigen::Index v = 0; v < surface.V.rows(); ++v)
    if (std::abs(surface.V(v, 2) - top) <= 1e-9 &&
        (nearest < 0 ||
         (surface.V.row(v).transpose() - load).norm() < (surface.V.row(nearest).transpose() - load).norm()))
      nearest = static_cast<int>(v);
  EXPECT_EQ(data_run["observed_vertex_nearest_load"].get<int>(), nearest);
  EXPECT_NEAR(surface.V(nearest, 0), 0.0, 0.02);  // the top centre, about
}

TEST(DataDirectory, TheLiverScenarioReadsTheSharedMeshesFromTheDefaultDataDirectory) {
  ::unsetenv("TISSUEBENCH_DATA");
  const DataDir d = data_dir();
  EXPECT_EQ(d.path, (fs::path(TB_SOURCE_DIR) / ".." / "shared").lexically_normal().string());
  EXPECT_EQ(d.chosen_by, "the default, ../shared beside the repository");
  const Scenario s =
      load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/liver-pull.json").scenarios.at(0);
  EXPECT_EQ(s.mesh.surface_file, d.path + "/meshes/liver-smooth.obj");
  EXPECT_EQ(s.mesh.coarse_file, d.path + "/meshes/liver.msh");
  EXPECT_EQ(s.mesh.to_json()["surface"], "data:meshes/liver-smooth.obj");  // run.json: the reference, not the path
  EXPECT_TRUE(fs::is_regular_file(s.mesh.surface_file));
  // The same from another working directory.
  const fs::path here = fs::current_path();
  fs::current_path(fs::temp_directory_path());
  EXPECT_EQ(load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/liver-push.json")
                .scenarios.at(0)
                .mesh.surface_file,
            s.mesh.surface_file);
  fs::current_path(here);
}

// ---- the committed files ----

TEST(CommittedScenarioFiles, EveryExperimentLoadsAndEveryScenarioFileBelongsToOne) {
  const fs::path root = fs::path(TB_SOURCE_DIR) / "experiments";
  std::set<std::string> listed, scenario_files;
  int experiments = 0;
  for (const auto& entry : fs::recursive_directory_iterator(root)) {
    const fs::path& p = entry.path();
    if (p.extension() != ".json") continue;
    const std::string name = p.filename().string();
    if (p.parent_path().filename() == "scenarios" || p.parent_path().parent_path().filename() == "scenarios") {
      // Partial files meant only to be extended are named *.base.json.
      if (name.size() < 10 || name.substr(name.size() - 10) != ".base.json") scenario_files.insert(p.string());
      continue;
    }
    const auto j = nlohmann::json::parse(read_file(p.string()));
    if (!j.contains("scenarios")) continue;  // accuracy_gates.json
    ++experiments;
    Experiment e;
    ASSERT_NO_THROW(e = load_experiment(p.string())) << p;
    for (const Scenario& s : e.scenarios) listed.insert(fs::path(s.file).lexically_normal().string());
  }
  EXPECT_GE(experiments, 10);
  for (const std::string& f : scenario_files) EXPECT_TRUE(listed.count(f)) << f << " is in no experiment file";
}

TEST(CommittedScenarioFiles, TheSchemaDocumentListsEveryKeyTheLoaderReads) {
  // docs/scenario_schema.md: a "### `object`" heading per object of file_schema(),
  // then a table whose rows start "| `key` |".
  std::map<std::string, std::vector<std::string>> documented;
  std::istringstream doc(read_file(std::string(TB_SOURCE_DIR) + "/docs/scenario_schema.md"));
  std::string line, object;
  while (std::getline(doc, line)) {
    if (line.rfind("### `", 0) == 0) {
      object = line.substr(5, line.find('`', 5) - 5);
      documented[object];
    } else if (line.rfind("| `", 0) == 0 && !object.empty()) {
      documented[object].push_back(line.substr(3, line.find('`', 3) - 3));
    }
  }
  for (const auto& [name, keys] : file_schema()) {
    ASSERT_TRUE(documented.count(name)) << "docs/scenario_schema.md has no section ### `" << name << "`";
    std::set<std::string> doc_keys(documented[name].begin(), documented[name].end());
    for (const auto& k : keys) EXPECT_TRUE(doc_keys.count(k)) << name << "." << k << " is not documented";
    for (const auto& k : doc_keys)
      EXPECT_NE(std::find(keys.begin(), keys.end(), k), keys.end())
          << name << "." << k << " is documented but the loader does not read it (file_schema.cc)";
  }
  for (const auto& [name, keys] : documented)
    EXPECT_TRUE(file_schema().count(name))
        << "docs/scenario_schema.md documents ### `" << name << "`, which file_schema.cc does not declare";
}

}  // namespace
}  // namespace tb
