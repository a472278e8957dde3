// The real-time nonlinear steppers (vbd, xpbd_neo, pd) on the coarse tet mesh with
// the fine surface embedded (parameter volume coarse_embedded): a fixed point of VBD
// and PD is the law's static equilibrium, so each, run until it stops moving, must
// give the static Newton solve of the same law on the same coarse mesh (the embedded
// model with coarse_solver newton), interpolated to the same fine surface: the
// surface, the reactions on the support and the tools, and the probes; under a point
// force pulling and pushing, a bonded plate lifted, a grasp under gravity, and a
// traction beside a sliding plate, on a small clamped cube whose fine surface is
// finer than the coarse mesh. XPBD's fixed point is not its law's equilibrium (a bias
// of order h^2, tests/models/realtime/realtime_solvers_test.cc): it is held to that
// bias. And the parameter's errors.
#include <gtest/gtest.h>

#include "cube_generator.h"
#include "model.h"
#include "settled_cube.h"
#include "test_support.h"

namespace tb {
namespace {

using testing::kMaterial;
using testing::SmallCube;

constexpr double a = SmallCube::a;
const SupportBox kBottom{{-1, -1, -1e-9}, {1, 1, 1e-9}};

/// The small cube's coarse tets (a 4 x 4 x 4 surface grid) with a fine surface of
/// the same box on an 8 x 8 x 8 grid embedded in them; no fine volume.
const HybridMesh& embedded_cube() {
  static const HybridMesh h = [] {
    HybridMesh m;
    m.coarse_volume = SmallCube().mesh;
    m.fine_surface = make_cube_surface({1.0, 1.0, 8, 8, 8});
    m.fine_surface.V.col(0) = (m.fine_surface.V.col(0).array() + 0.5) * a;
    m.fine_surface.V.col(1) = (m.fine_surface.V.col(1).array() + 0.5) * a;
    m.fine_surface.V.col(2) *= a;
    return m;
  }();
  return h;
}

std::unique_ptr<Model> set_up(const std::string& model, const nlohmann::json& parameters, const LoadCase& load_case,
                              const Points& probes = Points(), const HybridMesh& mesh = embedded_cube()) {
  const ModelInfo& info = find_model(model);
  Problem p{&mesh, kMaterial, load_case, resolve_parameters(info.parameters, parameters, model), probes};
  auto m = info.create();
  m->setup(p);
  return m;
}

/// A stepper on volume coarse_embedded, the law whose equilibrium it reaches, and
/// its tolerance against Newton's answer of that law (relative, field and forces).
struct CoarseStepper {
  std::string model;
  nlohmann::json parameters;
  std::string law;
  double tolerance;
  int max_frames;
};

std::vector<CoarseStepper> coarse_steppers() {
  // Long steps (0.5 s against the cube's periods of milliseconds: inertia damps out
  // in a few frames) for the implicit steppers; XPBD at the 10 ms and 40 sub-steps
  // whose bias realtime_solvers_test.cc measured on the same cube (1.2e-3, 1.5e-3).
  return {{"vbd", {{"volume", "coarse_embedded"}, {"time_step", 0.5}, {"iterations", 50}}, "neo_hookean", 1e-9, 2000},
          {"pd",
           {{"volume", "coarse_embedded"}, {"time_step", 0.5}, {"iterations", 20}, {"tolerance", 0}},
           "neo_hookean",
           1e-9,
           2000},
          {"xpbd_neo",
           {{"volume", "coarse_embedded"}, {"time_step", 0.01}, {"substeps", 40}},
           "xpbd_neo_hookean",
           3e-3,
           4000}};
}

class CoarseEmbeddedStepper : public ::testing::TestWithParam<CoarseStepper> {};

/// The embedded model's coarse Newton solve of `law` to 1e-12.
std::unique_ptr<Model> newton_reference(const std::string& law, const LoadCase& load_case,
                                        const Points& probes = Points()) {
  return set_up("embedded",
                {{"coarse_solver", "newton"},
                 {"coarse_material_law", law},
                 {"coarse_newton_tolerance", 1e-12},
                 {"coarse_newton_load_steps", 4}},
                load_case, probes);
}

/// Frames under `loads` until the surface moves by at most 1e-11 of its displacement
/// in a frame; the frames taken (max_frames + 1: not settled).
int settle(Model& m, const FrameLoads& loads, int max_frames) {
  Displacements previous;
  for (int f = 1; f <= max_frames; ++f) {
    previous = m.surface_displacement();
    m.step(loads);
    if (f > 1 && (m.surface_displacement() - previous).norm() <= 1e-11 * m.surface_displacement().norm()) return f;
  }
  return max_frames + 1;
}

double relative(const Displacements& u, const Displacements& expected) {
  return (u - expected).norm() / expected.norm();
}

/// Each reaction (tools, then the support) against the reference's, relative to the
/// largest of the reference's.
double reactions_error(const Model& m, const Model& reference) {
  const std::vector<Eigen::Vector3d>& r = *m.reaction_forces();
  const std::vector<Eigen::Vector3d>& e = *reference.reaction_forces();
  double worst = 0, largest = 0;
  for (size_t k = 0; k < e.size(); ++k) {
    worst = std::max(worst, (r[k] - e[k]).norm());
    largest = std::max(largest, e[k].norm());
  }
  return worst / largest;
}

/// The stepper settled under constant `loads` against Newton's answer of its law on
/// the same coarse mesh: surface and reactions within its tolerance (recorded as
/// `<model>_<tag>_*`). Returns the reference, for a test's own further checks.
std::unique_ptr<Model> expect_settles_on_newtons_answer(const CoarseStepper& s, const LoadCase& load_case,
                                                        const FrameLoads& loads, const std::string& tag) {
  auto reference = newton_reference(s.law, load_case);
  reference->step(loads);
  auto m = set_up(s.model, s.parameters, load_case);
  const int frames = settle(*m, loads, s.max_frames);
  EXPECT_LE(frames, s.max_frames) << s.model;
  const double error = relative(m->surface_displacement(), reference->surface_displacement());
  EXPECT_LT(error, s.tolerance) << s.model;
  EXPECT_LT(reactions_error(*m, *reference), s.tolerance) << s.model;
  ::testing::Test::RecordProperty(s.model + "_" + tag + "_frames", frames);
  ::testing::Test::RecordProperty(s.model + "_" + tag + "_relative_error", ::testing::PrintToString(error));
  return reference;
}

// 0.2 N at the top centre, up then down (about 17 % of the height under Newton), and
// the displacement at a probe in the middle of the cube.
TEST_P(CoarseEmbeddedStepper, EqualsTheCoarseNewtonAnswerUnderAPointForce) {
  const CoarseStepper& s = GetParam();
  const LoadCase load_case{kBottom, {Load::point_force({a / 2, a / 2, a})}, {}};
  Points probe(1, 3);
  probe << a / 2, a / 2, a / 2;
  for (double fz : {0.2, -0.2}) {
    const FrameLoads loads = frame_of({0, 0, fz});
    auto reference = newton_reference(s.law, load_case, probe);
    reference->step(loads);
    auto m = set_up(s.model, s.parameters, load_case, probe);
    const int frames = settle(*m, loads, s.max_frames);
    EXPECT_LE(frames, s.max_frames) << s.model << " did not settle, force " << fz;
    const double error = relative(m->surface_displacement(), reference->surface_displacement());
    EXPECT_LT(error, s.tolerance) << s.model << " force " << fz << " frames " << frames;
    EXPECT_LT(reactions_error(*m, *reference), s.tolerance) << s.model << " force " << fz;
    // The support balances the load.
    EXPECT_LT((m->reaction_forces()->back() - Eigen::Vector3d(0, 0, fz)).norm(), s.tolerance * std::abs(fz));
    const Eigen::RowVector3d probe_u = m->probe_displacements()->row(0);
    const Eigen::RowVector3d probe_expected = reference->probe_displacements()->row(0);
    EXPECT_LT((probe_u - probe_expected).norm(), s.tolerance * probe_expected.norm()) << s.model;
    EXPECT_EQ(m->report()["volume"], "coarse_embedded");
    RecordProperty(s.model + (fz > 0 ? "_pull" : "_push") + "_frames", frames);
    RecordProperty(s.model + (fz > 0 ? "_pull" : "_push") + "_relative_error", ::testing::PrintToString(error));
  }
}

// A bonded plate on the top face lifted 8 mm (20 %) over 10 frames, then held: the
// surface and the plate's force (on the coarse nodes the plate holds) equal Newton's.
TEST_P(CoarseEmbeddedStepper, EqualsTheCoarseNewtonAnswerUnderAPlate) {
  const CoarseStepper& s = GetParam();
  const LoadCase load_case{kBottom, {}, {Tool::plate({{-1, -1, a - 1e-9}, {1, 1, 1}}, false)}};
  const Eigen::Vector3d lift(0, 0, 0.2 * a);
  auto reference = newton_reference(s.law, load_case);
  reference->step(FrameLoads{{}, {lift}});
  auto m = set_up(s.model, s.parameters, load_case);
  for (int f = 1; f <= 10; ++f) m->step(FrameLoads{{}, {lift * (f / 10.0)}});
  const int frames = settle(*m, FrameLoads{{}, {lift}}, s.max_frames);
  EXPECT_LE(frames, s.max_frames) << s.model;
  const double error = relative(m->surface_displacement(), reference->surface_displacement());
  EXPECT_LT(error, s.tolerance) << s.model;
  EXPECT_LT(reactions_error(*m, *reference), s.tolerance) << s.model;
  EXPECT_LT((*reference->reaction_forces())[0].z(), 0);  // the tissue pulls the plate down
  RecordProperty(s.model + "_plate_frames", frames);
  RecordProperty(s.model + "_plate_relative_error", ::testing::PrintToString(error));
}

// Gravity on the cube and a grasp at the top centre lifted 3 mm, held: the grasp
// holds the coarse nodes nearest the grasped vertices; surface and forces as Newton's.
TEST_P(CoarseEmbeddedStepper, EqualsTheCoarseNewtonAnswerUnderAGraspAndGravity) {
  const CoarseStepper& s = GetParam();
  const LoadCase load_case{kBottom, {Load::body_force()}, {Tool::grasp({a / 2, a / 2, a}, 0.006)}};
  const FrameLoads loads{{Eigen::Vector3d(0, 0, -9.81)}, {Eigen::Vector3d(0, 0, 0.003)}};
  expect_settles_on_newtons_answer(s, load_case, loads, "grasp_gravity");
}

// 0.2 N spread over a 1 cm disc at the top centre, and the side x = a pushed 2 mm in
// by a sliding plate (its normal component held, the face free to slide along it).
TEST_P(CoarseEmbeddedStepper, EqualsTheCoarseNewtonAnswerUnderATractionAndASlidingPlate) {
  const CoarseStepper& s = GetParam();
  const LoadCase load_case{kBottom,
                           {Load::surface_traction({a / 2, a / 2, a}, 0.01)},
                           {Tool::plate({{a - 1e-9, -1, 0.005}, {1, 1, 1}}, true, 0)}};
  const FrameLoads loads{{Eigen::Vector3d(0, 0, 0.2)}, {Eigen::Vector3d(-0.002, 0, 0)}};
  const auto reference = expect_settles_on_newtons_answer(s, load_case, loads, "traction_sliding_plate");
  EXPECT_GT((*reference->reaction_forces())[0].x(), 0);  // the tissue pushes the plate back out
}

INSTANTIATE_TEST_SUITE_P(Steppers, CoarseEmbeddedStepper, ::testing::ValuesIn(coarse_steppers()),
                         [](const ::testing::TestParamInfo<CoarseStepper>& i) { return i.param.model; });

std::string setup_error(const std::string& model, const nlohmann::json& parameters, const HybridMesh& mesh) {
  try {
    set_up(model, parameters, LoadCase{kBottom, {Load::point_force({a / 2, a / 2, a})}, {}}, Points(), mesh);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "(accepted)";
}

TEST(CoarseEmbeddedSteppers, BadVolumesAreOneLineErrors) {
  HybridMesh no_coarse = embedded_cube();
  no_coarse.coarse_volume = TetMesh();
  const struct {
    std::string model;
    nlohmann::json parameters;
    const HybridMesh* mesh;
    std::string expected;
  } cases[] = {
      {"vbd", {{"volume", "coarse"}}, &embedded_cube(), "vbd.volume: 'coarse' is not one of"},
      {"vbd", {{"volume", "coarse_embedded"}}, &no_coarse, "vbd: the scenario provides no coarse volume"},
      {"xpbd_neo", {{"volume", "coarse_embedded"}}, &no_coarse, "xpbd_neo: the scenario provides no coarse volume"},
      {"pd", {{"volume", "coarse_embedded"}}, &no_coarse, "pd: the scenario provides no coarse volume"},
      // The fine volume is what the default asks for.
      {"pd", {}, &embedded_cube(), "pd: the scenario provides no fine volume mesh"},
      // A stepper's own errors name the model once on the coarse volume too.
      {"pd",
       {{"volume", "coarse_embedded"}, {"solve", "local_global"}},
       &embedded_cube(),
       "pd: solve local_global minimises the arap_volume law only"},
      {"vbd", {{"volume", "coarse_embedded"}, {"time_step", 0}}, &embedded_cube(), "vbd.time_step"},
  };
  for (const auto& c : cases) {
    const std::string what = setup_error(c.model, c.parameters, *c.mesh);
    EXPECT_EQ(what.rfind(c.expected, 0), 0u) << c.parameters.dump() << ": " << what;
    EXPECT_EQ(what.find('\n'), std::string::npos) << what;
    EXPECT_EQ(what.find(c.model + ": " + c.model + ":"), std::string::npos) << what;
  }
  EXPECT_EQ(setup_error("vbd", {{"volume", "coarse_embedded"}}, embedded_cube()), "(accepted)");
}

}  // namespace
}  // namespace tb
