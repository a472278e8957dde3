// A grasp through compliant pads (ToolKind::CompliantGrasp): each held vertex tied
// to the jaw by a spring k_i = kappa x its vertex area. Against closed forms (a
// column under pads: the pads and the column in series), against the rigid grasp
// (stiff pads approach it, the gap shrinking with 1 / kappa), between solvers (the
// static Newton answer equals VBD's and PD's settled states under the same pads),
// on shapes other than the cube (a torus, an L-block: the weight carried, the
// steppers at rest on Newton's answer), and the refusals (solvers and models
// without springs).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "load_mapping.h"
#include "model.h"
#include "pd_solve.h"
#include "models/realtime/settled_cube.h"
#include "test_support.h"
#include "tool_placement.h"
#include "vbd_solve.h"
#include "xpbd_tet_solve.h"

namespace tb {
namespace {

/// Per node, a third of the area of its boundary faces on the plane z = top (the
/// vertex areas ContactArea gives on a surface mesh).
Eigen::VectorXd top_vertex_areas(const TetMesh& m, double top) {
  Eigen::VectorXd area = Eigen::VectorXd::Zero(m.V.rows());
  static const int faces[4][3] = {{1, 2, 3}, {0, 2, 3}, {0, 1, 3}, {0, 1, 2}};
  for (Eigen::Index t = 0; t < m.T.rows(); ++t)
    for (const auto& f : faces) {
      bool on_top = true;
      for (int k : f) on_top = on_top && std::abs(m.V(m.T(t, k), 2) - top) < 1e-12;
      if (!on_top) continue;
      const Eigen::Vector3d a = m.V.row(m.T(t, f[0])), b = m.V.row(m.T(t, f[1])), c = m.V.row(m.T(t, f[2]));
      for (int k : f) area(m.T(t, k)) += (b - a).cross(c - a).norm() / 6;
    }
  return area;
}

/// A body with pads on its top face: springs kappa x vertex area and the load that
/// pulls them (weights k_i, value the jaw's displacement d).
struct PaddedColumn {
  TetMesh mesh;
  std::vector<NodeSpring> springs;
  NodalWeights pull;
  double top = 0;

