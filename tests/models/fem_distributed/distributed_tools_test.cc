// The distributed FEM's tools, reactions and probes (distributed_elasticity.h),
// run by CTest with one rank and with two (its main is distributed_elasticity_test.cc):
// a homogeneous uniaxial compression between sliding faces against its closed form
// (linear and neo-Hookean, P1 and P2, nu = 0.499), every tool kind through the
// model against the serial fem model on the same mesh, P2 neo-Hookean against the
// serial newton P1 under a plate as both meshes refine, gravity with a grasp
// against the serial newton solve, the probes against nodal values and an exact
// quadratic field, and the bad inputs. Every check is made on
// values that are the same on every rank.
#include <gtest/gtest.h>
#include <mpi.h>

#include <cmath>
#include <numeric>
#include <sstream>

#include "cube_generator.h"
#include "distributed_elasticity.h"
#include "lame_parameters.h"
#include "mesh_checks.h"
#include "model.h"
#include "mpi_session.h"
#include "test_support.h"
#include "tetgen_driver.h"
#include "tool_placement.h"

namespace tb {
namespace {

std::string numbers(const std::vector<double>& v) { return ::testing::PrintToString(v); }

/// A cube of side 0.1 m on z = 0 (make_cube_surface: centred in x and y), its
/// surface an n x n x n grid, TetGen's tets of at most max_volume; the surface
/// vertices are the volume's first nodes.
HybridMesh cube_mesh(int n, double max_volume) {
  HybridMesh h;
  h.fine_surface = make_cube_surface({0.1, 0.1, n, n, n});
  check_and_orient_surface("test cube", h.fine_surface);
  TetgenOptions o;
  o.max_volume = max_volume;
  h.fine_volume = tetrahedralize_surface(h.fine_surface, o, "test cube");
  h.fine_surface_to_volume.resize(static_cast<size_t>(h.fine_surface.V.rows()));
  std::iota(h.fine_surface_to_volume.begin(), h.fine_surface_to_volume.end(), 0);
  return h;
}

const HybridMesh& small_cube() {
  static const HybridMesh h = cube_mesh(6, 5e-7);
  return h;
}

/// The nodes of `m` with coordinate `axis` equal to `value` (to 1e-12).
std::vector<int> nodes_on_plane(const TetMesh& m, int axis, double value) {
  std::vector<int> nodes;
  for (Eigen::Index v = 0; v < m.V.rows(); ++v)
    if (std::abs(m.V(v, axis) - value) < 1e-12) nodes.push_back(static_cast<int>(v));
  return nodes;
}

PrescribedGroup sliding_group(std::vector<int> nodes, int axis) {
  PrescribedGroup g;
  g.nodes = std::move(nodes);
  for (int c = 0; c < 3; ++c) g.components[c] = c == axis;
  return g;
}

bool nowhere(const Eigen::Vector3d&) { return false; }

/// Lateral stretch a of the neo-Hookean law (neo_hookean.h) under uniaxial stress
/// with axial stretch c: P_xx = mu a + (lambda ln J - mu) / a = 0, J = a^2 c,
/// i.e. mu (a^2 - 1) + lambda ln(a^2 c) = 0, by Newton's method from a = 1.
double neo_hookean_lateral_stretch(double c, const LameParameters& l) {
  double a = 1;
  for (int it = 0; it < 100; ++it) {
    const double r = l.mu * (a * a - 1) + l.lambda * std::log(a * a * c);
    const double step = r / (2 * l.mu * a + 2 * l.lambda / a);
    a -= step;
    if (std::abs(step) < 1e-16 * a) break;
  }
  return a;
}

/// (a) The unit cube [0, 1]^3 (box_mesh) held by frictionless faces: x = 0, y = 0
/// and z = 0 each in their normal component at 0 (symmetry planes), z = 1 moved
/// down by 18.25 % (the Truth Cube's largest strain). The exact solution is
/// homogeneous, u = ((a - 1) x, (a - 1) y, (c - 1) z) with c = 0.8175 and a from
/// the law (linear: a - 1 = nu (1 - c); neo-Hookean: neo_hookean_lateral_stretch),
/// and lies in the P1 and P2 spaces, so both reproduce it on any mesh, locking or
/// not, at nu = 0.499. The plate's reaction is -P_zz times the unit area.
TEST(DistributedTools, UniaxialCompressionBetweenSlidingFacesIsExact) {
  const TetMesh m = testing::box_mesh(1, 1, 1, 3, 3, 3, 0.01);
  const Material material{15300, 0.499, 980};
  const LameParameters lame = lame_parameters(material);
  const double c = 1 - 0.1825;
  const std::vector<PrescribedGroup> groups = {
      sliding_group(nodes_on_plane(m, 0, 0), 0), sliding_group(nodes_on_plane(m, 1, 0), 1),
      sliding_group(nodes_on_plane(m, 2, 0), 2), sliding_group(nodes_on_plane(m, 2, 1), 2)};
  const std::vector<Eigen::Vector3d> values = {Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(),
                                               Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, c - 1)};
  std::vector<int> all(static_cast<size_t>(m.V.rows()));
  std::iota(all.begin(), all.end(), 0);
  std::vector<double> errors, force_errors;
  for (const std::string law : {"linear", "neo_hookean"}) {
    double a = 1 + material.poisson_ratio * (1 - c), P_zz = material.youngs_modulus * (c - 1);
    if (law != "linear") {
      a = neo_hookean_lateral_stretch(c, lame);
      P_zz = lame.mu * c + (lame.lambda * std::log(a * a * c) - lame.mu) / c;
    }
    Points exact(m.V.rows(), 3);
    exact << (a - 1) * m.V.col(0), (a - 1) * m.V.col(1), (c - 1) * m.V.col(2);
    for (int degree = 1; degree <= 2; ++degree) {
      DistributedSettings s;
      s.degree = degree;
      s.law = law;
      s.cg_tolerance = 1e-12;
      s.newton_tolerance = 1e-11;
      s.load_steps = 2;
      DistributedElasticity fem(m, material, nowhere, s, MPI_COMM_WORLD, {}, groups);
      fem.solve({}, Eigen::Vector3d::Zero(), values);
      const double error = (fem.node_displacements(all) - exact).norm() / exact.norm();
      const Eigen::Vector3d plate = fem.reactions()[3];
      const double force_error = std::abs(plate.z() + P_zz) / std::abs(P_zz);
      EXPECT_LT(error, 1e-10) << law << " P" << degree;  // measured 6e-16 to 3e-13
      EXPECT_LT(force_error, 1e-10) << law << " P" << degree << ": plate " << plate.transpose() << ", exact " << -P_zz;
      EXPECT_LT(plate.head<2>().norm(), 1e-9 * std::abs(P_zz)) << "a frictionless plate takes no tangential force";
      EXPECT_EQ(fem.reactions()[4].norm(), 0.0) << "no support";
      // The four faces' forces balance.
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (const Eigen::Vector3d& r : fem.reactions()) sum += r;
      EXPECT_LT(sum.norm(), 1e-8 * std::abs(P_zz)) << law << " P" << degree;
      errors.push_back(error);
      force_errors.push_back(force_error);
    }
  }
  RecordProperty("relative_errors_linear_p1_p2_neo_p1_p2", numbers(errors));
  RecordProperty("plate_force_relative_errors", numbers(force_errors));
}

/// (a) Every tool kind through the models' interface, the fem_distributed model
/// (linear, P1) against the serial fem model (direct solve) on the same mesh
/// (tool_placement.h holds the same nodes in both), with a point force inside:
/// the surface, the reactions and the probes agree to the CG tolerance (1e-14)
/// times the condition number (measured 1e-15 to 1e-14 relative, 1 and 2 ranks).
TEST(DistributedTools, EveryToolKindEqualsTheSerialFemModel) {
  const HybridMesh& h = small_cube();
  const std::vector<Tool> tools = {Tool::plate({{-1, -1, 0.1 - 1e-9}, {1, 1, 1}}, false, 2, "tools[0]"),
                                   Tool::plate({{-1, -1, 0.1 - 1e-9}, {1, 1, 1}}, true, 2, "tools[0]"),
                                   Tool::grasp({0.05, 0, 0.05}, 0.02, "tools[0]")};
  const std::vector<Eigen::Vector3d> moves = {{0.001, -0.002, -0.01}, {0.001, -0.002, -0.01}, {0.004, 0, 0.002}};
  Points probes(3, 3);
  probes << 0, 0, 0.05, 0.02, -0.01, 0.08, -0.03, 0.03, 0.02;
  const std::vector<Load> loads = {Load::point_force({0.01, 0.015, 0.05}, "loads[0]")};
  std::vector<double> differences;
  for (size_t k = 0; k < tools.size(); ++k) {
    const LoadCase c{testing::kCubeBottom, loads, {tools[k]}};
    const FrameLoads frame{{Eigen::Vector3d(0.05, 0, -0.1)}, {moves[k]}};
    Displacements u[2];
    Points probe_u[2];
    std::vector<Eigen::Vector3d> reactions[2];
    int index = 0;
    for (const auto& [name, parameters] : {std::pair<std::string, nlohmann::json>{"fem", {{"solver", "direct"}}},
                                           {"fem_distributed", {{"cg_tolerance", 1e-14}}}}) {
      const ModelInfo& info = find_model(name);
      EXPECT_NO_THROW(check_supported(info, c)) << name;
      Problem p{&h, Material{}, c, resolve_parameters(info.parameters, parameters, name), probes};
      auto model = info.create();
      model->setup(p);
      model->step(frame);
      u[index] = model->surface_displacement();
      probe_u[index] = *model->probe_displacements();
      reactions[index] = *model->reaction_forces();
      ++index;
    }
    const std::string kind = name(tools[k].kind);
    const double du = (u[1] - u[0]).norm() / u[0].norm();
    const double dp = (probe_u[1] - probe_u[0]).norm() / probe_u[0].norm();
    ASSERT_EQ(reactions[1].size(), 2u) << kind;
    double dr = 0;
    for (size_t r = 0; r < 2; ++r)
      dr = std::max(dr, (reactions[1][r] - reactions[0][r]).norm() / reactions[0][r].norm());
    EXPECT_LT(du, 1e-10) << kind;
    EXPECT_LT(dp, 1e-10) << kind;
    EXPECT_LT(dr, 1e-9) << kind;
    // The tool's vertices follow it exactly; the tissue pulls the tool back.
    for (int v : tool_vertices(tools[k], h.fine_surface, testing::kCubeBottom))
      for (int comp = 0; comp < 3; ++comp)
        if (tools[k].kind != ToolKind::SlidingPlate || comp == 2) {
          EXPECT_NEAR(u[1](v, comp), moves[k](comp), 1e-15) << kind;
        }
    EXPECT_LT(reactions[1][0].dot(moves[k]), 0) << kind;
    // Equilibrium: the tool's and the support's forces sum to the applied force.
    const Eigen::Vector3d sum = reactions[1][0] + reactions[1][1];
    EXPECT_LT((sum - frame.values[0]).norm(), 1e-9 * reactions[1][0].norm()) << kind;
    differences.insert(differences.end(), {du, dp, dr});
  }
  RecordProperty("surface_probe_reaction_differences", numbers(differences));
}

/// (b) The Truth Cube's load on a small cube: the bottom clamped, a bonded plate
/// pressing the top down 10 %, neo-Hookean at nu = 0.49. P2 (fem_distributed) and
/// P1 (the serial newton solve, models/numerics/elasticity/newton_solve.cc) on
/// the same meshes, refined three times: both converge to the continuum solution,
/// so their difference at interior probes and in the plate's force falls at every
/// refinement. Measured (surface grids 2, 4, 8): probes 0.38, 0.061, 0.033
/// (relative); the plate's force P1 60.2, 45.0, 27.8 N, P2 23.8, 22.2, 21.3 N: most
/// of the difference is P1's locking at nu = 0.49.
TEST(DistributedTools, P2NeoHookeanAndSerialNewtonP1ConvergeTogetherUnderAPlate) {
  const Material material{15300, 0.49, 980};
  const LoadCase c{testing::kCubeBottom, {}, {Tool::plate({{-1, -1, 0.1 - 1e-9}, {1, 1, 1}}, false, 2, "tools[0]")}};
  const FrameLoads frame{{}, {Eigen::Vector3d(0, 0, -0.01)}};
  Points probes(27, 3);
  for (int i = 0; i < 27; ++i) probes.row(i) << 0.025 * (i % 3 - 1), 0.025 * (i / 3 % 3 - 1), 0.025 * (i / 9 + 1);
  std::vector<double> probe_differences, force_differences, forces_p2, forces_p1;
  for (int n : {2, 4, 8}) {
    const HybridMesh h = cube_mesh(n, std::pow(0.1 / n, 3) / 4);
    Points probe_u[2];
    Eigen::Vector3d force[2];
    int index = 0;
    for (const auto& [name, parameters] :
         {std::pair<std::string, nlohmann::json>{
              "fem", {{"solver", "newton"}, {"material_law", "neo_hookean"}, {"newton_load_steps", 2}}},
          {"fem_distributed", {{"degree", 2}, {"material_law", "neo_hookean"}, {"load_steps", 2}}}}) {
      const ModelInfo& info = find_model(name);
      Problem p{&h, material, c, resolve_parameters(info.parameters, parameters, name), probes};
      auto model = info.create();
      model->setup(p);
      model->step(frame);
      probe_u[index] = *model->probe_displacements();
      force[index] = (*model->reaction_forces())[0];
      ++index;
    }
    probe_differences.push_back((probe_u[1] - probe_u[0]).norm() / probe_u[1].norm());
    force_differences.push_back(std::abs(force[1].z() - force[0].z()) / force[1].z());
    forces_p1.push_back(force[0].z());
    forces_p2.push_back(force[1].z());
  }
  RecordProperty("probe_relative_differences", numbers(probe_differences));
  RecordProperty("plate_force_relative_differences", numbers(force_differences));
  RecordProperty("plate_force_p1_N", numbers(forces_p1));
  RecordProperty("plate_force_p2_N", numbers(forces_p2));
  for (size_t k = 1; k < probe_differences.size(); ++k) {
    EXPECT_LT(probe_differences[k], probe_differences[k - 1]) << k;
    EXPECT_LT(force_differences[k], force_differences[k - 1]) << k;
  }
  // Both press back: P1 stiffer than P2 (locking).
  for (size_t k = 0; k < forces_p1.size(); ++k) EXPECT_GT(forces_p1[k], forces_p2[k]) << k;
}

/// (b') Gravity through the models' interface, the liver's load case
/// (suite/liver-grasp-gravity.json) on the small cube: its weight (rho g L / E = 6 %)
/// and a grasp lifting the top, ramped over two frames, with a point force beside
/// (gravity is loads[0], the force loads[1]), neo-Hookean. fem_distributed (P1)
/// against the serial newton solve (models/numerics/elasticity/newton_solve.cc,
/// CHOLMOD) on the same mesh: both integrate rho g N_i over the rest configuration
/// (the same consistent nodal forces) and take their load increments from the
/// previous frame's loads and tool values to this one's, so they solve the same
/// equations; the surface, the probes and the reactions agree to the Newton
/// tolerances. The tool's and the support's forces balance the weight and the force.
TEST(DistributedTools, GravityAndAGraspEqualTheSerialNewtonSolve) {
  const HybridMesh& h = small_cube();
  const Material material{15300, 0.45, 1000};
  const LoadCase c{testing::kCubeBottom,
                   {Load::body_force("loads[0]"), Load::point_force({0.01, 0.015, 0.05}, "loads[1]")},
                   {Tool::grasp({0, 0, 0.1}, 0.02, "tools[0]")}};
  Points probes(3, 3);
  probes << 0, 0, 0.05, 0.02, -0.01, 0.08, -0.03, 0.03, 0.02;
  const std::vector<FrameLoads> frames = {
      {{Eigen::Vector3d(0, 0, -4.905), Eigen::Vector3d(0.05, 0, 0)}, {Eigen::Vector3d(0, 0, 0.0025)}},
      {{Eigen::Vector3d(0, 0, -9.81), Eigen::Vector3d(0.1, 0, 0)}, {Eigen::Vector3d(0, 0, 0.005)}}};
  std::unique_ptr<Model> models[2];
  int index = 0;
  for (const auto& [name, parameters] :
       {std::pair<std::string, nlohmann::json>{
            "fem", {{"solver", "newton"}, {"material_law", "neo_hookean"}, {"newton_load_steps", 2}}},
        {"fem_distributed", {{"material_law", "neo_hookean"}, {"load_steps", 2}, {"cg_tolerance", 1e-12}}}}) {
    const ModelInfo& info = find_model(name);
    EXPECT_NO_THROW(check_supported(info, c)) << name;
    Problem p{&h, material, c, resolve_parameters(info.parameters, parameters, name), probes};
    models[index] = info.create();
    models[index]->setup(p);
    ++index;
  }
  const double weight = material.density * 9.81 * 1e-3;  // the cube's 1e-3 m^3
  std::vector<double> differences;
  for (const FrameLoads& frame : frames) {
    for (auto& m : models) m->step(frame);
    const double du = (models[1]->surface_displacement() - models[0]->surface_displacement()).norm() /
                      models[0]->surface_displacement().norm();
    const double dp = (*models[1]->probe_displacements() - *models[0]->probe_displacements()).norm() /
                      models[0]->probe_displacements()->norm();
    const std::vector<Eigen::Vector3d>& r = *models[1]->reaction_forces();
    ASSERT_EQ(r.size(), 2u);
    double dr = 0;
    for (size_t k = 0; k < 2; ++k) dr = std::max(dr, (r[k] - (*models[0]->reaction_forces())[k]).norm() / weight);
    EXPECT_LT(du, 1e-8);
    EXPECT_LT(dp, 1e-8);
    EXPECT_LT(dr, 1e-8);
    // Equilibrium: the forces on the grasp and the support sum to the applied ones.
    const Eigen::Vector3d applied = material.density * 1e-3 * frame.values[0] + frame.values[1];
    EXPECT_LT((r[0] + r[1] - applied).norm(), 1e-8 * weight) << (r[0] + r[1]).transpose();
    EXPECT_LT(r[0].z(), 0) << "the tissue pulls the grasp down";
    differences.insert(differences.end(), {du, dp, dr});
  }
  RecordProperty("surface_probe_reaction_differences_per_frame", numbers(differences));
}

/// (c) A probe at a node reads the nodal value (P1 and P2); inside a cell it reads
/// the field there: for P2, an exact quadratic field at arbitrary points.
TEST(DistributedTools, ProbesReadTheNodalValuesAtNodesAndTheFieldInside) {
  const TetMesh m = testing::box_mesh(1, 1, 1, 2, 2, 2, 0.02);
  // u = (x^2 - y^2 + yz, -2xy + xz, xy): divergence-free and harmonic, so a
  // solution of linear elasticity with no body force (the P2 test of
  // distributed_elasticity_test.cc), held on the whole boundary.
  auto field = [](const Eigen::Vector3d& x) -> Eigen::Vector3d {
    return {x.x() * x.x() - x.y() * x.y() + x.y() * x.z(), -2 * x.x() * x.y() + x.x() * x.z(), x.x() * x.y()};
  };
  auto on_boundary = [](const Eigen::Vector3d& x) {
    return (x.array() < 1e-12).any() || (x.array() > 1 - 1e-12).any();
  };
  // Every node, then points inside cells.
  Points inside(4, 3);
  inside << 0.31, 0.47, 0.52, 0.5, 0.5, 0.5, 0.12, 0.83, 0.29, 0.7, 0.2, 0.9;
  Points points(m.V.rows() + inside.rows(), 3);
  points << m.V, inside;
  std::vector<int> tets;
  for (const TetEmbedding& e : place_probes(points, m, "test box", false)) tets.push_back(e.tet);
  std::vector<int> all(static_cast<size_t>(m.V.rows()));
  std::iota(all.begin(), all.end(), 0);
  for (int degree = 1; degree <= 2; ++degree) {
    DistributedSettings s;
    s.degree = degree;
    s.cg_tolerance = 1e-13;
    DistributedElasticity fem(m, Material{1000, 0.3, 1000}, on_boundary, s, MPI_COMM_WORLD, field);
    fem.solve({}, Eigen::Vector3d::Zero());
    fem.set_probes(points, tets);
    const Points probe = fem.probe_displacements();
    const Points nodal = fem.node_displacements(all);
    const double scale = nodal.cwiseAbs().maxCoeff();
    EXPECT_LT((probe.topRows(m.V.rows()) - nodal).cwiseAbs().maxCoeff(), 1e-14 * scale) << "P" << degree;
    if (degree == 2) {
      for (Eigen::Index p = 0; p < inside.rows(); ++p)
        EXPECT_LT((probe.row(m.V.rows() + p).transpose() - field(inside.row(p).transpose())).norm(), 1e-9) << p;
    }
    // P1: inside a cell, the barycentric combination of its nodes' values.
    if (degree == 1) {
      for (Eigen::Index p = 0; p < inside.rows(); ++p) {
        const TetEmbedding e = place_probes(inside.row(p), m, "test box", false)[0];
        Eigen::Vector3d x = Eigen::Vector3d::Zero();
        for (int k = 0; k < 4; ++k) x += e.weights(k) * nodal.row(m.T(e.tet, k)).transpose();
        EXPECT_LT((probe.row(m.V.rows() + p).transpose() - x).norm(), 1e-14 * scale) << p;
      }
    }
  }
}

std::string setup_error(const LoadCase& c, const nlohmann::json& parameters = nlohmann::json::object(),
                        const Material& material = Material{}) {
  const ModelInfo& info = find_model("fem_distributed");
  Problem p{&small_cube(), material, c, resolve_parameters(info.parameters, parameters, info.name), Points()};
  try {
    info.create()->setup(p);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

/// (d) Bad tools and groups: one line naming the tool's key (or the group) and the
/// problem, the same on every rank, before any solve.
TEST(DistributedTools, BadToolsAndGroupsAreOneLineErrors) {
  std::string e = setup_error({testing::kCubeBottom, {}, {Tool::plate({{1, 1, 1}, {2, 2, 2}}, false, 2, "tools[0]")}});
  EXPECT_EQ(
      e.rfind("fem_distributed: tools[0] (bonded_plate): its box (1, 1, 1) to (2, 2, 2) holds no surface vertex", 0),
      0u)
      << e;
  EXPECT_EQ(e.find('\n'), std::string::npos) << e;
  e = setup_error({testing::kCubeBottom, {}, {Tool::grasp({0, 0, 0.01}, 0.02, "tools[1]")}});
  EXPECT_EQ(e.rfind("fem_distributed: tools[1] (grasp): ", 0), 0u) << e;
  EXPECT_NE(e.find("in the support box"), std::string::npos) << e;

  const TetMesh& m = small_cube().fine_volume;
  auto engine_error = [&](const std::vector<PrescribedGroup>& groups, bool (*support)(const Eigen::Vector3d&)) {
    try {
      DistributedElasticity(m, Material{}, support, DistributedSettings{}, MPI_COMM_WORLD, {}, groups);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string("no error");
  };
  auto bottom = [](const Eigen::Vector3d& x) { return x.z() <= 1e-9; };
  const std::vector<int> top = nodes_on_plane(m, 2, 0.1), base = nodes_on_plane(m, 2, 0);
  EXPECT_EQ(engine_error({PrescribedGroup{}}, bottom), "distributed FEM: prescribed group 0 has no node");
  EXPECT_EQ(engine_error({sliding_group(top, 2), sliding_group({top[0]}, 2)}, bottom),
            "distributed FEM: node " + std::to_string(top[0]) + " is held by groups 0 and 1 in component 2");
  EXPECT_EQ(engine_error({sliding_group({static_cast<int>(m.V.rows())}, 2)}, bottom),
            "distributed FEM: prescribed group 0 names node " + std::to_string(m.V.rows()) + ", outside the mesh's " +
                std::to_string(m.V.rows()) + " nodes");
  e = engine_error({sliding_group(base, 2)}, bottom);
  EXPECT_EQ(e.rfind("distributed FEM: prescribed group 0 holds ", 0), 0u) << e;
  EXPECT_NE(e.find("dofs the support clamps: a dof cannot be clamped and moved"), std::string::npos) << e;
  EXPECT_EQ(engine_error({}, nowhere),
            "distributed FEM: the support selects no dof and no group holds one, so K is singular");
  // A frame's values: one per group.
  DistributedElasticity fem(m, Material{}, bottom, DistributedSettings{}, MPI_COMM_WORLD, {}, {sliding_group(top, 2)});
  try {
    fem.solve({}, Eigen::Vector3d::Zero(), {});
    ADD_FAILURE() << "no value for the group";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()), "distributed FEM: 0 group values for 1 prescribed groups");
  }
}

/// (e) Bad loads: one line naming the load's key and the problem.
TEST(DistributedTools, BadLoadsAreOneLineErrors) {
  const nlohmann::json defaults = nlohmann::json::object();
  EXPECT_EQ(setup_error({testing::kCubeBottom, {Load::body_force("loads[2]")}, {}}, defaults, Material{3000, 0.45, 0}),
            "fem_distributed: loads[2] (body_force): a body force needs a positive density");
  EXPECT_EQ(setup_error({testing::kCubeBottom,
                         {Load::point_force({0, 0, 0.05}, "loads[0]"), Load::body_force("loads[1]"),
                          Load::surface_traction({0, 0, 0.1}, 0.01, "loads[2]")},
                         {}}),
            "fem_distributed: loads[2] (surface_traction): takes at most one point force or surface traction; "
            "loads[0] is one");
  // Body forces add up: two and a traction are taken.
  EXPECT_EQ(setup_error({testing::kCubeBottom,
                         {Load::body_force("loads[0]"), Load::body_force("loads[1]"),
                          Load::surface_traction({0, 0, 0.1}, 0.01, "loads[2]")},
                         {}}),
            "no error");
}

}  // namespace
}  // namespace tb
