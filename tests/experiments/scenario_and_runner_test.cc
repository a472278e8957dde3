// Scenario validation, divergence reporting, atomic outputs and determinism.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <csignal>
#include <filesystem>
#include <fstream>

#include "atomic_file.h"
#include "runner.h"
#include "scenario_fixture.h"
#include "strict_json.h"
#include "test_support.h"

namespace tb {
namespace {
namespace fs = std::filesystem;

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
  // The machine's load beside the times (the analysis flags a busy machine's cases).
  const auto timings =
      nlohmann::json::parse(read_file((dir / "a" / "small" / "small" / "pbd" / "timings.json").string()));
  for (const char* when : {"at_setup", "at_last_frame"}) {
    ASSERT_TRUE(timings["load_average_1min"][when].is_number()) << when;
    EXPECT_GE(timings["load_average_1min"][when].get<double>(), 0.0) << when;
  }
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

TEST_F(Scenarios, KilledRunLeavesThePreviousResultAndItsLeftoversAreCleaned) {
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.only_case = "pbd";
  ASSERT_TRUE(run_experiment(load_experiment(write("s.json", small_cube())), o).at(0).ok);
  const fs::path result = dir / "out" / "small" / "small" / "pbd";
  const std::string before = read_file((result / "top_surface.csv").string());

  // A run that never reaches the steady state, killed (SIGKILL) mid-way.
  auto j = small_cube();
  j["frames"] = {{"max", 100000000}, {"steady_tolerance", 0}};
  const std::string scenario = write("long.json", j);
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    execl(TB_CLI, TB_CLI, "run", scenario.c_str(), "--model", "pbd", "--out", o.out_dir.c_str(), "--quiet",
          "--no-mesh-cache", static_cast<char*>(nullptr));
    _exit(127);
  }
  usleep(1500 * 1000);  // meshing takes about 0.2 s; then it steps
  kill(child, SIGKILL);
  int status = 0;
  waitpid(child, &status, 0);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the run ended before it was killed";
  EXPECT_EQ(read_file((result / "top_surface.csv").string()), before);

  // The next run replaces the result and removes what the killed run left.
  ASSERT_TRUE(run_experiment(load_experiment(write("s.json", small_cube())), o).at(0).ok);
  for (const auto& entry : fs::directory_iterator(result.parent_path()))
    EXPECT_EQ(entry.path().filename().string().find(".tmp"), std::string::npos) << "left behind: " << entry.path();
}

TEST_F(Scenarios, MeshCacheReturnsTheBuiltMeshExactly) {
  const Experiment e = load_experiment(write("s.json", small_cube()));
  const std::string cache = (dir / "cache").string();
  MeshReport r1, r2;
  bool hit1 = true, hit2 = false;
  const HybridMesh built = build_mesh_cached(e.scenarios[0].mesh, r1, cache, hit1);
  const HybridMesh read = build_mesh_cached(e.scenarios[0].mesh, r2, cache, hit2);
  EXPECT_FALSE(hit1);
  EXPECT_TRUE(hit2);
  EXPECT_EQ(built.fine_surface.V, read.fine_surface.V);
  EXPECT_EQ(built.fine_surface.F, read.fine_surface.F);
  EXPECT_EQ(built.fine_volume.V, read.fine_volume.V);
  EXPECT_EQ(built.fine_volume.T, read.fine_volume.T);
  EXPECT_EQ(built.coarse_volume.T, read.coarse_volume.T);
  ASSERT_EQ(built.control_points.size(), read.control_points.size());
  for (size_t k = 0; k < built.control_points.size(); ++k) {
    EXPECT_EQ(built.control_points[k].surface_vertex, read.control_points[k].surface_vertex);
    EXPECT_EQ(built.control_points[k].coarse.weights, read.control_points[k].coarse.weights);
  }
  // An unusable cache folder (a file stands there) costs a rebuild, not the run.
  std::ofstream(dir / "not-a-folder") << "x";
  bool hit3 = true;
  MeshReport r3;
  EXPECT_NO_THROW(build_mesh_cached(e.scenarios[0].mesh, r3, (dir / "not-a-folder").string(), hit3));
  EXPECT_FALSE(hit3);
  // A different recipe is a different entry.
  MeshRecipe other = e.scenarios[0].mesh;
  other.build.target_coarse_nodes += 1;
  EXPECT_NE(mesh_content_hash(other), mesh_content_hash(e.scenarios[0].mesh));
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