  PaddedColumn(TetMesh m, double kappa) : mesh(std::move(m)) {
    top = mesh.V.col(2).maxCoeff();
    const Eigen::VectorXd area = top_vertex_areas(mesh, top);
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v)
      if (area(v) > 0) springs.push_back({static_cast<int>(v), kappa * area(v)});
    pull.nodes.resize(static_cast<Eigen::Index>(springs.size()));
    pull.weights.resize(pull.nodes.size());
    for (size_t i = 0; i < springs.size(); ++i) {
      pull.nodes(static_cast<Eigen::Index>(i)) = springs[i].node;
      pull.weights(static_cast<Eigen::Index>(i)) = springs[i].stiffness;
    }
  }
  std::vector<char> clamped_bottom() const {
    std::vector<char> c(static_cast<size_t>(mesh.V.rows()), 0);
    for (Eigen::Index v = 0; v < mesh.V.rows(); ++v) c[static_cast<size_t>(v)] = mesh.V(v, 2) < 1e-12;
    return c;
  }
  /// The force the body exerts on the jaw: sum k_i (u_i - d).
  Eigen::Vector3d jaw_force(const Eigen::VectorXd& u, const Eigen::Vector3d& d) const {
    Eigen::Vector3d r = Eigen::Vector3d::Zero();
    for (const NodeSpring& k : springs) r += k.stiffness * (u.segment<3>(3 * k.node) - d);
    return r;
  }
};

/// A column of length L and section A, clamped at its base, nu = 0, its top face
/// pulled up by pads of stiffness kappa: uniaxial stress E u / L = kappa (d - u) on
/// the top, so u = kappa d / (kappa + E / L) everywhere on it, and the field
/// u_z = u z / L is linear, which P1 tets reproduce exactly; the jaw feels
/// A kappa (u - d) = -A E u / L, the support the opposite. With kappa = E / L the
/// top moves half the jaw's lift.
TEST(CompliantGrasp, AColumnUnderPadsMovesAsThePadsAndTheColumnInSeries) {
  const double L = 0.05, a = 0.02;
  Material material;
  material.youngs_modulus = 3000;
  material.poisson_ratio = 0;
  const double kappa = material.youngs_modulus / L;
  const PaddedColumn column(testing::box_mesh(a, a, L, 3, 3, 6, 2e-7), kappa);
  const ElasticBody body(column.mesh, material, column.clamped_bottom(), {}, column.springs);
  const BodyLoads loads(body, {column.pull});
  const Eigen::Vector3d d(0, 0, 1e-3);
  const double expected_top = kappa * d.z() / (kappa + material.youngs_modulus / L);
  ASSERT_NEAR(expected_top, d.z() / 2, 1e-15);
  const double expected_force = -a * a * material.youngs_modulus * expected_top / L;
  auto solve = make_direct_solve(body);
  ElasticFrame frame(body, loads, *solve);
  Eigen::VectorXd u;
  frame.step({d}, {}, u);
  double worst = 0;
  for (Eigen::Index v = 0; v < column.mesh.V.rows(); ++v) {
    const Eigen::Vector3d exact(0, 0, expected_top * column.mesh.V(v, 2) / L);
    worst = std::max(worst, (u.segment<3>(3 * v) - exact).norm());
  }
  EXPECT_LT(worst, 1e-12 * expected_top) << worst;
  const Eigen::Vector3d jaw = column.jaw_force(u, d);
  EXPECT_NEAR(jaw.z(), expected_force, 1e-10 * std::abs(expected_force));
  EXPECT_LT(jaw.head<2>().norm(), 1e-10 * std::abs(expected_force));
  // No load but the pads': the support takes what the jaw gives.
  EXPECT_LT((frame.support_force() + jaw).norm(), 1e-10 * std::abs(expected_force));

  // The static Newton solve of neo-Hookean, its pads in f_int and the tangent, at a
  // lift of 1e-4 L: the linear answer to O(strain), 1e-4 relative. (At 1e-6 L the
  // cancellation in P = mu F - mu F^-T leaves round-off of 1e-10 of the stress, at
  // Newton's tolerance: it stalls.)
  const Eigen::Vector3d tiny = d * (1e-4 * L / d.z());
  auto newton = testing::make_solve(body, {{"solver", "newton"}});
  ElasticFrame newton_frame(body, loads, *newton);
  Eigen::VectorXd u_newton;
  newton_frame.step({tiny}, {}, u_newton);
  const double scale = tiny.z() / d.z();
  const double departure = (u_newton - scale * u).norm() / (scale * u.norm());
  EXPECT_LT(departure, 1e-3) << departure;
  RecordProperty("newton_departure_at_1e-4_strain", ::testing::PrintToString(departure));
  EXPECT_NEAR(column.jaw_force(u_newton, tiny).z(), scale * expected_force, 1e-3 * scale * std::abs(expected_force));
}

/// The paper cube's top centre grasped (radius 11 mm) and lifted 5 mm, rigidly and
/// through pads ever stiffer, in the fem model (linear, direct): the pads' answer
/// approaches the rigid one, the gap shrinking about tenfold per tenfold kappa
/// (their compliance 1 / kappa in series with the tissue's), and the jaw's force
/// with it.
TEST(CompliantGrasp, StiffPadsApproachTheRigidGrasp) {
  const HybridMesh& cube = testing::scenario_mesh("cube-pull");
  const Eigen::Vector3d point(0, 0, 0.1), lift(0, 0, 0.005);
  const ModelInfo& info = find_model("fem");
  auto run = [&](const Tool& tool) {
    Problem p{&cube, Material{}, LoadCase{testing::kCubeBottom, {}, {tool}}, resolve_parameters(info.parameters, {}, "fem"),
              Points()};
    auto m = info.create();
    m->setup(p);
    m->step(FrameLoads{{}, {lift}});
    return std::make_pair(Displacements(m->surface_displacement()), Eigen::Vector3d((*m->reaction_forces())[0]));
  };
  const auto [rigid_u, rigid_force] = run(Tool::grasp(point, 0.011));
  ASSERT_LT(rigid_force.z(), 0) << "the tissue pulls the jaw down";
  std::vector<double> gaps, force_gaps;
  for (double kappa : {1e6, 1e7, 1e8}) {
    const auto [u, force] = run(Tool::compliant_grasp(point, 0.011, kappa));
    gaps.push_back((u - rigid_u).norm() / rigid_u.norm());
    force_gaps.push_back((force - rigid_force).norm() / rigid_force.norm());
    // Pads in series with the tissue: the same lift pulls less hard than the rigid grasp.
    EXPECT_LT(force.z(), 0) << kappa;
    EXPECT_GT(force.z(), rigid_force.z()) << kappa;
  }
  RecordProperty("field_gaps", ::testing::PrintToString(gaps));
  RecordProperty("force_gaps", ::testing::PrintToString(force_gaps));
  for (size_t k = 1; k < gaps.size(); ++k) {
    EXPECT_GT(gaps[k - 1] / gaps[k], 5) << k;  // about 10 once the pads are stiff against the tissue
    EXPECT_GT(force_gaps[k - 1] / force_gaps[k], 5) << k;
  }
  EXPECT_LT(gaps.back(), 0.01);
}

/// The small clamped cube's top face under pads lifted 6 mm (15 % of its height):
/// VBD and PD run until they stop moving equal the static Newton answer of their law
/// on the same body, and the jaw's force with it (the pads in VBD's 3x3 blocks, in
/// PD's global matrix, in Newton's f_int and tangent: three implementations).
TEST(CompliantGrasp, VbdAndPdSettleToTheStaticNewtonAnswerUnderPads) {
  const testing::SmallCube c;
  const PaddedColumn pads(c.mesh, testing::kMaterial.youngs_modulus / 0.002);
  const ElasticBody body(c.mesh, testing::kMaterial, c.clamped(), {}, pads.springs);
  const BodyLoads loads(body, {pads.pull});
  const Eigen::Vector3d lift(0, 0, 0.15 * c.a);
  const Eigen::VectorXd expected = testing::newton_answer(body, loads, "neo_hookean", {lift}, {});
  const Eigen::Vector3d expected_force = pads.jaw_force(expected, lift);
  ASSERT_LT(expected_force.z(), 0);
  // The pads are neither rigid nor slack here: the top lags the jaw by a few per cent.
  const double lag = lift.z() - expected(3 * pads.springs[0].node + 2);
  EXPECT_GT(lag, 0.01 * lift.z());
  EXPECT_LT(lag, 0.5 * lift.z());

  VbdSettings vbd;
  vbd.stepping.time_step = 0.5;
  vbd.iterations = 50;
  PdSettings pd;
  pd.stepping.time_step = 0.5;
  for (const std::string name : {"vbd", "pd"}) {
    auto stepper = name == "vbd" ? make_vbd_solve(body, vbd) : make_pd_solve(body, pd);
    ASSERT_TRUE(stepper->takes_springs()) << name;
    ElasticFrame frame(body, loads, *stepper);
    Eigen::VectorXd u;
    for (int f = 1; f <= 10; ++f) frame.step({lift * (f / 10.0)}, {}, u);
    const int frames = testing::settle(frame, {lift}, {}, u, 2000);
    EXPECT_LE(frames, 2000) << name;
    const double error = (u - expected).norm() / expected.norm();
    const double force_error = (pads.jaw_force(u, lift) - expected_force).norm() / expected_force.norm();
    EXPECT_LT(error, 1e-6) << name << " frames " << frames;
    EXPECT_LT(force_error, 1e-6) << name;
    // Settled, the report's static residual counts the pads' k u: zero at equilibrium.
    EXPECT_LT(stepper->report()["static_residual"].get<double>(), 1e-6) << name;
    RecordProperty(name + "_frames", frames);
    RecordProperty(name + "_relative_error", ::testing::PrintToString(error));
  }
}

/// Every model that takes pads, the paper cube's top lifted through them beside a
/// bonded plate pushing a side, under a point force and gravity: once settled the
/// jaw's, the plate's and the support's forces sum to the applied loads (the
/// springs' pull is internal to the tissue and jaw), and the jaw is pulled down.
TEST(CompliantGrasp, TheJawsForceBalancesTheLoadsInEveryModelThatTakesIt) {
  const HybridMesh& cube = testing::scenario_mesh("cube-pull");
  const std::vector<Tool> tools = {Tool::compliant_grasp({-0.02, 0.01, 0.1}, 0.012, 1e6, "tools[0]"),
                                   Tool::plate({{-1, 0.0499, 0.03}, {1, 1, 0.07}}, false, 2, "tools[1]")};
  const std::vector<Load> loads = {Load::point_force({0.02, 0, 0.1}, "loads[0]"), Load::body_force("loads[1]")};
  const FrameLoads frame{{{0, 0, 0.2}, {0, 0, -9.81}}, {{0, 0, 0.004}, {0, -0.002, 0}}};
  const double mass = nodal_masses(cube.fine_volume, Material{}.density).weights.sum();
  const Eigen::Vector3d applied = frame.values[0] + mass * frame.values[1];
  int measured = 0;
  for (const auto& [model, given] : std::vector<std::pair<std::string, nlohmann::json>>{
           {"fem", {{"solver", "direct"}}},
           {"fem", {{"solver", "iterative"}, {"cg_tolerance", 1e-12}}},
           {"fem", {{"solver", "newton"}}},
           {"fem_dynamic", {{"time_step", 0.5}}},
           {"pd", {{"time_step", 0.5}}}}) {
    const ModelInfo& info = find_model(model);
    ASSERT_TRUE(info.takes(ToolKind::CompliantGrasp)) << model;
    Problem p{&cube, Material{}, LoadCase{testing::kCubeBottom, loads, tools},
              resolve_parameters(info.parameters, given, model), Points()};
    auto m = info.create();
    m->setup(p);
    testing::step_until_reactions_settle(*m, frame, info.dynamic ? 300 : 0);
    const std::vector<Eigen::Vector3d>& r = *m->reaction_forces();
    const Eigen::Vector3d sum = r[0] + r[1] + r[2];
    EXPECT_LT((sum - applied).norm(), 1e-8 * (r[0].norm() + r[1].norm() + r[2].norm())) << model << " " << given;
    EXPECT_LT(r[0].z(), 0) << model;
    ++measured;
  }
  EXPECT_EQ(measured, 5);
}

/// Pads hold each vertex by kappa times its vertex area: uniform across the disc, or
/// smooth, times (1 - (r / R)^2)^2, falling to zero at the rim (a vertex on it held
/// by none). On the paper cube's flat top the smooth pads' summed stiffness is about
/// a third of the uniform pads' (the profile's mean over a disc is 1 / 3).
TEST(CompliantGrasp, SmoothPadsFallToZeroAtTheRim) {
  const HybridMesh& cube = testing::scenario_mesh("cube-pull");
  const Eigen::Vector3d point(0, 0, 0.1);
  const double R = 0.02, kappa = 1e6;
  const Tool uniform = Tool::compliant_grasp(point, R, kappa);
  const Tool smooth = Tool::compliant_grasp(point, R, kappa, "tools[0]", true);
  const std::vector<int> held = tool_vertices(uniform, cube.fine_surface, testing::kCubeBottom);
  const std::vector<NodeSpring> flat = pad_springs(uniform, held, cube.fine_surface, cube.fine_surface_to_volume);
  const std::vector<NodeSpring> tapered = pad_springs(smooth, held, cube.fine_surface, cube.fine_surface_to_volume);
  ASSERT_EQ(flat.size(), held.size());
  const ContactArea area(cube.fine_surface);
  double flat_sum = 0, tapered_sum = 0;
  size_t k = 0;
  for (size_t i = 0; i < held.size(); ++i) {
    const int v = held[i];
    EXPECT_NEAR(flat[i].stiffness, kappa * area.area({v}), 1e-12 * flat[i].stiffness);
    flat_sum += flat[i].stiffness;
    const double r2 = (cube.fine_surface.V.row(v).transpose() - point).squaredNorm() / (R * R);
    if (r2 >= 1) continue;  // on the rim: left out
    ASSERT_LT(k, tapered.size());
    EXPECT_EQ(tapered[k].node, flat[i].node);
    EXPECT_NEAR(tapered[k].stiffness, flat[i].stiffness * (1 - r2) * (1 - r2), 1e-12 * flat[i].stiffness);
    tapered_sum += tapered[k++].stiffness;
  }
  EXPECT_EQ(k, tapered.size());
  RecordProperty("smooth_over_uniform", ::testing::PrintToString(tapered_sum / flat_sum));
  EXPECT_NEAR(tapered_sum / flat_sum, 1.0 / 3, 0.1);
}

/// Smooth pads on shapes the pads were not written for: a torus (a hole, a curved
/// top) and an L-block (a re-entrant corner), their bottom tenth clamped, the pads
/// at their highest vertex lifted 5 mm under gravity. Once settled, in every model
/// that takes pads: the jaw's and the support's forces carry the weight; the
/// nonlinear ones (implicit-Euler FEM, PD and VBD at rest) equal static Newton's
/// field of the same law to 1e-6, the linear FEM's differs from it; every model's
/// pads lag the jaw.
TEST(CompliantGrasp, SmoothPadsOnATorusAndAnLBlockCarryTheirWeightInEveryModelThatTakesThem) {
  for (const std::string shape : {"torus", "l_block"}) {
    const HybridMesh& mesh = testing::shape_mesh(shape);
    const Points& V = mesh.fine_surface.V;
    const double zmin = V.col(2).minCoeff(), zmax = V.col(2).maxCoeff();
    const SupportBox support{{-1, -1, -1}, {1, 1, zmin + 0.1 * (zmax - zmin)}};
    Eigen::Index top = 0;
    V.col(2).maxCoeff(&top);
    const std::vector<Tool> tools = {Tool::compliant_grasp(V.row(top).transpose(), 0.005, 3e6, "tools[0]", true)};
    const double lift = 0.005;
    const FrameLoads frame{{Eigen::Vector3d(0, 0, -9.81)}, {Eigen::Vector3d(0, 0, lift)}};
    const Eigen::Vector3d weight(0, 0, -9.81 * nodal_masses(mesh.fine_volume, Material{}.density).weights.sum());
    Displacements newton;
    int measured = 0;
    for (const auto& [model, given] : std::vector<std::pair<std::string, nlohmann::json>>{
             {"fem", {{"solver", "newton"}}},  // first: the others compare with it
             {"fem", {{"solver", "direct"}}},
             {"fem_dynamic", {{"time_step", 0.5}}},
             {"pd", {{"time_step", 0.5}}},
             {"vbd", {{"time_step", 0.5}, {"iterations", 50}, {"start", "previous"}}}}) {
      const ModelInfo& info = find_model(model);
      ASSERT_TRUE(info.takes(ToolKind::CompliantGrasp)) << model;
      Problem p{&mesh, Material{}, LoadCase{support, {Load::body_force()}, tools},
                resolve_parameters(info.parameters, given, model), Points()};
      auto m = info.create();
      m->setup(p);
      for (int f = 1; f < 10; ++f)  // the lift and gravity ramped over ten frames
        m->step(FrameLoads{{frame.values[0] * (f / 10.0)}, {frame.tool_values[0] * (f / 10.0)}});
      testing::step_until_reactions_settle(*m, frame, info.dynamic ? 3000 : 0);
      const std::string what = shape + " " + model + " " + given.dump();
      const Displacements& u = m->surface_displacement();
      ASSERT_TRUE(u.allFinite()) << what;
      const std::vector<Eigen::Vector3d>& r = *m->reaction_forces();
      EXPECT_LT((r[0] + r[1] - weight).norm(), 1e-6 * weight.norm()) << what;
      EXPECT_LT(r[0].z(), 0) << what;  // the tissue hangs on the jaw
      EXPECT_LT(u(top, 2), lift) << what;  // the pads lag the jaw
      if (model == "fem" && given["solver"] == "newton") {
        newton = u;
      } else if (model != "fem") {
        EXPECT_LT((u - newton).norm(), 1e-6 * newton.norm()) << what;
      } else {
        EXPECT_GT((u - newton).norm(), 1e-3 * newton.norm()) << what;  // linear: another answer
      }
      ++measured;
    }
    EXPECT_EQ(measured, 5) << shape;
  }
}

/// Solvers and models that cannot hold pads say so in one line naming the tool,
/// before setup (check_supported with the case's parameters), and setup says the
/// same to a caller that skips that check.
TEST(CompliantGrasp, SolversAndModelsWithoutSpringsRefuseIt) {
  const HybridMesh& cube = testing::scenario_mesh("cube-pull");
  const Tool pads = Tool::compliant_grasp({0, 0, 0.1}, 0.011, 1e6, "tools[0]");
  const LoadCase load_case{testing::kCubeBottom, {}, {pads}};
  auto setup_error = [&](const std::string& model, const nlohmann::json& given) {
    const ModelInfo& info = find_model(model);
    const Parameters parameters = resolve_parameters(info.parameters, given, model);
    std::string before_setup = "accepted";
    try {
      check_supported(info, parameters, load_case);
    } catch (const std::invalid_argument& e) {
      before_setup = e.what();
    }
    if (before_setup.rfind("model '", 0) == 0) return before_setup;  // its kinds: setup would not be reached
    try {
      info.create()->setup(Problem{&cube, Material{}, load_case, parameters, Points()});
    } catch (const std::invalid_argument& e) {
      EXPECT_EQ(e.what(), before_setup) << model;
      return std::string(e.what());
    }
    EXPECT_EQ(before_setup, "accepted") << model;
    return std::string("accepted");
  };
  EXPECT_EQ(setup_error("fem", {{"solver", "direct"}}), "accepted");
  EXPECT_EQ(setup_error("fem", {{"solver", "newton"}}), "accepted");
  EXPECT_EQ(setup_error("vbd", nlohmann::json::object()), "accepted");
  EXPECT_EQ(setup_error("pd", nlohmann::json::object()), "accepted");
  std::string e = setup_error("fem", {{"solver", "corotational"}});
  EXPECT_EQ(e,
            "fem: tools[0] (compliant_grasp): the corotational solver has no springs for its pads; use solver direct, "
            "iterative or newton");
  // XPBD's ModelInfo lists no compliant grasp: refused before setup (check_supported).
  e = setup_error("xpbd_neo", nlohmann::json::object());
  EXPECT_EQ(e.rfind("model 'xpbd_neo' does not take compliant_grasp tools (tools[0])", 0), 0u) << e;
  e = setup_error("vbd", {{"volume", "coarse_embedded"}});
  EXPECT_NE(e.find("volume coarse_embedded has no pads"), std::string::npos) << e;
  for (const std::string model : {"embedded", "pbd", "hybrid", "condensed"}) {
    e = setup_error(model, nlohmann::json::object());
    EXPECT_EQ(e.rfind("model '" + model + "' does not take compliant_grasp tools (tools[0])", 0), 0u) << e;
  }
  // A pad stiffness that is not a positive number, and a disc that catches nothing.
  for (double kappa : {0.0, -1.0, std::nan("")}) {
    try {
      tool_vertices(Tool::compliant_grasp({0, 0, 0.1}, 0.011, kappa, "tools[3]"), cube.fine_surface,
                    testing::kCubeBottom);
      ADD_FAILURE() << kappa << " accepted";
    } catch (const std::invalid_argument& error) {
      EXPECT_EQ(std::string(error.what()).rfind("tools[3] (compliant_grasp): pad stiffness", 0), 0u) << error.what();
    }
  }
  EXPECT_THROW(tool_vertices(Tool::compliant_grasp({0, 0, 0.2}, 0.01, 1e6), cube.fine_surface, testing::kCubeBottom),
               std::invalid_argument);
}

}  // namespace
}  // namespace tb
