// The liver's steady state: with the setting the committed liver
// scenarios state (experiments/scenarios/liver-*.json: sub-steps, the signed bending
// angle, and for the hybrid the supported surface following the coarse FEM), pbd and
// the hybrid meet the runner's steady-state test on both scenarios within the frame
// budget, no surface triangle turned over; with the same setting but one sub-step
// (the paper's step) pbd does not settle and the hybrid's push settles folded.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <fstream>
#include <sstream>

#include "mesh_io.h"
#include "runner.h"
#include "scenario.h"
#include "test_support.h"

namespace tb {
namespace {

/// The committed scenario, its models reduced to `cases` (no fine volume: no FEM runs).
Experiment liver(const std::string& scenario, const std::vector<std::string>& cases) {
  Experiment e = load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/" + scenario + ".json");
  Scenario& s = e.scenarios.at(0);
  s.mesh.build_fine_volume = false;
  std::vector<ModelRun> kept;
  for (const std::string& c : cases)
    for (const ModelRun& m : s.models)
      if (m.case_name == c) kept.push_back(m);
  EXPECT_EQ(kept.size(), cases.size()) << scenario;
  s.models = kept;
  return e;
}

nlohmann::json run_json(const std::string& out, const Experiment& e, const std::string& c) {
  std::ifstream f(out + "/" + e.name + "/" + e.scenarios[0].name + "/" + c + "/run.json");
  std::stringstream ss;
  ss << f.rdbuf();
  return nlohmann::json::parse(ss.str());
}

/// Surface triangles of a case's final surface whose normal turned more than 90
/// degrees from its rest normal (the scenario's meshes written beside the cases).
int turned_triangles(const std::string& out, const Experiment& e, const std::string& c) {
  const std::string scenario_dir = out + "/" + e.name + "/" + e.scenarios[0].name;
  const SurfaceMesh rest = read_surface(scenario_dir + "/mesh/fine_surface.obj");
  Eigen::MatrixXd moved = rest.V;
  std::ifstream csv(scenario_dir + "/" + c + "/surface.csv");
  std::string line;
  std::getline(csv, line);
  // The liver's mesh is a data: file: the runner writes no coordinates (experiments/runner.cc).
  EXPECT_EQ(line, "vertex,ux,uy,uz") << c;
  for (Eigen::Index i = 0; i < moved.rows(); ++i) {
    EXPECT_TRUE(std::getline(csv, line)) << c << ": surface.csv ends at vertex " << i;
    std::replace(line.begin(), line.end(), ',', ' ');
    std::istringstream row(line);
    double vertex, u[3];
    row >> vertex >> u[0] >> u[1] >> u[2];
    EXPECT_EQ(vertex, static_cast<double>(i)) << c;
    for (int d = 0; d < 3; ++d) moved(i, d) += u[d];
  }
  auto normal = [](const Eigen::MatrixXd& V, const Eigen::RowVector3i& f) {
    const Eigen::Vector3d a = V.row(f(0)), b = V.row(f(1)), c = V.row(f(2));
    return Eigen::Vector3d((b - a).cross(c - a));
  };
  int turned = 0;
  for (Eigen::Index t = 0; t < rest.F.rows(); ++t)
    turned += normal(rest.V, rest.F.row(t)).dot(normal(moved, rest.F.row(t))) < 0;
  return turned;
}

TEST(LiverSteadyState, PbdAndHybridSettleOnBothLiverScenarios) {
  const testing::TempFolder tmp("liver-steady");
  for (const std::string scenario : {"liver-pull", "liver-push"}) {
    const Experiment e = liver(scenario, {"pbd", "hybrid"});
    RunOptions o;
    o.out_dir = tmp.path.string();
    o.progress = false;
    for (const CaseOutcome& c : run_experiment(e, o)) {
      ASSERT_TRUE(c.ok) << scenario << "/" << c.case_name << ": " << c.error;
      EXPECT_EQ(turned_triangles(o.out_dir, e, c.case_name), 0) << scenario << "/" << c.case_name;
      EXPECT_GE(c.steady_frame, 0) << scenario << "/" << c.case_name << " ran " << c.frames << " frames";
      const nlohmann::json run = run_json(o.out_dir, e, c.case_name);
      EXPECT_TRUE(run["reached_steady_state"].get<bool>()) << scenario << "/" << c.case_name;
      EXPECT_GT(run["parameters"]["substeps"].get<double>(), 1) << scenario << "/" << c.case_name;
      EXPECT_LT(run["last_frame_change_m"].get<double>(),
                run["scenario_resolved"]["frames"]["steady_tolerance"].get<double>() *
                    run["max_displacement_m"].get<double>());
    }
  }
}

TEST(LiverSteadyState, WithOneSubstepPbdDoesNotSettleAndTheHybridPushSettlesFolded) {
  // The contrast, one case per scenario (about 7 s each: 5000 frames of the paper's
  // step). Before the bending step's trust region (constraints.h) the hybrid's push
  // did not settle at one sub-step either; now it settles, with triangles turned over.
  const testing::TempFolder tmp("liver-one-substep");
  for (const auto& [scenario, case_name] : {std::pair<std::string, std::string>{"liver-pull", "pbd"},
                                            std::pair<std::string, std::string>{"liver-push", "pbd"},
                                            std::pair<std::string, std::string>{"liver-push", "hybrid"}}) {
    Experiment e = liver(scenario, {case_name});
    e.scenarios[0].models[0].parameters.set_number("substeps", 1);
    RunOptions o;
    o.out_dir = tmp.path.string();
    o.progress = false;
    const std::vector<CaseOutcome> out = run_experiment(e, o);
    ASSERT_EQ(out.size(), 1u);
    ASSERT_TRUE(out[0].ok) << out[0].error;
    const bool settled = run_json(o.out_dir, e, case_name)["reached_steady_state"].get<bool>();
    if (case_name == "pbd") {
      EXPECT_EQ(out[0].steady_frame, -1) << scenario << "/" << case_name << " settled with one sub-step";
      EXPECT_EQ(out[0].frames, e.scenarios[0].max_frames);
      EXPECT_FALSE(settled);
    } else {
      EXPECT_GT(turned_triangles(o.out_dir, e, case_name), 0) << scenario << "/" << case_name;
    }
  }
}

}  // namespace
}  // namespace tb
