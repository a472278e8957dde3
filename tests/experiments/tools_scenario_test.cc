// Scenario files with tools, more loads and interior probes (docs/scenario_schema.md
// "loads", "tools", "probes"): what the runner writes (reactions.csv per frame,
// probes.csv, run.json's observables), the schedules of values over the frames,
// and each bad input as one error naming the file and the key, before any case runs.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "runner.h"
#include "scenario_fixture.h"

namespace tb {
namespace {

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class ToolScenarios : public Scenarios {
 protected:
  /// The small cube lifted by a grasp at its top centre, pushed by a bonded plate on
  /// a side, under gravity, with two probes.
  static nlohmann::json grasped_cube();
};

nlohmann::json ToolScenarios::grasped_cube() {
  nlohmann::json j = small_cube();
  j.erase("load");
  j["loads"] = {{{"type", "gravity"}, {"g", {0, 0, -9.81}}}};
  j["tools"] = {{{"type", "grasp"}, {"point", {0, 0, 0.1}}, {"radius", 0.02}, {"path", {{0, 0, 0, 0}, {4, 0, 0, 0.004}}}},
                {{"type", "plate"}, {"box", {{"min", {-1, 0.0499, 0.04}}, {"max", {1, 1, 0.06}}}},
                 {"displacement", {0, -0.001, 0}}, {"ramp_frames", 3}}};
  j["probes"] = {{"points", {{0, 0, 0.05}, {0.01, -0.01, 0.08}}}};
  j["models"] = {{{"name", "fem-direct"}, {"model", "fem"}}, {{"model", "embedded"}}, {{"model", "pbd"}}};
  return j;
}

TEST_F(ToolScenarios, ToolsLoadsAndProbesReachTheResults) {
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.mesh_cache_dir = "";
  const auto outcomes = run_experiment(load_experiment(write("grasped.json", grasped_cube())), o);
  for (const CaseOutcome& c : outcomes) EXPECT_TRUE(c.ok) << c.case_name << ": " << c.error;
  const auto folder = dir / "out" / "small" / "small";  // a scenario run alone: an experiment named after it
  // The static FEM: a reactions row per frame for each tool and the support; the
  // changing frames (the path to frame 4) run before the static samples.
  const std::string reactions = read(folder / "fem-direct" / "reactions.csv");
  EXPECT_EQ(reactions.rfind("frame,constraint,kind,fx,fy,fz\n", 0), 0u);
  EXPECT_NE(reactions.find("\n4,tools[0],grasp,"), std::string::npos);
  EXPECT_NE(reactions.find("\n4,tools[1],bonded_plate,"), std::string::npos);
  EXPECT_NE(reactions.find("\n4,support,support,"), std::string::npos);
  const std::string probes = read(folder / "fem-direct" / "probes.csv");
  EXPECT_EQ(std::count(probes.begin(), probes.end(), '\n'), 3) << probes;
  const nlohmann::json run = nlohmann::json::parse(read(folder / "fem-direct" / "run.json"));
  EXPECT_EQ(run["observables"]["reactions"]["file"], "reactions.csv");
  EXPECT_EQ(run["scenario_resolved"]["tools"][0]["schedule"]["path"][1][3], 0.004);
  // The surface-only model: no probes, said in run.json, no invented file.
  const nlohmann::json pbd = nlohmann::json::parse(read(folder / "pbd" / "run.json"));
  EXPECT_TRUE(pbd["observables"]["probes"]["file"].is_null());
  EXPECT_NE(pbd["observables"]["probes"]["why_not"].get<std::string>().find("no volume"), std::string::npos);
  EXPECT_FALSE(std::filesystem::exists(folder / "pbd" / "probes.csv"));
  // PBD measures the force on its pins (docs/equations.md, "Reactions in PBD").
  const std::string pbd_reactions = read(folder / "pbd" / "reactions.csv");
  EXPECT_NE(pbd_reactions.find(",tools[0],grasp,"), std::string::npos);
  EXPECT_NE(pbd_reactions.find(",support,support,"), std::string::npos);
  EXPECT_EQ(pbd_reactions.find("nan"), std::string::npos) << pbd_reactions.substr(0, 300);
  EXPECT_TRUE(std::filesystem::exists(folder / "embedded" / "reactions.csv"));
}

TEST_F(ToolScenarios, SchedulesRampAndFollowTheirPath) {
  const Scenario s = load_experiment(write("grasped.json", grasped_cube())).scenarios.at(0);
  EXPECT_EQ(s.changing_frames(), 5) << "the path ends at frame 4";
  FrameLoads f;
  s.loads_at(2, f);
  ASSERT_EQ(f.values.size(), 1u);
  ASSERT_EQ(f.tool_values.size(), 2u);
  EXPECT_EQ(f.values[0], Eigen::Vector3d(0, 0, -9.81)) << "no ramp: full from the first frame";
  EXPECT_NEAR(f.tool_values[0].z(), 0.002, 1e-15) << "half way along the path";
  EXPECT_NEAR(f.tool_values[1].y(), -0.001, 1e-15) << "ramp of 3: full at frame 2";
  s.loads_at(100, f);
  EXPECT_EQ(f.tool_values[0].z(), 0.004) << "held after the path";
  EXPECT_FALSE(s.load_case().tools.empty());
}

TEST_F(ToolScenarios, BadToolsLoadsAndProbesAreOneLineErrorsNamingFileAndKey) {
  nlohmann::json j = grasped_cube();
  j["tools"][0]["path"] = {{0, 0, 0, 0}, {0, 0, 0, 0.004}};
  expect_error(j, "tools[0].path[1]: frames must increase (0 after 0)");
  j = grasped_cube();
  j["tools"][0]["path"] = {{0, 0, 0, "up"}};
  expect_error(j, "tools[0].path[0]: must hold finite numbers");
  j = grasped_cube();
  j["tools"][0]["displacement"] = {0, 0, 1};
  expect_error(j, "give either displacement (with ramp_frames) or path");
  j = grasped_cube();
  j["tools"][1]["box"]["min"] = {2, 2, 2};
  expect_error(j, "tools[1].box.min: exceeds max");
  j = grasped_cube();
  j["loads"][0]["type"] = "magnetism";
  expect_error(j, "loads[0].type: 'magnetism' is not one of point_force, surface_traction, gravity");
  j = grasped_cube();
  j["material"] = {{"density", 0}};
  expect_error(j, "material.density: 0 is out of range");
  j = grasped_cube();
  j["probes"] = {{"points", {{0, 0, 0.05}}}, {"file", "p.csv"}};
  expect_error(j, "probes.points: give one of points, file or truth_cube");
  j = grasped_cube();
  j["probes"] = {{"file", "missing.csv"}};
  expect_error(j, "missing.csv: cannot open file");

  // Checked on the mesh, before any case runs: a tool that holds nothing or holds
  // the support, probes outside the body (each with its distance).
  const auto failure_of = [&](const nlohmann::json& scenario) {
    RunOptions o;
    o.out_dir = (dir / "out").string();
    o.progress = false;
    o.mesh_cache_dir = "";
    const auto outcomes = run_experiment(load_experiment(write("bad-mesh.json", scenario)), o);
    EXPECT_FALSE(outcomes.empty());
    for (const CaseOutcome& c : outcomes) EXPECT_FALSE(c.ok) << c.case_name;
    return outcomes.empty() ? std::string() : outcomes[0].error;
  };
  j = grasped_cube();
  j["tools"][0]["point"] = {0, 0, 0.3};
  std::string e = failure_of(j);
  EXPECT_EQ(e.rfind("bad-mesh.json: tools[0] (grasp): a radius of 0.02 m around (0, 0, 0.3) catches no surface vertex", 0),
            0u)
      << e;
  j = grasped_cube();
  j["tools"][1]["box"] = {{"min", {-1, -1, -1}}, {"max", {1, 1, 0.01}}};
  e = failure_of(j);
  EXPECT_NE(e.find("bad-mesh.json: tools[1] (bonded_plate): "), std::string::npos) << e;
  EXPECT_NE(e.find("are in the support box"), std::string::npos) << e;
  j = grasped_cube();
  j["tools"][1]["box"] = {{"min", {2, 2, 2}}, {"max", {3, 3, 3}}};
  e = failure_of(j);
  EXPECT_NE(e.find("holds no surface vertex"), std::string::npos) << e;
  j = grasped_cube();
  j["probes"] = {{"points", {{0, 0, 0.05}, {0, 0, 0.13}, {0.2, 0, 0.05}}}};
  e = failure_of(j);
  EXPECT_NE(e.find("bad-mesh.json: probes: 2 point(s) outside the body: probes[1] (0, 0, 0.13) by 0.03"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find("probes[2] (0.2, 0, 0.05) by 0.15"), std::string::npos) << e;
}

/// A compliant grasp (docs/scenario_schema.md, "pad_stiffness") runs end to end in
/// the fem model, its jaw force in reactions.csv and run.json's tool; its bad keys
/// are one line naming the file and the key, and a model without pads refuses it.
TEST_F(ToolScenarios, ACompliantGraspRunsAndItsBadKeysAreOneLineErrors) {
  nlohmann::json j = grasped_cube();
  j["tools"][0] = {{"type", "compliant_grasp"}, {"point", {0, 0, 0.1}}, {"radius", 0.02}, {"pad_stiffness", 3e6},
                   {"displacement", {0, 0, 0.004}}, {"ramp_frames", 2}};
  j["models"] = {{{"name", "fem-direct"}, {"model", "fem"}}};
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.mesh_cache_dir = "";
  const auto outcomes = run_experiment(load_experiment(write("pads.json", j)), o);
  ASSERT_EQ(outcomes.size(), 1u);
  ASSERT_TRUE(outcomes[0].ok) << outcomes[0].error;
  const auto folder = dir / "out" / "small" / "small";
  const std::string csv = read(folder / "fem-direct" / "reactions.csv");
  const size_t row = csv.find("\n2,tools[0],compliant_grasp,");
  ASSERT_NE(row, std::string::npos) << csv.substr(0, 300);
  // The tissue pulls the lifted jaw down (fz, the row's last field).
  std::string line = csv.substr(row + 1, csv.find('\n', row + 1) - row - 1);
  EXPECT_LT(std::stod(line.substr(line.rfind(',') + 1)), 0) << line;
  const nlohmann::json run = nlohmann::json::parse(read(folder / "fem-direct" / "run.json"));
  EXPECT_EQ(run["scenario_resolved"]["tools"][0]["pad_stiffness"], 3e6);
  EXPECT_EQ(run["scenario_resolved"]["tools"][0]["type"], "compliant_grasp");

  j = grasped_cube();
  j["tools"][0] = {{"type", "compliant_grasp"}, {"point", {0, 0, 0.1}}, {"radius", 0.02}, {"displacement", {0, 0, 0.004}}};
  expect_error(j, "tools[0].pad_stiffness");
  j["tools"][0]["pad_stiffness"] = -1;
  expect_error(j, "tools[0].pad_stiffness: -1 is out of range");
  // A model without pads: its case fails with the one line, before it runs.
  j["tools"][0]["pad_stiffness"] = 3e6;
  j["models"] = {{{"model", "pbd"}}};
  const auto refused = run_experiment(load_experiment(write("pads-pbd.json", j)), o);
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_FALSE(refused[0].ok);
  EXPECT_NE(refused[0].error.find("model 'pbd' does not take compliant_grasp tools (tools[0])"), std::string::npos)
      << refused[0].error;
}

}  // namespace
}  // namespace tb

namespace tb {
namespace {

/// The small cube pressed by a sphere from above and released (docs/scenario_schema.md,
/// "sphere"): fem, pbd and hybrid write contact.csv and the sphere's force; the other
/// models refuse it with one line.
class SphereScenarios : public Scenarios {
 protected:
  static nlohmann::json sphere_on_cube();
};

nlohmann::json SphereScenarios::sphere_on_cube() {
  nlohmann::json j = small_cube();
  j.erase("load");
  j["tools"] = {{{"type", "sphere"}, {"radius", 0.03}, {"path", {{0, 0, 0, 0.13}, {2, 0, 0, 0.122}, {4, 0, 0, 0.122}}}}};
  j["models"] = {{{"name", "fem-direct"}, {"model", "fem"}}, {{"model", "pbd"}}, {{"model", "hybrid"}}};
  return j;
}

TEST_F(SphereScenarios, ASphereWritesItsContactAndForcePerFrame) {
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.mesh_cache_dir = "";
  const auto outcomes = run_experiment(load_experiment(write("sphere.json", sphere_on_cube())), o);
  ASSERT_EQ(outcomes.size(), 3u);
  for (const CaseOutcome& c : outcomes) EXPECT_TRUE(c.ok) << c.case_name << ": " << c.error;
  const std::filesystem::path folder = dir / "out" / "small" / "small";  // a scenario run alone
  const std::filesystem::path fem = folder / "fem-direct";
  const std::string contact = read(fem / "contact.csv");
  EXPECT_EQ(contact.rfind("frame,constraint,kind,points_in_contact,contact_area_m2,max_penetration_m\n", 0), 0u);
  EXPECT_NE(contact.find("\n4,tools[0],sphere,"), std::string::npos) << contact;
  EXPECT_NE(read(fem / "reactions.csv").find("\n4,tools[0],sphere,"), std::string::npos);
  EXPECT_TRUE(std::filesystem::exists(folder / "pbd" / "contact.csv"));
  EXPECT_TRUE(std::filesystem::exists(folder / "hybrid" / "contact.csv"));

  nlohmann::json j = sphere_on_cube();
  j["models"] = {{{"model", "embedded"}}};
  const auto refused = run_experiment(load_experiment(write("sphere-embedded.json", j)), o);
  ASSERT_EQ(refused.size(), 1u);
  EXPECT_FALSE(refused[0].ok);
  EXPECT_NE(refused[0].error.find("model 'embedded' does not take sphere tools (tools[0])"), std::string::npos)
      << refused[0].error;
  EXPECT_EQ(refused[0].error.find('\n'), std::string::npos);
}

TEST_F(SphereScenarios, BadSpheresAreOneLineErrorsNamingFileAndKey) {
  nlohmann::json j = sphere_on_cube();
  j["tools"][0]["radius"] = 0;
  expect_error(j, "tools[0].radius: 0 is out of range");
  j = sphere_on_cube();
  j["tools"][0]["radius"] = -0.01;
  expect_error(j, "tools[0].radius: -0.01 is out of range");
  j = sphere_on_cube();
  j["tools"][0]["path"] = {{0, 0, 0, 0.13}, {0, 0, 0, 0.12}};
  expect_error(j, "tools[0].path[1]: frames must increase (0 after 0)");
  j = sphere_on_cube();
  j["tools"][0]["path"] = {{0, 0, 0, "NaN"}};
  expect_error(j, "tools[0].path[0]: must hold finite numbers");
  j = sphere_on_cube();
  j["tools"][0].erase("path");
  expect_error(j, "tools[0].path: a sphere needs the path of its centre");
  j = sphere_on_cube();
  j["tools"][0]["point"] = {0, 0, 0.1};
  expect_error(j, "tools[0]");
  // Starting inside the body: an error before any case runs.
  j = sphere_on_cube();
  j["tools"][0]["path"] = {{0, 0, 0, 0.11}};
  RunOptions o;
  o.out_dir = (dir / "out").string();
  o.progress = false;
  o.mesh_cache_dir = "";
  const auto outcomes = run_experiment(load_experiment(write("inside.json", j)), o);
  ASSERT_FALSE(outcomes.empty());
  EXPECT_FALSE(outcomes[0].ok);
  EXPECT_EQ(outcomes[0].error.rfind("inside.json: tools[0] (sphere): at its first centre (0, 0, 0.11) surface vertex", 0),
            0u)
      << outcomes[0].error;
  EXPECT_EQ(outcomes[0].error.find('\n'), std::string::npos);
}

}  // namespace
}  // namespace tb
