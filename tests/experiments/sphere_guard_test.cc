// The runner's guard on rigid spheres (experiments/sphere_guard.h): the winding
// number, the triangles' penetration and the segment test against closed forms; a
// sphere jumped into the cube, or through it, in one frame stopping its cases with one
// line; long moves onto and off the cube, a normal press and a press into the
// L-block's concave corner passing, the press recording its faces' small penetration.
#include "sphere_guard.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>

#include "mesh_recipe.h"
#include "runner.h"
#include "scenario_fixture.h"
#include "shapes.h"

namespace tb {
namespace {

/// The unit cube [0, 1]^3: 8 vertices, 12 outward-oriented triangles.
SurfaceMesh unit_cube() {
  SurfaceMesh s;
  s.V.resize(8, 3);
  for (int i = 0; i < 8; ++i) s.V.row(i) << (i & 1), (i >> 1) & 1, (i >> 2) & 1;
  // Each face as a quad (a, b, c, d) counter-clockwise seen from outside.
  const int quads[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
  s.F.resize(12, 3);
  for (int q = 0; q < 6; ++q) {
    s.F.row(2 * q) << quads[q][0], quads[q][1], quads[q][2];
    s.F.row(2 * q + 1) << quads[q][0], quads[q][2], quads[q][3];
  }
  return s;
}

SphereAgainstSurface against(const SurfaceMesh& s, const Eigen::Vector3d& centre, double radius) {
  return sphere_against_surface(s.V, s.F, centre, radius);
}

// The path check, run directly on the unit cube with made-up surfaces: a sphere of
// radius 0.2 starts 0.3 above the top. (a) It moves 0.35 down to z = 0.95 while the
// top has moved 0.3 down (a press): the move is longer than the centre's distance to
// both surfaces, so the path is tested; it crosses the surface of the frame before
// (z = 1) but not this frame's (z = 0.7): no error. (b) It moves through the whole
// undeformed cube to z = -0.5 in one frame: its path crosses both surfaces and its
// centre ends outside (winding number 0): the one-line error.
TEST(SphereGuard, ThePathCheckPassesAPressAndStopsASphereThatCrossedTheBody) {
  const SurfaceMesh cube = unit_cube();
  const std::vector<Tool> tools = {Tool::sphere({0.5, 0.5, 1.3}, 0.2)};
  const Points rest_u = Points::Zero(8, 3);
  Points pressed = Points::Zero(8, 3);
  for (int i = 4; i < 8; ++i) pressed(i, 2) = -0.3;  // the top's four corners (z = 1) down to 0.7
  {
    SphereGuard guard(tools, cube);
    guard.check(0, rest_u, {Eigen::Vector3d(0.5, 0.5, 1.3)});
    EXPECT_NO_THROW(guard.check(1, pressed, {Eigen::Vector3d(0.5, 0.5, 0.95)}));
    EXPECT_NEAR(guard.to_json()["tools"]["tools[0]"]["largest_move_per_frame_m"].get<double>(), 0.35, 1e-12);
  }
  // The segment of (a) meets the surface before and misses the pressed one: what the check tells apart.
  SurfaceMesh top_down = cube;
  top_down.V += pressed;
  EXPECT_TRUE(segment_meets_surface(cube.V, cube.F, {0.5, 0.5, 1.3}, {0.5, 0.5, 0.95}));
  EXPECT_FALSE(segment_meets_surface(top_down.V, top_down.F, {0.5, 0.5, 1.3}, {0.5, 0.5, 0.95}));
  SphereGuard guard(tools, cube);
  guard.check(0, rest_u, {Eigen::Vector3d(0.5, 0.5, 1.3)});
  try {
    guard.check(1, rest_u, {Eigen::Vector3d(0.5, 0.5, -0.5)});
    ADD_FAILURE() << "a sphere that crossed the body in one frame was not stopped";
  } catch (const std::runtime_error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("tools[0]"), std::string::npos) << what;
    EXPECT_NE(what.find("frame 1"), std::string::npos) << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
  }
}

TEST(SphereAgainstSurface, UnitCubeWindingNumberAndFacePenetrationAreTheClosedForms) {
  const SurfaceMesh cube = unit_cube();
  // Away from the surface the winding number of a closed surface is an integer.
  EXPECT_NEAR(against(cube, {0.5, 0.5, 0.5}, 0.1).winding_number, 1, 1e-12);
  EXPECT_NEAR(against(cube, {0.9, 0.1, 0.2}, 0.1).winding_number, 1, 1e-12);
  EXPECT_NEAR(against(cube, {2, 0.5, 0.5}, 0.1).winding_number, 0, 1e-12);
  EXPECT_NEAR(against(cube, {-3, 4, 7}, 0.1).winding_number, 0, 1e-12);
  // A micrometre either side of the top face (and of an edge, a corner).
  EXPECT_NEAR(against(cube, {0.5, 0.5, 1 - 1e-6}, 0.1).winding_number, 1, 1e-5);
  EXPECT_NEAR(against(cube, {0.5, 0.5, 1 + 1e-6}, 0.1).winding_number, 0, 1e-5);
  EXPECT_GE(against(cube, {1 - 1e-6, 0.5, 1 - 1e-6}, 0.1).winding_number, kInsideWindingNumber);
  EXPECT_LT(against(cube, {1 + 1e-6, 1 + 1e-6, 1 + 1e-6}, 0.1).winding_number, kInsideWindingNumber);
  // Penetration r - distance: to the face, the edge, the corner; none when clear.
  EXPECT_NEAR(against(cube, {0.5, 0.5, 1.2}, 0.3).face_penetration, 0.1, 1e-15);
  EXPECT_NEAR(against(cube, {0.3, -0.25, 0.6}, 0.3).face_penetration, 0.05, 1e-15);
  EXPECT_NEAR(against(cube, {1.1, 0.5, 1.1}, 0.2).face_penetration, 0.2 - std::sqrt(0.02), 1e-15);
  EXPECT_NEAR(against(cube, {1.1, 1.1, 1.1}, 0.2).face_penetration, 0.2 - std::sqrt(0.03), 1e-15);
  EXPECT_EQ(against(cube, {0.5, 0.5, 1.2}, 0.19).face_penetration, 0);
  EXPECT_EQ(against(cube, {1.1, 1.1, 1.1}, 0.17).face_penetration, 0);
  // A centre inside: the nearest face point, from the inside.
  EXPECT_NEAR(against(cube, {0.5, 0.5, 0.9}, 0.3).face_penetration, 0.2, 1e-15);
}

/// An equilateral triangle with its vertices on the sphere: the nearest point is its
/// centre, at sqrt(r^2 - R^2) from the sphere's (R its circumradius): the most a
/// triangle whose vertices are all outside the sphere can reach into it (for x in the
/// triangle, |x - c|^2 = sum_i l_i |v_i - c|^2 - R^2 + |x - o|^2 >= r^2 - R^2, o the
/// circumcentre): what a model holding only the nodes out of the sphere allows.
TEST(SphereAgainstSurface, ATriangleWithItsVerticesOnTheSphereSagsByTheChordBound) {
  const double r = 0.0127, R = 0.006;
  SurfaceMesh tri;
  tri.V.resize(3, 3);
  const double h = std::sqrt(r * r - R * R);
  for (int i = 0; i < 3; ++i) tri.V.row(i) << R * std::cos(2 * M_PI * i / 3), R * std::sin(2 * M_PI * i / 3), h;
  tri.F.resize(1, 3);
  tri.F << 0, 1, 2;
  EXPECT_NEAR(against(tri, Eigen::Vector3d::Zero(), r).face_penetration, r - h, 1e-15);
  EXPECT_EQ(against(tri, Eigen::Vector3d::Zero(), h * (1 - 1e-12)).face_penetration, 0);
}

TEST(SphereAgainstSurface, TheTorusHoleAndTheLBlockCornerAreOutside) {
  // The torus stands in the x-z plane, its hole of radius 0.02 m around (0, 0, 0.05)
  // along y (shapes.h): the hole's centre is outside, the tube's centre inside.
  const SurfaceMesh torus = make_shape_surface({"torus", 20});
  const Eigen::Vector3d hole(0, 0, 0.05);
  EXPECT_NEAR(against(torus, hole, 0.01).winding_number, 0, 1e-9);
  EXPECT_NEAR(against(torus, {0, 0.01, 0.05}, 0.01).winding_number, 0, 1e-9);
  EXPECT_NEAR(against(torus, {0.035, 0, 0.05}, 0.01).winding_number, 1, 1e-9);
  EXPECT_NEAR(against(torus, {0, 0, 0.05 - 0.035}, 0.01).winding_number, 1, 1e-9);
  // The hole's rim vertices lie on the circle of radius 0.02; its faces' chords come
  // at most 0.02 (1 - cos(pi / n)) closer, n >= 40 segments around the hole.
  const double sag = 0.02 * (1 - std::cos(M_PI / 40));
  EXPECT_EQ(against(torus, hole, 0.02 - sag - 1e-9).face_penetration, 0);
  const double p = against(torus, hole, 0.021).face_penetration;
  EXPECT_GE(p, 0.001 - 1e-12);
  EXPECT_LE(p, 0.001 + sag);

  // The L-block: a column x in [-0.05, -0.01] to z = 0.1 on a base z in [0, 0.04];
  // (-0.01, y, 0.04) its concave edge. Points a tenth of a millimetre off it.
  const SurfaceMesh l_block = make_shape_surface({"l_block", 15});
  EXPECT_NEAR(against(l_block, {-0.0099, 0, 0.0401}, 0.01).winding_number, 0, 1e-6);
  EXPECT_NEAR(against(l_block, {-0.0101, 0, 0.0399}, 0.01).winding_number, 1, 1e-6);
  EXPECT_NEAR(against(l_block, {0.02, 0, 0.07}, 0.01).winding_number, 0, 1e-9);
  // A sphere in the corner, 0.01 m from both faces: each face 2 mm inside r = 0.012.
  EXPECT_NEAR(against(l_block, {0, 0, 0.05}, 0.012).face_penetration, 0.002, 1e-12);
}

TEST(SegmentMeetsSurface, ThroughTheCubeAndTheTorusHole) {
  const SurfaceMesh cube = unit_cube();
  auto meets = [](const SurfaceMesh& s, const Eigen::Vector3d& p, const Eigen::Vector3d& q) {
    return segment_meets_surface(s.V, s.F, p, q);
  };
  EXPECT_TRUE(meets(cube, {2, 0.5, 0.5}, {-1, 0.5, 0.5}));     // through two faces
  EXPECT_TRUE(meets(cube, {0.5, 0.5, 0.5}, {0.5, 0.5, 3}));    // from inside out
  EXPECT_TRUE(meets(cube, {0.3, 0.6, 2}, {0.3, 0.6, 0.999}));  // ends just inside
  EXPECT_FALSE(meets(cube, {0.3, 0.6, 2}, {0.3, 0.6, 1.001}));
  EXPECT_FALSE(meets(cube, {2, 0.5, 0.5}, {1.5, 0.5, 0.5}));
  EXPECT_FALSE(meets(cube, {-1, 0.5, 1.2}, {2, 0.5, 1.2}));     // above the top, parallel to it
  EXPECT_FALSE(meets(cube, {0.2, 0.3, 0.4}, {0.8, 0.7, 0.6}));  // inside throughout
  // Through the torus's hole along its axis (y): no triangle; through its tube: some.
  const SurfaceMesh torus = make_shape_surface({"torus", 20});
  EXPECT_FALSE(meets(torus, {0, -0.1, 0.05}, {0, 0.1, 0.05}));
  EXPECT_TRUE(meets(torus, {0.035, -0.1, 0.05}, {0.035, 0.1, 0.05}));
  // Across the L-block's concave corner, outside it, and through the column.
  const SurfaceMesh l_block = make_shape_surface({"l_block", 15});
  EXPECT_FALSE(meets(l_block, {-0.009, 0, 0.1}, {0.05, 0, 0.041}));
  EXPECT_TRUE(meets(l_block, {-0.06, 0, 0.07}, {0, 0, 0.07}));
}

std::string read(const std::filesystem::path& p) {
  std::ifstream in(p);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

class SphereGuardRuns : public Scenarios {
 protected:
  RunOptions options() const {
    RunOptions o;
    o.out_dir = (dir / "out").string();
    o.progress = false;
    o.mesh_cache_dir = "";
    return o;
  }
  /// small_cube() (0.1 m, its bottom clamped) with one sphere on `path` ([frame, x, y, z]
  /// rows), run by the linear fem and by pbd.
  static nlohmann::json sphere_scenario(double radius, const nlohmann::json& path) {
    nlohmann::json j = small_cube();
    j.erase("load");
    j["tools"] = {{{"type", "sphere"}, {"radius", radius}, {"path", path}}};
    j["models"] = {{{"name", "fem-direct"}, {"model", "fem"}}, {{"model", "pbd"}}};
    return j;
  }
};

TEST_F(SphereGuardRuns, ASphereJumpedThroughTheTopInOneFrameStopsEachCaseWithOneLine) {
  // Radius 2 cm, 1 mm above the top face at frame 0, its centre 3 cm below the top at
  // frame 1: the top nodes are 3 cm from it, outside it, so no model sees a contact.
  // It is the second tool: a sphere resting clear of the +x face is the first.
  nlohmann::json j = sphere_scenario(0.02, {{0, 0, 0, 0.121}, {1, 0, 0, 0.07}});
  j["tools"].insert(j["tools"].begin(),
                    nlohmann::json{{"type", "sphere"}, {"radius", 0.01}, {"path", {{0, 0.065, 0, 0.05}}}});
  const auto outcomes = run_experiment(load_experiment(write("jump.json", j)), options());
  ASSERT_EQ(outcomes.size(), 2u);
  for (const CaseOutcome& c : outcomes) {
    EXPECT_FALSE(c.ok) << c.case_name;
    EXPECT_EQ(c.error.rfind("tools[1] (sphere) tunnelled through the surface at frame 1: its centre (0, 0, 0.07) is "
                            "inside the deformed body",
                            0),
              0u)
        << c.case_name << ": " << c.error;
    EXPECT_NE(c.error.find("it moved 0.051 m since the previous frame against its radius 0.02 m"), std::string::npos)
        << c.error;
    EXPECT_NE(c.error.find(", its centre 0.03 m below the undeformed surface: ramp it"), std::string::npos) << c.error;
    EXPECT_EQ(c.error.find('\n'), std::string::npos);
    // No half result: the case's folder absent, its failure beside it.
    const auto scenario = dir / "out" / "small" / "small";
    EXPECT_FALSE(std::filesystem::exists(scenario / c.case_name)) << c.case_name;
    EXPECT_NE(read(scenario / (c.case_name + ".failed.json")).find("tunnelled"), std::string::npos);
  }
}

// The palpation's sphere (radius 12.7 mm) ramped 1 mm a frame until its centre is
// 2.1 mm below the undeformed top of the coarse cube (nodes 25 mm apart): the linear
// fem solves each frame from the rest state, so the top nodes above the centre are
// pushed up around the sphere as soon as it dips below the top, and pbd's nodes let
// it slip between them once held there. Not the move but the depth: the guard says so.
TEST_F(SphereGuardRuns, ASphereBelowTheUndeformedSurfaceAfterShortMovesIsTooDeep) {
  const nlohmann::json path = {{0, 0, 0, 0.1129}, {15, 0, 0, 0.0979}};
  const auto outcomes = run_experiment(load_experiment(write("deep.json", sphere_scenario(0.0127, path))), options());
  ASSERT_EQ(outcomes.size(), 2u);
  for (const CaseOutcome& c : outcomes) {
    ASSERT_FALSE(c.ok) << c.case_name;
    EXPECT_EQ(c.error.rfind("tools[0] (sphere) tunnelled through the surface at frame ", 0), 0u) << c.error;
    EXPECT_NE(c.error.find(" m below the undeformed surface: press it less deep or refine the surface"),
              std::string::npos)
        << c.error;
    EXPECT_EQ(c.error.find("ramp it"), std::string::npos) << c.error;
  }
  // The linear fem as soon as the centre is below the top (0.0999 at frame 13).
  EXPECT_NE(outcomes[0].error.find("at frame 13: its centre (0, 0, 0.0999)"), std::string::npos) << outcomes[0].error;
}

// A sphere that crosses the whole body within one frame and ends outside it: its
// centre 1 mm clear of the cube's +x face, then past its -x face. No frame ends with
// the centre inside; the path of the frame crosses the body before and after it.
TEST_F(SphereGuardRuns, ASphereCrossingTheWholeBodyWithinOneFrameStopsTheCase) {
  nlohmann::json j = sphere_scenario(0.02, {{0, 0.071, 0, 0.05}, {1, -0.071, 0, 0.05}});
  const auto outcomes = run_experiment(load_experiment(write("through.json", j)), options());
  ASSERT_EQ(outcomes.size(), 2u);
  for (const CaseOutcome& c : outcomes) {
    EXPECT_FALSE(c.ok) << c.case_name;
    EXPECT_EQ(c.error.rfind("tools[0] (sphere) passed through the body within frame 1: the path of its centre from "
                            "(0.071, 0, 0.05) to (-0.071, 0, 0.05) crosses the deformed surface",
                            0),
              0u)
        << c.case_name << ": " << c.error;
    EXPECT_NE(c.error.find("it moved 0.142 m since the previous frame against its radius 0.02 m"), std::string::npos)
        << c.error;
    EXPECT_EQ(c.error.find('\n'), std::string::npos);
  }
}

// Long moves that do not cross the body pass: the sphere brought from 8 cm above the
// top onto it, 8 mm deep, in one frame, held, and lifted away in one frame (the swept
// test runs: each move is longer than the centre's distance to the surface).
TEST_F(SphereGuardRuns, LongMovesOntoTheBodyAndAwayFromItPass) {
  const nlohmann::json path = {{0, 0, 0, 0.2}, {1, 0, 0, 0.122}, {3, 0, 0, 0.122}, {4, 0, 0, 0.2}};
  const auto outcomes = run_experiment(load_experiment(write("long.json", sphere_scenario(0.03, path))), options());
  ASSERT_EQ(outcomes.size(), 2u);
  for (const CaseOutcome& c : outcomes) {
    ASSERT_TRUE(c.ok) << c.case_name << ": " << c.error;
    const nlohmann::json run = nlohmann::json::parse(read(dir / "out" / "small" / "small" / c.case_name / "run.json"));
    const nlohmann::json faces = run["observables"]["contact"]["faces"]["tools"]["tools[0]"];
    EXPECT_NEAR(faces["largest_move_per_frame_m"].get<double>(), 0.078, 1e-12);
    EXPECT_GT(faces["max_face_penetration_m"].get<double>(), 0);  // it did press
  }
}

TEST_F(SphereGuardRuns, ANormalPressPassesAndRecordsItsFacesSmallPenetration) {
  // Radius 3 cm touching the top at frame 0, pressed 8 mm in by frame 2 and held.
  const nlohmann::json path = {{0, 0, 0, 0.13}, {2, 0, 0, 0.122}, {4, 0, 0, 0.122}};
  const Experiment e = load_experiment(write("press.json", sphere_scenario(0.03, path)));
  const auto outcomes = run_experiment(e, options());
  ASSERT_EQ(outcomes.size(), 2u);
  MeshReport report;
  const HybridMesh mesh = build_mesh(e.scenarios[0].mesh, report);
  const Eigen::Vector3d centre(0, 0, 0.122);
  for (const CaseOutcome& c : outcomes) {
    ASSERT_TRUE(c.ok) << c.case_name << ": " << c.error;
    const auto folder = dir / "out" / "small" / "small" / c.case_name;
    const nlohmann::json run = nlohmann::json::parse(read(folder / "run.json"));
    const nlohmann::json faces = run["observables"]["contact"]["faces"]["tools"]["tools[0]"];
    const double face = faces["max_face_penetration_m"];
    // The deepest surface node (contact.csv's last column), over the frames.
    std::istringstream csv(read(folder / "contact.csv"));
    std::string line;
    std::getline(csv, line);
    double node = 0;
    while (std::getline(csv, line)) node = std::max(node, std::stod(line.substr(line.rfind(',') + 1)));
    // The faces reach deeper than the nodes, by less than the chord bound
    // r - sqrt((r - node)^2 - R^2) of the largest deformed triangle's circumradius R
    // (the last frame's surface: the sphere is held from frame 2).
    Points u(mesh.fine_surface.V.rows(), 3);
    std::istringstream surface(read(folder / "surface.csv"));
    std::getline(surface, line);
    for (Eigen::Index v = 0; v < u.rows(); ++v) {
      std::getline(surface, line);
      std::vector<double> values;
      std::istringstream row(line);
      for (std::string cell; std::getline(row, cell, ',');) values.push_back(std::stod(cell));
      u.row(v) << values[4], values[5], values[6];
    }
    const Points deformed = mesh.fine_surface.V + u;
    double circumradius = 0;
    for (Eigen::Index t = 0; t < mesh.fine_surface.F.rows(); ++t) {
      const Eigen::Vector3d a = deformed.row(mesh.fine_surface.F(t, 0)), b = deformed.row(mesh.fine_surface.F(t, 1)),
                            d = deformed.row(mesh.fine_surface.F(t, 2));
      circumradius =
          std::max(circumradius, (b - a).norm() * (d - a).norm() * (d - b).norm() / (2 * (b - a).cross(d - a).norm()));
    }
    const double r = 0.03, bound = r - std::sqrt((r - node) * (r - node) - circumradius * circumradius);
    EXPECT_NEAR(faces["largest_move_per_frame_m"].get<double>(), 0.004, 1e-12);  // 8 mm over 2 frames
    EXPECT_GT(face, 0) << c.case_name;
    EXPECT_GE(face, node) << c.case_name;
    EXPECT_LE(face, bound) << c.case_name << ": circumradius " << circumradius;
    // fem: static, so its last frame is the frame of the maximum; the number is
    // the one recomputed from what it wrote.
    if (c.case_name == "fem-direct") {
      EXPECT_NEAR(face, sphere_against_surface(deformed, mesh.fine_surface.F, centre, r).face_penetration, 1e-9);
    }
    std::cout << c.case_name << ": face penetration " << face << " m, nodes " << node << " m, chord bound " << bound
              << " m\n";
  }
}

TEST_F(SphereGuardRuns, ASpherePressedIntoTheLBlocksConcaveCornerPasses) {
  // The L-block's concave edge at x = -0.01, z = 0.04: a sphere of radius 1 cm from
  // 0.5 mm off both faces to 2 mm into both, over 4 frames.
  nlohmann::json j = sphere_scenario(0.01, {{0, 0.0005, 0, 0.0505}, {4, -0.002, 0, 0.048}});
  j["mesh"] = {{"type", "shape"},
               {"shape", "l_block"},
               {"resolution", 8},
               {"fine_tetgen", {{"max_volume", 1e-5}}},
               {"coarse_selection", {{"target_nodes", 30}}}};
  j["support"] = {{"lowest_fraction", 0.2}};
  const auto outcomes = run_experiment(load_experiment(write("corner.json", j)), options());
  ASSERT_EQ(outcomes.size(), 2u);
  for (const CaseOutcome& c : outcomes) {
    ASSERT_TRUE(c.ok) << c.case_name << ": " << c.error;
    const nlohmann::json run = nlohmann::json::parse(read(dir / "out" / "small" / "small" / c.case_name / "run.json"));
    const double face = run["observables"]["contact"]["faces"]["tools"]["tools[0]"]["max_face_penetration_m"];
    EXPECT_LT(face, 0.01) << c.case_name;  // the centre stayed outside
    std::cout << c.case_name << ": face penetration in the corner " << face << " m\n";
  }
}

}  // namespace
}  // namespace tb
