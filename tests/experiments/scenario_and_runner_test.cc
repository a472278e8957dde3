// Scenario validation, divergence reporting, atomic outputs and determinism (issue 6).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "atomic_file.h"
#include "runner.h"
#include "strict_json.h"
#include "test_support.h"

namespace tb {
namespace {
namespace fs = std::filesystem;

class Scenarios : public ::testing::Test {
 protected:
  const tb::testing::TempFolder tmp{"scenarios"};
  const fs::path dir = tmp.path;

  /// A small valid cube scenario (coarse divisions so it runs in a second).
  static nlohmann::json small_cube() {
    return nlohmann::json::parse(R"({
      "name": "small",
      "mesh": {"type": "cube", "nx": 4, "ny": 4, "nz": 4, "fine_tetgen": {"max_volume": 2e-6},
               "coarse_selection": {"target_nodes": 30}},
      "support": {"min": [-1, -1, -1e-9], "max": [1, 1, 1e-9]},
      "load": {"point": [0, 0, 0.1], "force": [0, 0, 0.1], "ramp_frames": 5},
      "frames": {"max": 300, "static": 5, "steady_tolerance": 1e-4},
      "models": [{"name": "fem-direct", "model": "fem"}, {"model": "pbd"}, {"model": "hybrid"}]
    })");
  }
  std::string write(const std::string& name, const nlohmann::json& j) {
    const std::string p = (dir / name).string();
    std::ofstream(p) << j.dump(2);
    return p;
  }
  void expect_error(const nlohmann::json& j, const std::string& message) {
    const std::string p = write("bad.json", j);
    try {
      load_experiment(p);
      FAIL() << "accepted: " << message;
    } catch (const ScenarioError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.json"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
    }
  }
};

TEST_F(Scenarios, ValidationErrorsNameFileKeyAndProblem) {
  auto j = small_cube();
  j["materail"] = nlohmann::json::object();
  expect_error(j, "unknown key 'materail'");
  j = small_cube();
  j["material"] = {{"poisson_ratio", 0.5}};
  expect_error(j, "material.poisson_ratio: 0.5 is out of range");
  j = small_cube();
  j["material"] = {{"youngs_modulus", -3}};
  expect_error(j, "material.youngs_modulus");
  j = small_cube();
  j["load"]["force"] = "up";
  expect_error(j, "load.force: must be an array of 3 numbers");
  j = small_cube();
  j["models"][1]["model"] = "fancy";
  expect_error(j, "models[1].model: unknown model 'fancy'");
  j = small_cube();
  j["models"][1]["parameters"] = {{"iterations", -1}};
  expect_error(j, "models[1].parameters.iterations");
  j = small_cube();
  j["mesh"]["type"] = "sphere";
  expect_error(j, "mesh.type: 'sphere' is not one of cube, files");
  j = small_cube();
  j.erase("support");
  expect_error(j, "support: missing");
  std::ofstream(dir / "bad.json") << "{\"name\": ";
  EXPECT_THROW(load_experiment((dir / "bad.json").string()), ScenarioError);
  EXPECT_THROW(load_experiment((dir / "absent.json").string()), ScenarioError);
}

TEST_F(Scenarios, MissingMeshFileFailsTheCaseWithItsName) {
  auto j = small_cube();
  j["mesh"] = {{"type", "files"}, {"surface", "nowhere.obj"}};
  const Experiment e = load_experiment(write("s.json", j));
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  const auto out = run_experiment(e, o);
  ASSERT_EQ(out.size(), 3u);
  for (const auto& c : out) {
    EXPECT_FALSE(c.ok);
    EXPECT_NE(c.error.find("nowhere.obj: cannot open file"), std::string::npos) << c.error;
  }
  EXPECT_FALSE(fs::exists(dir / "out" / "small" / "small" / "pbd"));
}

TEST_F(Scenarios, RunWritesResultsDeterministically) {
  const Experiment e = load_experiment(write("s.json", small_cube()));
  RunOptions o;
  o.progress = false;
  std::string first;
  for (const char* run : {"a", "b"}) {
    o.out_dir = (dir / run).string();
    for (const auto& c : run_experiment(e, o)) EXPECT_TRUE(c.ok) << c.case_name << ": " << c.error;
  }
  for (const char* c : {"fem-direct", "pbd", "hybrid"})
    for (const char* f : {"top_surface.csv", "surface.csv", "surface.vtu"})
      EXPECT_EQ(read_file((dir / "a" / "small" / "small" / c / f).string()),
                read_file((dir / "b" / "small" / "small" / c / f).string()))
          << c << "/" << f;
  const auto run = nlohmann::json::parse(read_file((dir / "a" / "small" / "small" / "pbd" / "run.json").string()));
  EXPECT_TRUE(run["reached_steady_state"].get<bool>());
  EXPECT_EQ(run["parameters"]["iterations"], 10);
}

TEST_F(Scenarios, DivergenceIsReportedAndLeavesThePreviousResult) {
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.only_case = "pbd";
  const Experiment good = load_experiment(write("s.json", small_cube()));
  ASSERT_TRUE(run_experiment(good, o).at(0).ok);
  const fs::path csv = dir / "out" / "small" / "small" / "pbd" / "top_surface.csv";
  const std::string before = read_file(csv.string());

  auto j = small_cube();
  j["models"][1]["parameters"] = {{"time_step", 1.0}};  // a huge step
  j["load"]["force"] = {0, 0, 100};
  const auto out = run_experiment(load_experiment(write("s.json", j)), o);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_FALSE(out[0].ok);
  EXPECT_NE(out[0].error.find("diverged at frame"), std::string::npos) << out[0].error;
  EXPECT_EQ(read_file(csv.string()), before);  // the old result is intact
  for (const auto& entry : fs::directory_iterator(dir / "out" / "small" / "small"))
    EXPECT_EQ(entry.path().string().find(".tmp"), std::string::npos) << "left behind: " << entry.path();
}

TEST(Timing, MedianAndP95) {
  std::vector<double> s;
  for (int i = 1; i <= 100; ++i) s.push_back(i);
  const TimingStats t = timing_stats(s);
  EXPECT_DOUBLE_EQ(t.median, 50.5);
  EXPECT_NEAR(t.p95, 95.05, 1e-12);
  EXPECT_EQ(t.count, 100);
}

}  // namespace
}  // namespace tb
