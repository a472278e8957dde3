// The problem package (experiments/problem_package.h): every file read back and
// checked against the mesh the runner builds, the scenario's loads_at frame by frame
// and the committed observation points; problem.json against its schema's
// requirements; deterministic bytes; and each bad input one line naming the file.
#include "problem_package.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>

#include "atomic_file.h"
#include "cli_run.h"
#include "csv_reader.h"
#include "mesh_io.h"
#include "mesh_recipe.h"
#include "observation_points.h"
#include "runner.h"
#include "test_support.h"
#include "tool_placement.h"

namespace tb {
namespace {
namespace fs = std::filesystem;

/// One mesh cache for the suite's tests: each scenario is meshed once.
const testing::TempFolder& cache() {
  static const testing::TempFolder folder("problem-package-cache");
  return folder;
}

/// An experiment of the suite's scenario `file` (experiments/scenarios/suite/) alone,
/// with its suite role, written in the cache's folder: the tests need no other
/// scenario's data.
std::string suite_experiment(const std::string& role, const std::string& file) {
  const nlohmann::json e = {
      {"name", "suite"},
      {"scenarios", {{{"file", std::string(TB_SOURCE_DIR) + "/experiments/scenarios/suite/" + file}, {"role", role}}}}};
  const std::string path = cache() / (role + ".json");
  std::ofstream(path) << e.dump();
  return path;
}

/// The suite's scenario of `role` in `file`, as loaded (not yet resolved on its mesh).
Scenario suite_scenario(const std::string& role, const std::string& file) {
  return load_experiment(suite_experiment(role, file)).scenarios.at(0);
}

/// Exports the suite's `role` (scenario file `file`) into `out`; returns its package folder.
fs::path export_role(const std::string& role, const std::string& file, const fs::path& out) {
  ExportOptions o;
  o.out_dir = out.string();
  o.mesh_cache_dir = cache().path.string();
  const std::string experiment = suite_experiment(role, file);
  const std::vector<std::string> written = export_problem_packages(load_experiment(experiment), experiment, o);
  EXPECT_EQ(written.size(), 1u);
  return written.at(0);
}

/// The mesh the package was written from (read from the shared cache).
HybridMesh built_mesh(const Scenario& s) {
  MeshReport report;
  bool hit = false;
  HybridMesh mesh = build_mesh_cached(s.mesh, report, cache().path.string(), hit);
  EXPECT_TRUE(hit);
  return mesh;
}

/// A CSV's rows as text cells, its header first.
std::vector<std::vector<std::string>> csv_rows(const std::string& file) {
  CsvReader csv(file, size_t{1} << 30);
  std::vector<std::vector<std::string>> rows{csv.header()};
  while (csv.next()) {
    rows.emplace_back();
    for (size_t c = 0; c < csv.header().size(); ++c) rows.back().push_back(csv.cell(static_cast<int>(c)));
  }
  return rows;
}

/// "frame,x,y,z" rows as numbers, one row a frame.
std::vector<Eigen::Vector3d> frame_values(const std::string& file) {
  CsvReader csv(file, size_t{1} << 30);
  csv.expect_header({"frame", "x", "y", "z"});
  std::vector<Eigen::Vector3d> out;
  while (csv.next()) {
    EXPECT_EQ(csv.integer(0), static_cast<long>(out.size())) << file;
    out.emplace_back(csv.number(1), csv.number(2), csv.number(3));
  }
  return out;
}

/// What `value` breaks of `schema` (JSON Schema 2020-12: the keywords problem.schema.json
/// uses: $ref to #/$defs, type, required, properties, items, const, enum, minimum and
/// exclusive bounds, minItems, maxItems, pattern). python3-jsonschema is not a
/// dependency of the project (scripts/setup).
void schema_errors(const nlohmann::json& value, const nlohmann::json& schema, const nlohmann::json& root,
                   const std::string& at, std::vector<std::string>& errors) {
  if (schema.contains("$ref")) {
    const std::string ref = schema["$ref"];
    const std::string prefix = "#/$defs/";
    ASSERT_EQ(ref.rfind(prefix, 0), 0u) << ref;
    schema_errors(value, root["$defs"][ref.substr(prefix.size())], root, at, errors);
  }
  auto fail = [&](const std::string& what) {
    errors.push_back(at + ": " + what + " (" + value.dump().substr(0, 80) + ")");
  };
  if (schema.contains("type")) {
    auto is = [&](const std::string& t) {
      return (t == "object" && value.is_object()) || (t == "array" && value.is_array()) ||
             (t == "string" && value.is_string()) || (t == "integer" && value.is_number_integer()) ||
             (t == "number" && value.is_number()) || (t == "boolean" && value.is_boolean()) ||
             (t == "null" && value.is_null());
    };
    bool ok = false;
    if (schema["type"].is_string()) ok = is(schema["type"]);
    for (const auto& t : schema["type"].is_array() ? schema["type"] : nlohmann::json::array()) ok = ok || is(t);
    if (!ok) return fail("not of type " + schema["type"].dump());
  }
  if (schema.contains("const") && value != schema["const"]) fail("not " + schema["const"].dump());
  if (schema.contains("enum") && std::find(schema["enum"].begin(), schema["enum"].end(), value) == schema["enum"].end())
    fail("not one of " + schema["enum"].dump());
  if (value.is_number()) {
    const double x = value;
    if (schema.contains("minimum") && x < schema["minimum"].get<double>()) fail("below the minimum");
    if (schema.contains("maximum") && x > schema["maximum"].get<double>()) fail("above the maximum");
    if (schema.contains("exclusiveMinimum") && x <= schema["exclusiveMinimum"].get<double>())
      fail("not above the bound");
    if (schema.contains("exclusiveMaximum") && x >= schema["exclusiveMaximum"].get<double>())
      fail("not below the bound");
  }
  if (value.is_string() && schema.contains("pattern") &&
      !std::regex_search(value.get<std::string>(), std::regex(schema["pattern"].get<std::string>())))
    fail("does not match " + schema["pattern"].get<std::string>());
  if (value.is_object()) {
    for (const auto& key : schema.value("required", nlohmann::json::array()))
      if (!value.contains(key)) fail("lacks the required key " + key.dump());
    if (schema.contains("properties"))
      for (const auto& [key, sub] : schema["properties"].items())
        if (value.contains(key)) schema_errors(value[key], sub, root, at + "." + key, errors);
  }
  if (value.is_array()) {
    if (schema.contains("minItems") && value.size() < schema["minItems"].get<size_t>()) fail("too few items");
    if (schema.contains("maxItems") && value.size() > schema["maxItems"].get<size_t>()) fail("too many items");
    if (schema.contains("items"))
      for (size_t i = 0; i < value.size(); ++i)
        schema_errors(value[i], schema["items"], root, at + "[" + std::to_string(i) + "]", errors);
  }
}

std::vector<std::string> problem_schema_errors(const nlohmann::json& problem) {
  const nlohmann::json schema = nlohmann::json::parse(read_file(default_schema_dir() + "/problem.schema.json"));
  std::vector<std::string> errors;
  schema_errors(problem, schema, schema, "problem.json", errors);
  return errors;
}

/// The package's observation points equal the committed role's id, patch, x, y, z
/// (`surface` gives the liver's coordinates); no converged value is copied.
void expect_committed_points(const fs::path& package, const std::string& role) {
  const auto written = csv_rows((package / "observation_points.csv").string());
  const auto committed = csv_rows(default_observation_points_dir() + "/" + role + ".csv");
  ASSERT_EQ(written.size(), committed.size());
  EXPECT_EQ(written[0], (std::vector<std::string>{"id", "patch", "x", "y", "z"}));
  auto column = [&](const std::string& name) {
    return std::find(committed[0].begin(), committed[0].end(), name) - committed[0].begin();
  };
  for (size_t r = 1; r < written.size(); ++r) {
    EXPECT_EQ(written[r][0], committed[r][column("id")]);
    EXPECT_EQ(written[r][1], committed[r][column("patch")]);
    for (int c = 0; c < 3; ++c)
      EXPECT_EQ(std::stod(written[r][2 + c]), std::stod(committed[r][column(std::string(1, char('x' + c)))]))
          << role << " row " << r;
  }
}

TEST(ProblemPackage, CubePullDiscFilesMatchTheMeshTheLoadsAndTheCommittedPoints) {
  const testing::TempFolder out("problem-package-cube");
  const fs::path package = export_role("cube_pull_disc", "cube-pull-disc.json", out.path);
  Scenario s = suite_scenario("cube_pull_disc", "cube-pull-disc.json");
  EXPECT_EQ(package.filename(), s.name);
  const HybridMesh mesh = built_mesh(s);
  resolve_on_mesh(s, mesh.fine_surface);

  const nlohmann::json problem = nlohmann::json::parse(read_file((package / "problem.json").string()));
  const std::vector<std::string> errors = problem_schema_errors(problem);
  EXPECT_TRUE(errors.empty()) << errors.front();
  EXPECT_EQ(problem["role"], "cube_pull_disc");
  EXPECT_EQ(problem["material"]["law"], "neo_hookean");
  EXPECT_NE(problem["material"]["energy_density"].get<std::string>().find("Bonet and Wood 2008"), std::string::npos);
  EXPECT_DOUBLE_EQ(problem["material"]["youngs_modulus"], s.material.youngs_modulus);

  // The meshes: the surface as built, in both formats; the volume's two files alike and as built.
  const SurfaceMesh obj = read_surface((package / "surface.obj").string());
  EXPECT_EQ(obj.V, mesh.fine_surface.V);
  EXPECT_EQ(obj.F, mesh.fine_surface.F);
  EXPECT_EQ(problem["meshes"]["surface"]["vertices"], obj.V.rows());
  EXPECT_EQ(problem["meshes"]["surface"]["triangles"], obj.F.rows());
  const SurfaceMesh stl = read_surface((package / "surface.stl").string());
  EXPECT_EQ(stl.V.rows(), obj.V.rows());
  ASSERT_EQ(stl.F.rows(), obj.F.rows());
  for (Eigen::Index t = 0; t < obj.F.rows(); ++t)  // the same triangles, corner by corner, to the bit
    for (int k = 0; k < 3; ++k) ASSERT_EQ(stl.V.row(stl.F(t, k)), obj.V.row(obj.F(t, k))) << "triangle " << t;
  const TetMesh vtu = read_volume((package / "volume.vtu").string());
  const TetMesh msh = read_volume((package / "volume.msh").string());
  EXPECT_EQ(msh.V, vtu.V);
  EXPECT_EQ(msh.T, vtu.T);
  EXPECT_EQ(vtu.V, mesh.fine_volume.V);
  EXPECT_EQ(vtu.T, mesh.fine_volume.T);
  EXPECT_EQ(problem["meshes"]["volume"]["nodes"], vtu.V.rows());
  EXPECT_EQ(problem["meshes"]["volume"]["tets"], vtu.T.rows());

  // The support: the surface vertices the scenario's box holds.
  const std::vector<char> clamped = s.support.select(mesh.fine_surface.V);
  std::vector<std::vector<std::string>> expected{{"vertex"}};
  for (size_t v = 0; v < clamped.size(); ++v)
    if (clamped[v]) expected.push_back({std::to_string(v)});
  EXPECT_EQ(csv_rows((package / "support_vertices.csv").string()), expected);

  // The load, frame by frame, to the bit; no tool.
  const int frames = problem["time"]["frames"];
  EXPECT_EQ(frames, package_frames(s));
  EXPECT_EQ(problem["observation"]["frames"], nlohmann::json::array({frames - 1}));
  ASSERT_EQ(problem["loads"].size(), 1u);
  EXPECT_EQ(problem["loads"][0]["type"], "surface_traction");
  const std::vector<Eigen::Vector3d> load = frame_values((package / "load_0.csv").string());
  ASSERT_EQ(load.size(), static_cast<size_t>(frames));
  FrameLoads at;
  for (int f = 0; f < frames; ++f) {
    s.loads_at(f, at);
    EXPECT_EQ(load[static_cast<size_t>(f)], at.values[0]) << "frame " << f;
  }
  EXPECT_TRUE(problem["tools"].empty());
  EXPECT_FALSE(fs::exists(package / "tool_0.csv"));
  EXPECT_FALSE(problem.contains("gravity"));

  expect_committed_points(package, "cube_pull_disc");
  EXPECT_FALSE(fs::exists(package / "observation_interior.csv"));
  for (const char* schema : {"problem.schema.json", "submission.schema.json"})
    EXPECT_EQ(read_file((package / schema).string()), read_file(default_schema_dir() + "/" + schema));
  // No converged answer anywhere in the package.
  for (const auto& entry : fs::directory_iterator(package)) {
    if (entry.path().extension() != ".csv") continue;
    EXPECT_EQ(read_file(entry.path().string()).find("ux"), std::string::npos) << entry.path();
  }

  // The same bytes a second time; nothing left beside the package.
  const testing::TempFolder again("problem-package-cube-again");
  const fs::path second = export_role("cube_pull_disc", "cube-pull-disc.json", again.path);
  for (const auto& entry : fs::directory_iterator(package))
    EXPECT_EQ(read_file(entry.path().string()), read_file((second / entry.path().filename()).string()))
        << entry.path().filename();
  EXPECT_EQ(std::distance(fs::directory_iterator(out.path), fs::directory_iterator()), 1);
}

TEST(ProblemPackage, LBlockGraspHasItsToolPathAndPoints) {
  const testing::TempFolder out("problem-package-l-block");
  const fs::path package = export_role("l_block_grasp", "l-block-grasp.json", out.path);
  Scenario s = suite_scenario("l_block_grasp", "l-block-grasp.json");
  const HybridMesh mesh = built_mesh(s);
  resolve_on_mesh(s, mesh.fine_surface);
  const nlohmann::json problem = nlohmann::json::parse(read_file((package / "problem.json").string()));
  const std::vector<std::string> errors = problem_schema_errors(problem);
  EXPECT_TRUE(errors.empty()) << errors.front();
  EXPECT_TRUE(problem["loads"].empty());
  ASSERT_EQ(problem["tools"].size(), 1u);
  EXPECT_EQ(problem["tools"][0]["type"], "grasp");
  EXPECT_EQ(problem["tools"][0]["path"], "tool_0.csv");
  const std::vector<int> held = tool_vertices(s.tools[0].tool, mesh.fine_surface, s.support);
  EXPECT_GT(held.size(), 0u);
  EXPECT_EQ(problem["tools"][0]["held_vertices"], held.size());
  std::vector<std::vector<std::string>> held_rows{{"vertex"}};
  for (int v : held) held_rows.push_back({std::to_string(v)});
  EXPECT_EQ(csv_rows((package / "tool_0_vertices.csv").string()), held_rows);
  EXPECT_EQ(problem["submission"]["files"].back(), "forces.csv");
  const int frames = problem["time"]["frames"];
  const std::vector<Eigen::Vector3d> tool = frame_values((package / "tool_0.csv").string());
  ASSERT_EQ(tool.size(), static_cast<size_t>(frames));
  FrameLoads at;
  for (int f = 0; f < frames; ++f) {
    s.loads_at(f, at);
    EXPECT_EQ(tool[static_cast<size_t>(f)], at.tool_values[0]) << "frame " << f;
  }
  EXPECT_EQ(read_volume((package / "volume.msh").string()).T, mesh.fine_volume.T);
  expect_committed_points(package, "l_block_grasp");
}

TEST(ProblemPackage, AFinerStudysRoleTakesItsBaseRolesPoints) {
  const testing::TempFolder dir("problem-package-roles");
  for (const char* role : {"flap_gravity", "cube_pull_disc", "cube_pull_disc_10k"})
    std::ofstream(fs::path(dir.path) / (std::string(role) + ".json")) << "{}";
  EXPECT_EQ(observation_role(dir.path, "flap_gravity"), "flap_gravity");
  EXPECT_EQ(observation_role(dir.path, "flap_gravity_10k"), "flap_gravity");
  EXPECT_EQ(observation_role(dir.path, "flap_gravity_100k"), "flap_gravity");
  EXPECT_EQ(observation_role(dir.path, "cube_pull_disc_10k"), "cube_pull_disc_10k");  // its own files first
  EXPECT_EQ(observation_role(dir.path, "torus_grasp_10k"), "torus_grasp_10k");  // no base: reading names it
  EXPECT_EQ(observation_role(dir.path, "flap_gravity_fine"), "flap_gravity_fine");  // not a finer study's name
}

TEST(ProblemPackage, ScenarioWithoutRoleObservesItsOwnVertices) {
  const testing::TempFolder out("problem-package-small");
  nlohmann::json small = nlohmann::json::parse(R"({
    "name": "small",
    "mesh": {"type": "cube", "nx": 4, "ny": 4, "nz": 4, "fine_tetgen": {"max_volume": 2e-6},
             "coarse_selection": {"target_nodes": 30}},
    "support": {"min": [-1, -1, -1e-9], "max": [1, 1, 1e-9]},
    "load": {"point": [0, 0, 0.1], "force": [0, 0, 0.1], "ramp_frames": 5},
    "probes": {"points": [[0, 0, 0.05]]},
    "frames": {"static": 3},
    "models": [{"model": "fem"}]
  })");
  const std::string file = out / "small.json";
  std::ofstream(file) << small.dump();
  ExportOptions o;
  o.out_dir = out / "packages";
  const fs::path package = export_problem_packages(load_experiment(file), file, o).at(0);
  const nlohmann::json problem = nlohmann::json::parse(read_file((package / "problem.json").string()));
  EXPECT_EQ(problem["role"], "");
  EXPECT_EQ(problem["time"]["frames"], 5);  // the ramp outlasts the static frames
  const Scenario s = load_experiment(file).scenarios.at(0);
  const SurfaceMesh surface = read_surface((package / "surface.obj").string());
  const auto points = csv_rows((package / "observation_points.csv").string());
  const std::vector<int> top = observed_vertices(s, surface.V);
  ASSERT_EQ(points.size(), top.size() + 1);
  for (size_t k = 0; k < top.size(); ++k) EXPECT_EQ(points[k + 1][0], "s" + std::to_string(top[k]));
  EXPECT_EQ(csv_rows((package / "observation_interior.csv").string()),
            (std::vector<std::vector<std::string>>{{"id", "x", "y", "z"}, {"p0", "0", "0", "0.050000000000000003"}}));
}

/// `tissuebench export ARGS` fails with one line naming `file` and saying `problem`.
void expect_cli_error(const std::string& args, const std::string& file, const std::string& problem) {
  std::string output;
  EXPECT_NE(testing::run_tissuebench("export " + args + " --quiet", output), 0) << output;
  EXPECT_EQ(std::count(output.begin(), output.end(), '\n'), 1) << output;
  EXPECT_NE(output.find(file), std::string::npos) << output;
  EXPECT_NE(output.find(problem), std::string::npos) << output;
}

/// export_problem_packages on `experiment` with `options` fails with one line naming
/// `file` and saying `problem`.
void expect_export_error(const std::string& experiment, ExportOptions options, const std::string& file,
                         const std::string& problem) {
  options.mesh_cache_dir = cache().path.string();
  try {
    export_problem_packages(load_experiment(experiment), experiment, options);
    ADD_FAILURE() << "no error";
  } catch (const std::exception& e) {
    const std::string what = e.what();
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_NE(what.find(file), std::string::npos) << what;
    EXPECT_NE(what.find(problem), std::string::npos) << what;
  }
}

TEST(ProblemPackage, BadInputsAreOneLineErrorsNamingTheFile) {
  const testing::TempFolder out("problem-package-errors");
  const std::string cube = suite_experiment("cube_pull_disc", "cube-pull-disc.json");
  ExportOptions o;
  o.out_dir = out / "p";
  o.only_scenario = "no_such_role";
  expect_export_error(cube, o, cube, "no scenario named 'no_such_role'");
  std::ofstream(out / "blocker") << "a file\n";
  o.only_scenario.clear();
  o.out_dir = out / "blocker/p";
  expect_export_error(cube, o, out / "blocker/p", "cannot create the output folder");
  // Points missing for the role, through the program: one line, a failing status, and
  // nothing written, not even a staging folder.
  fs::create_directories(out / "empty");
  expect_cli_error(cube + " --mesh-cache " + cache().path.string() + " --observation-points " + out / "empty" +
                       " --out " + out / "p",
                   out / "empty/cube_pull_disc.json", "cannot open file");
  EXPECT_TRUE(fs::is_empty(out / "p"));
}

/// Third-party geometry (README, "Data"): the liver's points are the built surface's
/// vertices at the committed source_vertex, the Truth Cube's beads the scenario's probes
/// at the committed table_row.
TEST(ProblemPackage, LiverAndTruthCubePointsArePlacedOnTheBuiltScenario) {
  const DataDir data = data_dir();
  if (!fs::exists(data.path + "/meshes/liver-smooth.obj") ||
      !fs::exists(data.path + "/data/truthcube/uniaxial_positions.csv"))
    GTEST_SKIP() << "the liver's and the Truth Cube's files are not in " << data.path;
  const testing::TempFolder out("problem-package-data");
  {
    const fs::path package = export_role("liver_grasp_gravity", "liver-grasp-gravity.json", out.path);
    const SurfaceMesh surface = read_surface((package / "surface.obj").string());
    CsvReader committed(default_observation_points_dir() + "/liver_grasp_gravity.csv", size_t{1} << 30);
    CsvReader written((package / "observation_points.csv").string(), size_t{1} << 30);
    const int source = committed.require_column("source_vertex");
    int rows = 0;
    while (committed.next()) {
      ASSERT_TRUE(written.next());
      EXPECT_EQ(written.cell(0), committed.cell(0));
      const Eigen::RowVector3d x(written.number(2), written.number(3), written.number(4));
      EXPECT_EQ(x, surface.V.row(committed.integer(source))) << written.cell(0);
      ++rows;
    }
    EXPECT_FALSE(written.next());
    EXPECT_GT(rows, 0);
    EXPECT_EQ(csv_rows((package / "observation_interior.csv").string()).size(), 2u);
  }
  {
    const fs::path package = export_role("truth_cube_5", "truth-cube-05.json", out.path);
    const Scenario s = suite_scenario("truth_cube_5", "truth-cube-05.json");
    expect_committed_points(package, "truth_cube_5");
    CsvReader committed(default_observation_points_dir() + "/truth_cube_5_interior.csv", size_t{1} << 30);
    CsvReader written((package / "observation_interior.csv").string(), size_t{1} << 30);
    written.expect_header({"id", "x", "y", "z"});
    const int row = committed.require_column("table_row");
    int beads = 0;
    while (committed.next()) {
      ASSERT_TRUE(written.next());
      EXPECT_EQ(written.cell(0), committed.cell(0));
      const Eigen::RowVector3d x(written.number(1), written.number(2), written.number(3));
      EXPECT_EQ(x, s.probes.row(committed.integer(row)));
      ++beads;
    }
    EXPECT_EQ(beads, 343);
    const nlohmann::json problem = nlohmann::json::parse(read_file((package / "problem.json").string()));
    EXPECT_EQ(problem["observation"]["interior_count"], 343);
    EXPECT_EQ(problem["tools"][0]["type"], "bonded_plate");
  }
}

}  // namespace
}  // namespace tb
