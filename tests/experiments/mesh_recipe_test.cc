// Mesh recipes: the "shape" type, the cube's defaults shared by
// scenario files and `tissuebench mesh --cube`, the unit-scale warning, and the
// coarse-mesh quality fields of summary.json.
#include "mesh_recipe.h"

#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <map>

#include "atomic_file.h"
#include "cli_run.h"
#include "mesh_checks.h"
#include "scenario.h"
#include "strict_json.h"
#include "test_support.h"

namespace tb {
namespace {

/// The mesh recipe of a committed scenario file.
MeshRecipe scenario_recipe(const std::string& name) {
  return load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/" + name + ".json").scenarios.at(0).mesh;
}

void expect_recipe_error(const nlohmann::json& j, const std::string& message) {
  try {
    parse_mesh_recipe(j, ".", "s.json: mesh");
    FAIL() << "accepted: " << j.dump();
  } catch (const ScenarioError& e) {
    EXPECT_NE(std::string(e.what()).find("s.json: mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(MeshRecipe, ShapeKeysAreStrict) {
  const MeshRecipe r = parse_mesh_recipe({{"type", "shape"}, {"shape", "torus"}, {"resolution", 20}}, ".", "s.json");
  EXPECT_EQ(r.kind, MeshRecipe::Kind::Shape);
  EXPECT_EQ(r.shape.name, "torus");
  EXPECT_EQ(r.shape.resolution, 20);
  EXPECT_EQ(r.build.fine_tetgen.max_volume, 0);  // the cube's bound is the cube's only
  expect_recipe_error({{"type", "shape"}}, "shape");
  expect_recipe_error({{"type", "shape"}, {"shape", "cylinder"}}, "'cylinder' is not one of");
  expect_recipe_error({{"type", "shape"}, {"shape", "torus"}, {"resolution", 3}}, "resolution");
  expect_recipe_error({{"type", "shape"}, {"shape", "torus"}, {"resolutoin", 20}}, "unknown key 'resolutoin'");
  expect_recipe_error({{"type", "shape"}, {"shape", "torus"}, {"side", 0.1}}, "unknown key 'side'");
  expect_recipe_error({{"type", "cube"}, {"coarse_selection", {{"min_dihedral_deg", 45}}}}, "min_dihedral_deg");
}

TEST(MeshRecipe, BareCubeIsThePaperScenariosCube) {
  // One place states the cube's defaults: a recipe that gives none builds the
  // same mesh as the committed cube scenarios (same content hash).
  const MeshRecipe bare = parse_mesh_recipe({{"type", "cube"}}, ".", "cli");
  EXPECT_EQ(bare.build.fine_tetgen.max_volume, kPaperCubeFineMaxVolume);
  EXPECT_EQ(mesh_content_hash(bare), mesh_content_hash(scenario_recipe("cube-pull")));
  EXPECT_EQ(mesh_content_hash(bare), mesh_content_hash(scenario_recipe("cube-push")));
}

TEST(MeshCommand, CubeWithNoOptionIsThePaperCube) {
  const testing::TempFolder dir("cli-cube");
  std::string out;
  ASSERT_EQ(testing::run_tissuebench("mesh --cube --out " + dir / "m", out), 0) << out;
  const auto j = nlohmann::json::parse(read_file(dir / "m/summary.json"));
  EXPECT_EQ(j.at("surface_vertices"), 682);
  EXPECT_EQ(j.at("fine_nodes"), 3114);
  EXPECT_EQ(j.at("warnings"), nlohmann::json::array());
}

TEST(MeshCommand, ShapeAndItsErrors) {
  const testing::TempFolder dir("cli-shape");
  std::string out;
  ASSERT_EQ(testing::run_tissuebench("mesh --shape dumbbell --resolution 10 --out " + dir / "m", out), 0) << out;
  const auto j = nlohmann::json::parse(read_file(dir / "m/summary.json"));
  EXPECT_GT(j.at("coarse_nodes").get<int>(), 100);
  // The coarse mesh of a curved surface lies inside it: the distance is reported.
  EXPECT_GT(j.at("max_embedding_distance").get<double>(), 0);
  EXPECT_LT(j.at("max_embedding_distance").get<double>(), 0.01);
  EXPECT_EQ(j.at("coarse_tets_below_5deg"), 0);
  EXPECT_TRUE(j.contains("fine_tets_below_5deg"));
  EXPECT_NE(testing::run_tissuebench("mesh --shape cylinder --out " + dir / "x", out), 0);
  EXPECT_NE(out.find("'cylinder' is not one of"), std::string::npos) << out;
  EXPECT_NE(testing::run_tissuebench("mesh --cube --resolution 20 --out " + dir / "x", out), 0);
  EXPECT_NE(out.find("--resolution requires --shape"), std::string::npos) << out;
  EXPECT_NE(testing::run_tissuebench("mesh --shape torus --unit-scale 0.01 --out " + dir / "x", out), 0);
  EXPECT_NE(out.find("--unit-scale requires --surface"), std::string::npos) << out;
  EXPECT_NE(testing::run_tissuebench("mesh --cube --shape torus --out " + dir / "x", out), 0);
  EXPECT_NE(out.find("excludes"), std::string::npos) << out;
}

TEST(MeshRecipe, UnitScaleThatLooksWrongIsAWarning) {
  const testing::TempFolder dir("scale");
  // A unit tetrahedron as a closed surface.
  write_file_atomically(dir / "tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  for (const auto& [scale, expect_warning] :
       std::vector<std::pair<double, bool>>{{1.0, false}, {20.0, true}, {1e-4, true}, {0.05, false}}) {
    MeshRecipe r =
        parse_mesh_recipe({{"type", "files"}, {"surface", dir / "tet.obj"}, {"unit_scale", scale}}, ".", "s.json");
    r.build.target_coarse_nodes = 4;
    MeshReport report;
    const HybridMesh h = build_mesh(r, report);
    ASSERT_EQ(report.warnings.size(), expect_warning ? 1u : 0u) << scale;
    const auto j = report.to_json(h);
    ASSERT_EQ(j.at("warnings").size(), report.warnings.size());
    if (expect_warning) {
      EXPECT_NE(report.warnings[0].find("tet.obj: bounding-box diagonal"), std::string::npos) << report.warnings[0];
      EXPECT_NE(report.warnings[0].find("is unit_scale right"), std::string::npos) << report.warnings[0];
    }
  }
}

TEST(MeshRecipe, CacheKeepsWarningsAndRepairCounts) {
  const testing::TempFolder dir("scale-cache");
  write_file_atomically(dir / "tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  MeshRecipe r =
      parse_mesh_recipe({{"type", "files"}, {"surface", dir / "tet.obj"}, {"unit_scale", 20.0}}, ".", "s.json");
  r.build.target_coarse_nodes = 4;
  MeshReport built, cached;
  bool hit = false;
  const HybridMesh a = build_mesh_cached(r, built, dir / "cache", hit);
  ASSERT_FALSE(hit);
  const HybridMesh b = build_mesh_cached(r, cached, dir / "cache", hit);
  ASSERT_TRUE(hit);
  EXPECT_EQ(built.to_json(a), cached.to_json(b));
  EXPECT_EQ(cached.warnings.size(), 1u);
}

TEST(ShapesExperiment, SupportAndLoadResolveOnTheGeneratedSurfaces) {
  // The shapes scenarios say "lowest fifth" and "highest vertex" (or the vertex
  // nearest a flat top's centre): on the generated surfaces that is a support up
  // to 0.2 of the height and a load at a highest vertex.
  const Experiment e = load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/shapes.json");
  ASSERT_EQ(e.scenarios.size(), 2 * shape_names().size());
  std::map<std::string, int> per_shape;
  for (Scenario s : e.scenarios) {
    ASSERT_EQ(s.mesh.kind, MeshRecipe::Kind::Shape) << s.name;
    ++per_shape[s.mesh.shape.name];
    const SurfaceMesh surface = make_shape_surface(s.mesh.shape);
    resolve_on_mesh(s, surface);
    const double height = surface.V.col(2).maxCoeff();
    EXPECT_NEAR(s.support.max.z(), 0.2 * height, 1e-15) << s.name;
    const std::vector<char> clamped = s.support.select(surface.V);
    EXPECT_GE(std::count(clamped.begin(), clamped.end(), 1), 3) << s.name;
    Eigen::Index nearest;
    const double d = (surface.V.rowwise() - s.load.point.transpose()).rowwise().norm().minCoeff(&nearest);
    EXPECT_LT(d, 1e-15) << s.name << ": the load point is not a surface vertex";
    EXPECT_EQ(surface.V(nearest, 2), height) << s.name << ": the load point is not a highest vertex";
    EXPECT_EQ(s.observed, "all") << s.name;
  }
  for (const auto& name : shape_names()) EXPECT_EQ(per_shape[name], 2) << name;
}

}  // namespace
// write_mesh_folder stages and renames (docs/robustness.md, "Interrupted runs"): a
// second write replaces the folder whole, a dead process's staging folder beside it
// is removed, and a folder holding files of the user's keeps them.
TEST(MeshRecipe, MeshFolderIsReplacedWholeAndAUsersFolderKeepsItsFiles) {
  namespace fs = std::filesystem;
  const testing::TempFolder dir("mesh-folder");
  write_file_atomically(dir / "tet.obj", "v 0 0 0\nv 1 0 0\nv 0 1 0\nv 0 0 1\nf 1 3 2\nf 1 2 4\nf 1 4 3\nf 2 3 4\n");
  MeshRecipe r = parse_mesh_recipe({{"type", "files"}, {"surface", dir / "tet.obj"}}, ".", "s.json");
  r.build.target_coarse_nodes = 4;
  MeshReport report;
  const HybridMesh h = build_mesh(r, report);
  const pid_t child = fork();  // a pid no process holds once reaped: a killed run's
  if (child == 0) _exit(0);
  waitpid(child, nullptr, 0);
  const fs::path mesh = fs::path(dir / "mesh");
  fs::create_directories(mesh.string() + ".tmp" + std::to_string(child));
  std::ofstream(mesh.string() + ".tmp" + std::to_string(child) + "/summary.json") << "{}";
  write_mesh_folder(mesh.string(), h, report);
  write_mesh_folder(mesh.string(), h, report);
  std::vector<std::string> names;
  for (const auto& e : fs::directory_iterator(dir.path)) names.push_back(e.path().filename().string());
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"mesh", "tet.obj"}));
  EXPECT_TRUE(fs::exists(mesh / "summary.json"));
  EXPECT_TRUE(fs::exists(mesh / "fine_surface.vtu"));

  const fs::path user = fs::path(dir / "user");
  fs::create_directories(user);
  std::ofstream(user / "notes.txt") << "mine";
  write_mesh_folder(user.string(), h, report);
  EXPECT_EQ(read_file((user / "notes.txt").string()), "mine");
  EXPECT_TRUE(fs::exists(user / "summary.json"));
  EXPECT_FALSE(fs::exists(user.string() + ".tmp" + std::to_string(getpid())));
}

}  // namespace tb
