// The rigid frictionless sphere (unilateral contact, docs/equations.md "Contact with a
// rigid sphere"): Hertz's indentation force against the linear FEM's active set under
// refinement, no vertex inside the sphere (FEM, PBD), release, equilibrium, models
// that cannot take it, and a sphere on the liver, a torus and an L-block through every
// model that declares it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <sstream>
#include <string>

#include "elastic_body.h"
#include "elastic_solve.h"
#include "hybrid_builder.h"
#include "parameters.h"
#include "model.h"
#include "shapes.h"
#include "sphere_contact.h"
#include "test_support.h"
#include "tool_placement.h"

namespace tb {
namespace {

/// 0, h0, 2 h0, ... uniform up to `core`, then growing by q per cell up to `length`
/// (the last cell cut to fit).
std::vector<double> graded(double h0, double core, double q, double length) {
  std::vector<double> x = {0};
  double h = h0;
  while (x.back() + h < length - 1e-12 * length) {
    x.push_back(x.back() + h);
    if (x.back() >= core - 1e-12) h *= q;
  }
  if (length - x.back() < 0.5 * h / q && x.size() > 1) x.back() = length;
  else x.push_back(length);
  return x;
}

/// A quarter block [0, L]^2 x [0, L] graded towards the top corner (0, 0, L): a tensor
/// grid of hexahedra each split in 6 tets (the Kuhn split, conforming), its
/// boundary triangles as the fine surface. Cells of side h0 up to `core` from the
/// corner in x and y and core / 2 in depth, then growing by q.
HybridMesh quarter_block(double h0, double core, double q, double L) {
  const std::vector<double> x = graded(h0, core, q, L), y = x;
  std::vector<double> z = graded(h0, core / 2, q, L);
  for (double& c : z) c = L - c;
  std::reverse(z.begin(), z.end());
  const int nx = static_cast<int>(x.size()), ny = static_cast<int>(y.size()), nz = static_cast<int>(z.size());
  HybridMesh h;
  h.fine_volume.V.resize(nx * ny * nz, 3);
  auto id = [&](int i, int j, int k) { return (k * ny + j) * nx + i; };
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) h.fine_volume.V.row(id(i, j, k)) << x[i], y[j], z[k];
  std::vector<std::array<int, 4>> tets;
  const int perms[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k + 1 < nz; ++k)
    for (int j = 0; j + 1 < ny; ++j)
      for (int i = 0; i + 1 < nx; ++i)
        for (const auto& p : perms) {
          std::array<int, 3> c = {i, j, k};
          std::array<int, 4> t;
          t[0] = id(c[0], c[1], c[2]);
          for (int s = 0; s < 3; ++s) {
            ++c[static_cast<size_t>(p[s])];
            t[static_cast<size_t>(s) + 1] = id(c[0], c[1], c[2]);
          }
          const Eigen::Vector3d a = h.fine_volume.V.row(t[0]), b = h.fine_volume.V.row(t[1]),
                                cc = h.fine_volume.V.row(t[2]), d = h.fine_volume.V.row(t[3]);
          if ((b - a).cross(cc - a).dot(d - a) < 0) std::swap(t[2], t[3]);
          tets.push_back(t);
        }
  h.fine_volume.T.resize(static_cast<Eigen::Index>(tets.size()), 4);
  for (size_t t = 0; t < tets.size(); ++t)
    for (int k = 0; k < 4; ++k) h.fine_volume.T(static_cast<Eigen::Index>(t), k) = tets[t][static_cast<size_t>(k)];
  // Boundary faces (in one tet), oriented away from the tet's fourth node.
  std::map<std::array<int, 3>, std::pair<int, std::array<int, 4>>> faces;
  for (const auto& t : tets)
    for (int skip = 0; skip < 4; ++skip) {
      std::array<int, 3> f;
      int n = 0;
      for (int j = 0; j < 4; ++j)
        if (j != skip) f[static_cast<size_t>(n++)] = t[static_cast<size_t>(j)];
      std::array<int, 3> key = f;
      std::sort(key.begin(), key.end());
      auto& e = faces[key];
      ++e.first;
      e.second = {f[0], f[1], f[2], t[static_cast<size_t>(skip)]};
    }
  std::map<int, int> surface_of;
  std::vector<std::array<int, 3>> tris;
  for (const auto& [key, e] : faces) {
    if (e.first != 1) continue;
    std::array<int, 3> f = {e.second[0], e.second[1], e.second[2]};
    const Eigen::Vector3d a = h.fine_volume.V.row(f[0]), b = h.fine_volume.V.row(f[1]), c = h.fine_volume.V.row(f[2]),
                          o = h.fine_volume.V.row(e.second[3]);
    if ((b - a).cross(c - a).dot(o - a) > 0) std::swap(f[1], f[2]);
    for (int& v : f) {
      auto it = surface_of.find(v);
      if (it == surface_of.end()) it = surface_of.emplace(v, static_cast<int>(surface_of.size())).first;
      v = it->second;
    }
    tris.push_back(f);
  }
  h.fine_surface.V.resize(static_cast<Eigen::Index>(surface_of.size()), 3);
  h.fine_surface_to_volume.resize(surface_of.size());
  for (const auto& [node, v] : surface_of) {
    h.fine_surface.V.row(v) = h.fine_volume.V.row(node);
    h.fine_surface_to_volume[static_cast<size_t>(v)] = node;
  }
  h.fine_surface.F.resize(static_cast<Eigen::Index>(tris.size()), 3);
  for (size_t t = 0; t < tris.size(); ++t)
    for (int k = 0; k < 3; ++k) h.fine_surface.F(static_cast<Eigen::Index>(t), k) = tris[t][static_cast<size_t>(k)];
  return h;
}

struct Indentation {
  double force = 0, hertz = 0, seconds = 0, area = 0;
  int nodes = 0, contacts = 0, candidates = 0, solves = 0;
  Eigen::Vector3d sphere = Eigen::Vector3d::Zero(), support = Eigen::Vector3d::Zero();
  double penetration = 0;
  Eigen::VectorXd u;  ///< the body's displacement (3 #V)
  // The Newton solve's KKT at convergence (newton_indent): the most negative
  // multiplier (lambda = f . n), |f_int - f - contact| / |contact| on the free dofs.
  double least_multiplier = 0, equilibrium = 0;
};

/// A mesh level of the indentation: the smallest cell h0 (uniform up to `core` from
/// the axis, core / 2 deep), growing by q beyond, on a quarter block of side L.
struct Level {
  double h0, core, q, L;
};

/// The indentation's candidates: the nodes within 0.01 R of the sphere at the
/// solution without contact (Hertz's contact radius sqrt(R d) lies inside the
/// penetrated disc sqrt(2 R d)), not the default 0.1 R + 2 d, which holds 5 times as
/// many nodes; a node missed would join (and is counted in `rebuilds`).
constexpr double kMargin = 0.01, kDepthFactor = 0;

/// The quarter block of side L (the full block 2 L wide, L deep), bottom
/// clamped, the planes x = 0 and y = 0 symmetry planes (the normal component held
/// at 0; both on their common axis), a sphere of radius R pressed d into the top at
/// the corner (0, 0, L); E = 1. The body and the contact solve the fem model uses
/// (ElasticBody, the direct solve, SphereContact), set up here for the symmetry
/// groups the scenario vocabulary has no tool for.
/// The quarter block's body: bottom clamped, the symmetry planes' groups.
ElasticBody quarter_body(const HybridMesh& h, double nu) {
  const Points& X = h.fine_volume.V;
  const double eps = 1e-9;
  std::vector<char> clamped(static_cast<size_t>(X.rows()), 0);
  PrescribedGroup px, py, pxy;
  px.components[1] = px.components[2] = false;
  py.components[0] = py.components[2] = false;
  pxy.components[2] = false;
  for (Eigen::Index n = 0; n < X.rows(); ++n) {
    const bool bottom = X(n, 2) < eps, on_x = X(n, 0) < eps, on_y = X(n, 1) < eps;
    if (bottom) clamped[static_cast<size_t>(n)] = 1;
    else if (on_x && on_y) pxy.nodes.push_back(static_cast<int>(n));
    else if (on_x) px.nodes.push_back(static_cast<int>(n));
    else if (on_y) py.nodes.push_back(static_cast<int>(n));
  }
  Material m;
  m.youngs_modulus = 1;
  m.poisson_ratio = nu;
  return ElasticBody(h.fine_volume, m, clamped, {px, py, pxy});
}

/// The same indentation by the static Newton solve with the sphere in it (the fem
/// model's solver newton, material law `law`): the sphere first touching the top,
/// then pressed d in `steps` load increments.
Indentation newton_indent(const Level& level, double d, double nu, const std::string& law, int steps = 4) {
  const double R = 1, L = level.L;
  const HybridMesh h = quarter_block(level.h0, level.core, level.q, L);
  const auto start = std::chrono::steady_clock::now();
  const ElasticBody body = quarter_body(h, nu);
  const Parameters p = resolve_parameters(elastic_solve_parameters("", "newton", "two_level"),
                                          {{"material_law", law}, {"newton_load_steps", steps}, {"newton_tolerance", 1e-12}},
                                          "test");
  std::unique_ptr<ElasticSolve> solve = make_elastic_solve(body, p, "");
  solve->enable_spheres(h.fine_surface_to_volume);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(body.dofs()), f_free = Eigen::VectorXd::Zero(body.free_dofs());
  Eigen::MatrixX3d centre(1, 3);
  for (double depth : {0.0, d}) {
    centre << 0, 0, L + R - depth;
    solve->spheres()->set(centre, Eigen::VectorXd::Constant(1, R));
    solve->solve(f_free, nullptr, u);
  }
  const SphereObstacles& contact = *solve->spheres();
  Indentation out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.sphere = contact.forces()[0];
  out.force = 4 * out.sphere.z();
  out.hertz = 4.0 / 3.0 / (1 - nu * nu) * std::sqrt(R) * std::pow(d, 1.5);
  out.nodes = static_cast<int>(h.fine_volume.V.rows());
  out.contacts = static_cast<int>(contact.contact_vertices()[0].size());
  out.area = ContactArea(h.fine_surface).area(contact.contact_vertices()[0]);
  out.penetration = contact.penetration()[0];
  out.u = u;
  // KKT: each contact force lambda n along the outward normal with lambda >= 0, and
  // f_int(u) - f = sum lambda n on the free dofs.
  Eigen::VectorXd contact_full = Eigen::VectorXd::Zero(body.dofs());
  out.least_multiplier = std::numeric_limits<double>::infinity();
  for (const auto& [node, force] : contact.node_forces()) {
    const Eigen::Vector3d x = h.fine_volume.V.row(node).transpose() + u.segment<3>(3 * node);
    const Eigen::Vector3d n = (x - centre.row(0).transpose()).normalized();
    out.least_multiplier = std::min(out.least_multiplier, force.dot(n));
    EXPECT_LT((force - force.dot(n) * n).norm(), 1e-12 * force.norm()) << "frictionless: along the normal";
    contact_full.segment<3>(3 * node) += force;
  }
  Eigen::VectorXd f_int_free, contact_free;
  body.to_free(*solve->internal_force(), f_int_free);
  body.to_free(contact_full, contact_free);
  out.equilibrium = (f_int_free - contact_free).norm() / contact_free.norm();
  std::vector<Eigen::Vector3d> groups(3);
  Eigen::Vector3d support;
  body.reactions(u, contact_full, groups, support, solve->internal_force());
  out.support = support + groups[0] + groups[1] + groups[2];
  return out;
}

/// The linear active-set indentation; `solver` "direct" (the flexibility G in blocks
/// of right-hand sides, solve_columns) or "iterative" (G column by column, CG).
Indentation indent(const Level& level, double d, double nu, const std::string& solver = "direct",
                   double margin = kMargin) {
  const double R = 1, L = level.L, E = 1;
  const HybridMesh h = quarter_block(level.h0, level.core, level.q, L);
  const Points& X = h.fine_volume.V;
  const auto start = std::chrono::steady_clock::now();
  const ElasticBody body = quarter_body(h, nu);
  std::unique_ptr<ElasticSolve> solve =
      solver == "direct" ? make_direct_solve(body)
                         : make_elastic_solve(body,
                                              resolve_parameters(elastic_solve_parameters("", solver, "ic"),
                                                                 {{"preconditioner", "ic"}, {"cg_tolerance", 1e-13}}, "test"),
                                              "");
  SphereContact contact(body, *solve, h.fine_surface_to_volume);
  contact.set_candidate_margin(margin, kDepthFactor);
  Eigen::VectorXd u = Eigen::VectorXd::Zero(body.dofs());
  Eigen::MatrixX3d centre(1, 3);
  centre << 0, 0, L + R - d;
  contact.solve(centre, Eigen::VectorXd::Constant(1, R), u);
  Indentation out;
  out.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  out.sphere = contact.forces()[0];
  out.force = 4 * out.sphere.z();  // the whole sphere's (four quarters); the tissue pushes it up, +z
  const double Estar = E / (1 - nu * nu);
  out.hertz = 4.0 / 3.0 * Estar * std::sqrt(R) * std::pow(d, 1.5);
  out.nodes = static_cast<int>(X.rows());
  out.contacts = static_cast<int>(contact.contact_vertices()[0].size());
  out.area = ContactArea(h.fine_surface).area(contact.contact_vertices()[0]);
  out.penetration = contact.penetration()[0];
  out.candidates = contact.report()["largest_candidate_count"].get<int>();
  out.solves = contact.report()["flexibility_solves"].get<int>();
  out.u = u;
  // The reactions of the support and the symmetry planes, the contact forces external.
  Eigen::VectorXd f = Eigen::VectorXd::Zero(body.dofs());
  for (const auto& [node, force] : contact.node_forces()) f.segment<3>(3 * node) += force;
  std::vector<Eigen::Vector3d> groups(3);
  Eigen::Vector3d support;
  body.reactions(u, f, groups, support);
  out.support = support + groups[0] + groups[1] + groups[2];
  return out;
}

/// Hertz (1882): F = 4/3 E* R^(1/2) d^(3/2), E* = E / (1 - nu^2), a rigid sphere on an
/// elastic half-space. Two meshes of the quarter block of side 20 R (smallest cell a/4
/// and a/8 up to 1.25 a from the axis, a = sqrt(R d) the contact radius, growing by
/// 1.3 beyond). P1 tets are too stiff, so the force lies above Hertz's and falls
/// towards it; the clamped bottom 20 R down adds about 1 % (Boussinesq), the exact
/// sphere (Sneddon 1965) takes 0.45 % off. Measured (docs/equations.md, with the
/// finer levels of DISABLED_HertzStudy): +7.44 % and +5.72 %; the direct solve is
/// deterministic, so the bounds leave 0.25 of a percentage point for rounding
/// elsewhere. Not within 5 % at these levels: docs/equations.md says which level is.
TEST(SphereContact, HertzIndentationForceConvergesUnderRefinement) {
  const double d = 0.04, a = std::sqrt(d);
  const Indentation coarse = indent({a / 4, 1.25 * a, 1.3, 20}, d, 0.3);
  const Indentation fine = indent({a / 8, 1.25 * a, 1.3, 20}, d, 0.3);
  for (const Indentation* i : {&coarse, &fine}) {
    RecordProperty("nodes_" + std::to_string(i->nodes), ::testing::PrintToString(i->force / i->hertz - 1));
    std::printf("Hertz: %d nodes, F = %.6g (Hertz %.6g, error %+.4f), %d in contact, area %.4g (pi a^2 / 4 = %.4g), "
                "%.2f s\n",
                i->nodes, i->force, i->hertz, i->force / i->hertz - 1, i->contacts, i->area, M_PI * d / 4, i->seconds);
    EXPECT_LT(i->penetration, 1e-6) << "no vertex inside the sphere";
    EXPECT_GT(i->force, i->hertz) << "P1 tets and the finite block both stiffen";
  }
  EXPECT_LT(coarse.force / coarse.hertz - 1, 0.0744 + 0.0025);
  EXPECT_LT(fine.force / fine.hertz - 1, 0.0572 + 0.0025);
  EXPECT_LT(fine.force, coarse.force) << "the error falls with refinement";
  // Equilibrium: the sphere's reaction and the support's (and the symmetry planes') sum to zero.
  EXPECT_LT((fine.sphere + fine.support).norm(), 1e-9 * fine.sphere.norm());
}

/// The flexibility G built in blocks of right-hand sides (the direct solve's
/// solve_columns) and column by column (CG): the same contact, the symmetry planes'
/// held components included, to the CG's tolerance.
TEST(SphereContact, BlockedAndColumnByColumnFlexibilityGiveTheSameContact) {
  const double d = 0.04, a = std::sqrt(d);
  const Level level{a / 2, 1.25 * a, 1.5, 5};  // a small mesh: CG on every column is slow
  // Candidates within 0.3 R of the sphere: a block of 96 columns and a partial one
  // (55 candidates, 165 columns).
  const Indentation blocked = indent(level, d, 0.3, "direct", 0.3);
  const Indentation columns = indent(level, d, 0.3, "iterative", 0.3);
  ASSERT_GT(3 * blocked.candidates, 96) << "a full block and more";
  ASSERT_NE(3 * blocked.candidates % 96, 0) << "a partial last block";
  EXPECT_EQ(blocked.solves, columns.solves);
  EXPECT_EQ(blocked.contacts, columns.contacts);
  EXPECT_LT((blocked.u - columns.u).norm(), 1e-8 * blocked.u.norm());
  EXPECT_LT(std::abs(blocked.force - columns.force), 1e-8 * blocked.force);
}

/// The indentation at the mesh levels of TB_HERTZ_LEVELS ("n,core,q,L;..." : smallest
/// cell a / n, uniform up to core * a, growth q, quarter side L in R), one line each;
/// outside CTest (DISABLED_), the finer levels take minutes. docs/equations.md
/// ("Contact with a rigid sphere") gives the command and the numbers.
TEST(SphereContact, DISABLED_HertzStudy) {
  const double d = 0.04, a = std::sqrt(d);
  const char* env = std::getenv("TB_HERTZ_LEVELS");
  std::string levels = env ? env : "4,1.25,1.3,5;8,1.25,1.3,5";
  std::stringstream list(levels);
  std::string item;
  while (std::getline(list, item, ';')) {
    double n = 0, core = 0, q = 0, L = 0;
    ASSERT_EQ(std::sscanf(item.c_str(), "%lf,%lf,%lf,%lf", &n, &core, &q, &L), 4) << item;
    const Indentation i = indent({a / n, core * a, q, L}, d, 0.3);
    std::printf("HERTZ a/%g core %.2fa q %.2f L %gR: %d nodes, F = %.6g (Hertz %.6g, error %+.4f), %d in contact, "
                "area %.4g, depth %.2g, equilibrium %.1e, %d candidates, %d solves, %.1f s\n",
                n, core, q, L, i.nodes, i.force, i.hertz, i.force / i.hertz - 1, i.contacts, i.area, i.penetration,
                (i.sphere + i.support).norm() / i.sphere.norm(), i.candidates, i.solves, i.seconds);
    std::fflush(stdout);
  }
}

/// Newton's contact on the Hertz indentation (the coarse level of the test above on
/// a block of side 10 R, d = 0.01 R: a = 0.1 R, a small strain): the neo-Hookean force against Hertz and
/// against the linear FEM's on the same mesh, and its KKT conditions at convergence.
TEST(NewtonSphereContact, HertzIndentationNeoHookeanAgreesWithTheLinearContactAndHertz) {
  const double d = 0.01, a = std::sqrt(d);
  const Level level{a / 4, 1.25 * a, 1.3, 5};
  const Indentation linear = indent(level, d, 0.3);
  const Indentation neo = newton_indent(level, d, 0.3, "neo_hookean");
  std::printf("Hertz d = 0.01 R: linear FEM F = %.6g (%+.4f), Newton neo-Hookean F = %.6g (%+.4f), %d / %d in contact, "
              "neo / linear - 1 = %+.2e, %.1f s\n",
              linear.force, linear.force / linear.hertz - 1, neo.force, neo.force / neo.hertz - 1, linear.contacts,
              neo.contacts, neo.force / linear.force - 1, neo.seconds);
  RecordProperty("neo_over_hertz", ::testing::PrintToString(neo.force / neo.hertz - 1));
  RecordProperty("neo_over_linear", ::testing::PrintToString(neo.force / linear.force - 1));
  // Measured: linear +7.39 %, neo-Hookean +6.83 % of Hertz (the P1 mesh's stiffness and the
  // finite block, as in the linear test above), the neo-Hookean 0.52 % below the linear (the
  // law's nonlinearity at a / R = 0.1); the direct solves are deterministic, so the bounds
  // leave a tenth of a percentage point for rounding elsewhere.
  EXPECT_LT(std::abs(neo.force / neo.hertz - 1 - 0.0683), 0.001);
  EXPECT_LT(std::abs(neo.force / linear.force - 1 + 0.0052), 0.001);
  // KKT at convergence.
  EXPECT_LE(neo.penetration, 1e-9) << "no node inside the sphere beyond 1e-9 R";
  EXPECT_GE(neo.least_multiplier, 0) << "no tensile multiplier";
  EXPECT_LT(neo.equilibrium, 1e-8) << "f_int - f = the contact forces";
  EXPECT_LT((neo.sphere + neo.support).norm(), 1e-8 * neo.sphere.norm()) << "the sphere's force balances the support's";
}

/// Newton with the linear law and the sphere solves the linear FEM's contact problem:
/// the same answer as the active set on K (SphereContact), to the latter's tolerance:
/// it re-linearises the normals until each active node is within 1e-6 r of the
/// sphere, Newton until 1e-9 r. Measured 7.4e-8 (field) and 2.8e-7 (force), the same
/// 17 nodes in contact; the bounds are three times that, not the 1e-8 Newton's own KKT
/// residual reaches (HertzIndentation... checks it).
TEST(NewtonSphereContact, LinearLawEqualsTheLinearActiveSetContact) {
  const double d = 0.01, a = std::sqrt(d);
  const Level level{a / 4, 1.25 * a, 1.3, 5};
  const Indentation linear = indent(level, d, 0.3);
  const Indentation newton = newton_indent(level, d, 0.3, "linear");
  const double du = (newton.u - linear.u).norm() / linear.u.norm();
  const double df = (newton.sphere - linear.sphere).norm() / linear.sphere.norm();
  std::printf("linear law: |u_newton - u_linear| / |u| = %.2e, force %.2e, %d / %d in contact\n", du, df,
              newton.contacts, linear.contacts);
  RecordProperty("displacement_difference", ::testing::PrintToString(du));
  RecordProperty("force_difference", ::testing::PrintToString(df));
  EXPECT_EQ(newton.contacts, linear.contacts);
  EXPECT_LT(du, 2.5e-7);
  EXPECT_LT(df, 9e-7);
}

const HybridMesh& cube() { return testing::scenario_mesh("cube-pull"); }

/// The sphere pressed into the cube's top then withdrawn: contact while pressed, none
/// after, the reaction back to zero, and no surface vertex inside it (FEM: 1e-9 of
/// the radius; PBD and the hybrid: 1e-6 m, the projection's last sweep).
TEST(SphereContact, PressedThenWithdrawnReleasesInEveryModelThatTakesIt) {
  const double R = 0.03;
  const Eigen::Vector3d above(0, 0, 0.1 + R), pressed(0, 0, 0.1 + R - 0.01), away(0, 0, 0.1 + R + 0.02);
  int models = 0;
  for (const ModelInfo& info : registered_models()) {
    if (!info.takes(ToolKind::Sphere)) continue;
    ++models;
    // The tet steppers (vbd, xpbd_neo, pd) cost tens of ms a frame on this mesh: a
    // 50 ms step settles them in 100 frames (PBD's 300 cost less than one of theirs).
    // The implicit-Euler reference (a Newton solve a step) settles in 20 steps of 0.5 s.
    const bool tet_stepper = info.name == "vbd" || info.name == "xpbd_neo" || info.name == "pd";
    const bool implicit_euler = info.name == "fem_dynamic";
    const nlohmann::json given = tet_stepper      ? nlohmann::json{{"time_step", 0.05}}
                                 : implicit_euler ? nlohmann::json{{"time_step", 0.5}}
                                                  : nlohmann::json::object();
    Problem p{&cube(), Material{}, LoadCase{testing::kCubeBottom, {}, {Tool::sphere(above, R, "tools[0]")}},
              resolve_parameters(info.parameters, given, info.name), Points()};
    auto m = info.create();
    m->setup(p);
    const int frames = tet_stepper ? 100 : implicit_euler ? 20 : info.dynamic ? 300 : 1;
    for (int f = 0; f < frames; ++f) m->step(FrameLoads{{}, {pressed}});
    const ToolContact on = (*m->tool_contacts())[0];
    const Eigen::Vector3d pushed = (*m->reaction_forces())[0];
    EXPECT_GT(on.points, 0) << info.name;
    // The contact set as defined (docs/equations.md): PBD and the hybrid, every vertex
    // within 0.01 R of the sphere's surface or inside it at the end of the frame; the
    // FEM, the active nodes, each on the sphere to 1e-6 R (and none inside).
    {
      const Displacements& u = m->surface_displacement();
      int on_sphere = 0, within = 0;
      for (Eigen::Index v = 0; v < u.rows(); ++v) {
        const double gap = (cube().fine_surface.V.row(v) + u.row(v) - pressed.transpose()).norm() - R;
        on_sphere += gap <= 1e-6 * R;  // an active node sits within 1e-6 r above the sphere
        within += gap <= 0.01 * R;
      }
      if (info.name == "fem" || implicit_euler)
        EXPECT_LE(on.points, on_sphere) << info.name;
      else if (info.name == "pbd" || info.name == "hybrid")
        EXPECT_EQ(on.points, within) << info.name;
      else  // the real-time FEMs: the nodes their last constraint step acted on, each on the sphere
        EXPECT_LE(on.points, within) << info.name;
    }
    // The area: the contact vertices' vertex areas, of the order of the patch the
    // sphere pressed 1 cm cuts from the top (2 pi R d, the cap's area; Hertz's pi R d).
    const double cap = 2 * M_PI * R * 0.01;
    RecordProperty(info.name + "_area_over_cap", ::testing::PrintToString(on.area / cap));
    std::printf("%s: %d in contact, area %.4g m^2 = %.3f of the cap 2 pi R d\n", info.name.c_str(), on.points, on.area,
                on.area / cap);
    // Measured (cube-pull mesh): fem 0.50, pbd 0.28, hybrid 0.87 of the cap; the bounds
    // leave a factor of about 3 below and 2 above.
    EXPECT_GT(on.area, 0.1 * cap) << info.name;
    EXPECT_LT(on.area, 2 * cap) << info.name;
    EXPECT_GT(pushed.z(), 0) << info.name << ": the tissue pushes the sphere up";
    // The hybrid's control points follow the coarse FEM, which does not feel the sphere.
    const bool projects_all = info.name != "hybrid";
    const double tolerance = info.dynamic && !implicit_euler ? 1e-6 : 1e-9 * R;
    if (projects_all) {
      EXPECT_LE(on.max_penetration, tolerance) << info.name;
    }
    const Displacements& u = m->surface_displacement();
    for (Eigen::Index v = 0; v < u.rows() && projects_all; ++v)
      EXPECT_GE((cube().fine_surface.V.row(v) + u.row(v) - pressed.transpose()).norm(), R - tolerance)
          << info.name << " vertex " << v;
    EXPECT_LT(u.col(2).minCoeff(), -0.005) << info.name << ": the top is pressed down";
    if (info.name == "fem" || implicit_euler) {  // equilibrium of the static FEM, and of the settled dynamic one
      const auto& r = *m->reaction_forces();
      EXPECT_LT((r[0] + r[1]).norm(), (implicit_euler ? 1e-7 : 1e-9) * r[0].norm()) << info.name;
    }
    for (int f = 0; f < frames; ++f) m->step(FrameLoads{{}, {away}});
    const ToolContact off = (*m->tool_contacts())[0];
    EXPECT_EQ(off.points, 0) << info.name;
    EXPECT_EQ(off.area, 0) << info.name;
    EXPECT_EQ((*m->reaction_forces())[0].norm(), 0) << info.name;
  }
  EXPECT_EQ(models, 7) << "fem, fem_dynamic, pbd, hybrid, vbd, xpbd_neo, pd";
}

/// Projective dynamics' contact set settles under a held sphere at long time steps.
/// Its constrained global step uses A, PD's fixed matrix, for the Hessian; taken
/// whole it overshot where the neo-Hookean Hessian outgrows A, and at 50 ms the
/// primal-dual set went from 1 to 13 nodes frame to frame with half the press inside
/// the sphere. With the step halved until the Lagrangian decreases (pd_solve.cc),
/// measured: 9 nodes (the static FEM's count at this press) and 0.8960 N from frame
/// 30 on at 50 ms and 500 ms; the bounds leave the force a thousandth.
TEST(SphereContact, ProjectiveDynamicsContactSetSettlesAtLongTimeSteps) {
  const double R = 0.03;
  const Eigen::Vector3d above(0, 0, 0.1 + R), pressed(0, 0, 0.1 + R - 0.01);
  const ModelInfo& info = find_model("pd");
  for (const double h : {0.05, 0.5}) {
    Problem p{&cube(), Material{}, LoadCase{testing::kCubeBottom, {}, {Tool::sphere(above, R, "tools[0]")}},
              resolve_parameters(info.parameters, {{"time_step", h}}, info.name), Points()};
    auto m = info.create();
    m->setup(p);
    std::vector<int> points;
    std::vector<double> force;
    for (int f = 0; f < 40; ++f) {
      m->step(FrameLoads{{}, {pressed}});
      const ToolContact on = (*m->tool_contacts())[0];
      points.push_back(on.points);
      force.push_back((*m->reaction_forces())[0].z());
      EXPECT_LE(on.max_penetration, 1e-9 * R) << "h " << h << " frame " << f;
    }
    for (int f = 30; f < 40; ++f) {
      EXPECT_EQ(points[f], 9) << "h " << h << " frame " << f;
      EXPECT_NEAR(force[f], 0.8960, 1e-3) << "h " << h << " frame " << f;
    }
  }
}

TEST(SphereContact, ModelsWithoutItRefuseItBeforeSetup) {
  const LoadCase c{testing::kCubeBottom, {}, {Tool::sphere({0, 0, 0.2}, 0.05, "tools[0]")}};
  for (const char* name : {"condensed", "embedded", "fem_distributed"}) {
    try {
      check_supported(find_model(name), c);
      ADD_FAILURE() << name << " took a sphere";
    } catch (const std::invalid_argument& e) {
      const std::string w = e.what();
      EXPECT_EQ(w.rfind(std::string("model '") + name + "' does not take sphere tools (tools[0]); it takes ", 0), 0u)
          << w;
      EXPECT_EQ(w.find('\n'), std::string::npos);
    }
  }
}

TEST(SphereContact, BadSpheresAreOneLineErrorsNamingTheKey) {
  const SurfaceMesh& s = cube().fine_surface;
  auto error = [&](const Tool& t) {
    try {
      tool_vertices(t, s, testing::kCubeBottom);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  std::string e = error(Tool::sphere({0, 0, 0.12}, 0.05, "tools[1]"));  // 0.03 m deep into the top
  EXPECT_EQ(e.rfind("tools[1] (sphere): at its first centre (0, 0, 0.12) surface vertex", 0), 0u) << e;
  e = error(Tool::sphere({0, 0, 0.05}, 0.01, "tools[0]"));  // wholly inside
  EXPECT_NE(e.find("is inside the body"), std::string::npos) << e;
  e = error(Tool::sphere({0, 0, 0.2}, 0, "tools[0]"));
  EXPECT_NE(e.find("tools[0] (sphere): radius 0"), std::string::npos) << e;
  EXPECT_EQ(error(Tool::sphere({0, 0, 0.1 + 0.05}, 0.05)), "no error") << "touching at the start is allowed";
}

/// The fem model with the Newton solver (and every nonlinear model that takes a
/// sphere) checks its spheres as the linear FEM does (tool_vertices): a sphere
/// starting too deep in the body, or with a radius that is not a number, is a
/// one-line error naming the tool before anything is solved.
TEST(NewtonSphereContact, BadSpheresAreOneLineErrorsInTheNonlinearModels) {
  const std::vector<std::pair<std::string, nlohmann::json>> cases = {
      {"fem", {{"solver", "newton"}}}, {"fem_dynamic", {}}, {"vbd", {}}, {"xpbd_neo", {}}, {"pd", {}}};
  for (const auto& [model, parameters] : cases) {
    const ModelInfo& info = find_model(model);
    for (const Tool& bad : {Tool::sphere({0, 0, 0.12}, 0.05, "tools[0]"),
                            Tool::sphere({0, 0, 0.2}, std::numeric_limits<double>::quiet_NaN(), "tools[0]")}) {
      Problem p{&cube(), Material{}, LoadCase{testing::kCubeBottom, {}, {bad}},
                resolve_parameters(info.parameters, parameters, info.name), Points()};
      auto m = info.create();
      try {
        m->setup(p);
        ADD_FAILURE() << model << " took a bad sphere";
      } catch (const std::invalid_argument& e) {
        const std::string w = e.what();
        EXPECT_NE(w.find("tools[0] (sphere): "), std::string::npos) << model << ": " << w;
        EXPECT_EQ(w.find('\n'), std::string::npos) << w;
      }
    }
  }
}

/// A sphere pressed into the liver, a torus and an L-block (from above, onto the
/// highest vertex) through every model that takes one: each runs, stays finite,
/// pushes the surface, and no vertex is left inside (the FEM's and PBD's tolerance).
TEST(SphereContact, ASphereOnTheLiverATorusAndAnLBlockRunsInEveryModelThatTakesOne) {
  HybridBuildOptions o;
  o.fine_tetgen.radius_edge_ratio = 1.414;
  o.target_coarse_nodes = 120;
  static const HybridMesh torus = build_hybrid_from_surface(make_shape_surface({"torus", 12}), o, "torus");
  static const HybridMesh l_block = build_hybrid_from_surface(make_shape_surface({"l_block", 12}), o, "l_block");
  const std::vector<std::pair<std::string, const HybridMesh*>> bodies = {
      {"liver", &testing::scenario_mesh("liver-pull")}, {"torus", &torus}, {"l_block", &l_block}};
  for (const auto& [name, mesh] : bodies) {
    const Points& V = mesh->fine_surface.V;
    const double zmin = V.col(2).minCoeff(), zmax = V.col(2).maxCoeff();
    const SupportBox support{{-1, -1, -1}, {1, 1, zmin + 0.1 * (zmax - zmin)}};
    Eigen::Index top = 0;
    V.col(2).maxCoeff(&top);
    const double R = 0.02;
    const Eigen::Vector3d start = V.row(top).transpose() + Eigen::Vector3d(0, 0, R + 1e-4);
    const Tool sphere = Tool::sphere(start, R);
    for (const ModelInfo& info : registered_models()) {
      if (!info.takes(ToolKind::Sphere)) continue;
      // VBD and XPBD with a 50 ms step over 100 frames (as in the test above); PD keeps its
      // 10 ms: with 50 ms and 10 iterations a frame its gaps did not close on the liver and
      // the L-block (2.6 and 4.6 mm inside at the end).
      // The implicit-Euler reference: 20 steps of 0.5 s.
      const bool tet_stepper = info.name == "vbd" || info.name == "xpbd_neo";
      const bool implicit_euler = info.name == "fem_dynamic";
      const nlohmann::json given = tet_stepper      ? nlohmann::json{{"time_step", 0.05}}
                                   : implicit_euler ? nlohmann::json{{"time_step", 0.5}}
                                                    : nlohmann::json::object();
      Problem p{mesh, Material{}, LoadCase{support, {}, {sphere}}, resolve_parameters(info.parameters, given, info.name),
                Points()};
      auto m = info.create();
      m->setup(p);
      const int frames = tet_stepper ? 100 : implicit_euler ? 20 : info.dynamic ? 200 : 5;
      for (int f = 0; f < frames; ++f)
        m->step(FrameLoads{{}, {start - Eigen::Vector3d(0, 0, 0.005 * std::min(1.0, (f + 1.0) / (frames / 2)))}});
      const Displacements& u = m->surface_displacement();
      ASSERT_TRUE(u.allFinite()) << name << " " << info.name;
      EXPECT_LT(u(top, 2), -0.001) << name << " " << info.name << ": the top vertex is pushed down";
      const ToolContact c = (*m->tool_contacts())[0];
      EXPECT_GT(c.points, 0) << name << " " << info.name;
      if (info.name != "hybrid") {  // the hybrid's control points follow the coarse FEM, not the sphere
        // PD closes the gaps of its contact set in each iteration, and a node that enters in a
        // frame's last iteration stays inside until the next: on the liver 5.5e-6 m measured
        // (200 frames of 10 ms); its bound is 1e-5 m, the others' 1e-6 m (dynamic) and 1e-9 R (static).
        const double bound = info.name == "pd" ? 1e-5 : info.dynamic && !implicit_euler ? 1e-6 : 1e-9 * R;
        EXPECT_LE(c.max_penetration, bound) << name << " " << info.name;
      }
      RecordProperty(name + "_" + info.name + "_penetration", ::testing::PrintToString(c.max_penetration));
    }
  }
}

}  // namespace
}  // namespace tb
