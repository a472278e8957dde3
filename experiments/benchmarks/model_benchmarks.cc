// Google Benchmark of setup and per-frame cost. Named arguments,
// counters (dofs, tets, vertices, constraints, solver iterations), milliseconds.
// Run: build/experiments/benchmarks/tissuebench_benchmarks --benchmark_out=FILE
//      --benchmark_out_format=json (scripts/benchmark does this).
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <map>
#include <memory>
#include <vector>

#include "blas_kernels.h"
#include "build_info.h"
#include "cube_generator.h"
#include "elastic_body.h"
#include "elastic_solve.h"
#include "hybrid_builder.h"
#include "load_mapping.h"
#include "mesh_recipe.h"
#include "model.h"
#include "pbd_solver.h"
#include "pd_solve.h"
#include "scenario.h"
#include "tetgen_driver.h"
#include "thread_team.h"
#include "vbd_solve.h"
#include "xpbd_tet_solve.h"

namespace tb {
namespace {

// Support and load as in experiments/scenarios/{cube,liver}-pull.json.
const SupportBox kCubeBottom{{-1, -1, -1e-9}, {1, 1, 1e-9}};
const SupportBox kLiverBottom{{-1, -1, -1}, {1, 1, -0.0101}};
/// A point force: where it acts (rest configuration) and its value.
struct PointForce {
  Eigen::Vector3d point, force;
  std::vector<Load> loads() const { return {Load::point_force(point)}; }
  FrameLoads frame() const { return frame_of(force); }
};
const PointForce kCubeLoad{{0, 0, 0.1}, {0, 0, 1}};
const PointForce kLiverLoad{{-0.01731, 0.02453, 0.0253}, {0, 0, 0.1}};

/// The mesh recipe of a committed scenario (experiments/scenarios/<name>.json).
MeshRecipe scenario_recipe(const std::string& name) {
  return load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/" + name + ".json").scenarios.at(0).mesh;
}

/// The paper's cube (cube-pull.json) with the fine TetGen volume bound divided by
/// `refinement` (1: the paper's ~3000 nodes; 4 and 16: about 4x and 16x more
/// tets). Cached.
const HybridMesh& cube_mesh(int refinement) {
  static std::map<int, std::unique_ptr<HybridMesh>> cache;
  auto& m = cache[refinement];
  if (!m) {
    MeshRecipe r = scenario_recipe("cube-pull");
    r.build.fine_tetgen.max_volume /= refinement;
    MeshReport report;
    m = std::make_unique<HybridMesh>(build_mesh(r, report));
  }
  return *m;
}

/// The liver of liver-pull.json, without its fine volume (not needed here).
const HybridMesh& liver_mesh() {
  static const HybridMesh h = [] {
    MeshRecipe r = scenario_recipe("liver-pull");
    r.build_fine_volume = false;
    MeshReport report;
    return build_mesh(r, report);
  }();
  return h;
}

/// A fine cube surface only (PBD needs no volume), n divisions per side.
const HybridMesh& surface_only_cube(int n) {
  static std::map<int, std::unique_ptr<HybridMesh>> cache;
  auto& m = cache[n];
  if (!m) {
    m = std::make_unique<HybridMesh>();
    m->fine_surface = make_cube_surface({0.1, 0.1, n, n, n});
  }
  return *m;
}

/// A cube of n divisions per side as a hybrid mesh built from its surface (paper
/// 1.2: TetGen without a volume bound, coverage selection aimed at
/// `coarse_nodes`). Cached.
const HybridMesh& scaled_cube(int n, int coarse_nodes) {
  static std::map<std::pair<int, int>, std::unique_ptr<HybridMesh>> cache;
  auto& m = cache[{n, coarse_nodes}];
  if (!m) {
    HybridBuildOptions o;
    o.fine_tetgen.radius_edge_ratio = 1.414;
    o.target_coarse_nodes = coarse_nodes;
    m = std::make_unique<HybridMesh>(build_hybrid_from_surface(make_cube_surface({0.1, 0.1, n, n, n}), o, "cube"));
  }
  return *m;
}

/// The paper cube's load with its force scaled by 682 / #V, so that the loaded
/// vertex (mass ~ 1 / #V) accelerates as on the paper's cube (682 vertices).
PointForce scaled_cube_load(const HybridMesh& mesh) {
  PointForce load = kCubeLoad;
  load.force *= 682.0 / static_cast<double>(mesh.fine_surface.V.rows());
  return load;
}

/// The fine-mesh body and the solve of benchmark argument "solver": 0 direct,
/// 1 CG with incomplete Cholesky, 2 CG with the two-level preconditioner on the
/// cube's coarse (hybrid) mesh.
struct FineSolver {
  std::unique_ptr<ElasticBody> body;
  std::unique_ptr<ElasticSolve> solve;
};
FineSolver fine_solver(const HybridMesh& h, int64_t solver) {
  FineSolver f;
  f.body = std::make_unique<ElasticBody>(h.fine_volume, Material{}, kCubeBottom.select(h.fine_volume.V));
  nlohmann::json given = {{"solver", solver == 0 ? "direct" : "iterative"}};
  if (solver != 0) given["preconditioner"] = solver == 2 ? "two_level" : "ic";
  f.solve = make_elastic_solve(
      *f.body, resolve_parameters(elastic_solve_parameters("", "direct", "ic"), given, "benchmark"), "",
      {&h.coarse_volume});
  return f;
}

void BM_FemSetup(benchmark::State& state) {
  const HybridMesh& h = cube_mesh(static_cast<int>(state.range(0)));
  double factor_nonzeros = 0;
  for (auto _ : state) {
    FineSolver solver = fine_solver(h, state.range(1));
    factor_nonzeros = solver.solve->report().value("factor_nonzeros", 0.0);
    benchmark::DoNotOptimize(solver.solve.get());
  }
  if (factor_nonzeros > 0) state.counters["factor_MiB"] = factor_nonzeros * 8 / (1024.0 * 1024.0);
  state.counters["dofs"] = static_cast<double>(3 * h.fine_volume.V.rows());
  state.counters["tets"] = static_cast<double>(h.fine_volume.T.rows());
}

void BM_FemFrame(benchmark::State& state) {
  const HybridMesh& h = cube_mesh(static_cast<int>(state.range(0)));
  FineSolver fine = fine_solver(h, state.range(1));
  ElasticSolve& solver = *fine.solve;
  const BodyLoads loads(*fine.body, {containing_tet(h.fine_volume, kCubeLoad.point, "fine volume")});
  std::vector<Eigen::Vector3d> values = {kCubeLoad.force};
  Eigen::VectorXd u;
  solver.solve(loads, values, u);
  // The load changes every frame (a ramp), so a warm-started CG has work to do.
  int frame = 0;
  double iterations = 0;
  for (auto _ : state) {
    values[0] = (1.0 + 0.01 * (++frame % 50)) * kCubeLoad.force;
    solver.solve(loads, values, u);
    iterations += solver.last_iterations();
  }
  state.counters["dofs"] = static_cast<double>(3 * h.fine_volume.V.rows());
  state.counters["cg_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}

std::unique_ptr<Model> make_model(const std::string& name, const HybridMesh& mesh, const SupportBox& support,
                                  const std::vector<Load>& loads, int iterations,
                                  nlohmann::json parameters = nlohmann::json::object()) {
  const ModelInfo& info = find_model(name);
  for (const ParameterSpec& spec : info.parameters)  // PBD iterations, for the models that have them
    if (spec.name == "iterations") parameters["iterations"] = iterations;
  Problem p{&mesh, Material{}, LoadCase{support, loads, {}}, resolve_parameters(info.parameters, parameters, name), Points()};
  auto m = info.create();
  m->setup(p);
  return m;
}

/// One frame of a model (after 200, near a dynamic model's steady state).
/// range(0): 0 cube, 1 liver; range(1): PBD iterations (ignored by models without).
void model_frame(benchmark::State& state, const std::string& model) {
  const bool liver = state.range(0) == 1;
  const HybridMesh& mesh = liver ? liver_mesh() : cube_mesh(1);
  const PointForce& load = liver ? kLiverLoad : kCubeLoad;
  auto m = make_model(model, mesh, liver ? kLiverBottom : kCubeBottom, load.loads(), static_cast<int>(state.range(1)));
  const FrameLoads frame = load.frame();
  for (int f = 0; f < 200; ++f) m->step(frame);  // measure near the steady state
  for (auto _ : state) m->step(frame);
  state.counters["surface_vertices"] = static_cast<double>(mesh.fine_surface.V.rows());
  state.SetLabel(pbd::name(pbd::best_instruction_set()));  // the projection's vector instructions
}
void BM_PbdFrame(benchmark::State& state) { model_frame(state, "pbd"); }
void BM_HybridFrame(benchmark::State& state) { model_frame(state, "hybrid"); }
void BM_CondensedFrame(benchmark::State& state) { model_frame(state, "condensed"); }
void BM_EmbeddedFrame(benchmark::State& state) { model_frame(state, "embedded"); }

/// What a tool or a wide load costs a frame against the paper's point force, in
/// pairs within one benchmark so the VM's drift hits both alike: each iteration
/// steps the model once with the point force alone and once with range(1) = 1 a
/// grasp (5 mm radius at the top, lifted), 2 a bonded plate on a side, 3 gravity
/// added. range(0): 0 fem (direct), 1 embedded, 2 pbd, 3 hybrid, 4 condensed. Counters: each
/// one's ms per frame and their ratio; the iteration time is the second one's.
void BM_FrameWithToolOrLoad(benchmark::State& state) {
  const char* names[] = {"fem", "embedded", "pbd", "hybrid", "condensed"};
  const std::string model = names[state.range(0)];
  const HybridMesh& mesh = cube_mesh(1);
  const ModelInfo& info = find_model(model);
  const auto parameters = [&] {
    nlohmann::json p = nlohmann::json::object();
    for (const ParameterSpec& spec : info.parameters)
      if (spec.name == "iterations") p["iterations"] = 10;
    return resolve_parameters(info.parameters, p, model);
  }();
  LoadCase base{kCubeBottom, kCubeLoad.loads(), {}}, with = base;
  FrameLoads f_base = kCubeLoad.frame(), f_with = f_base;
  if (state.range(1) == 1) {
    with.tools.push_back(Tool::grasp({0.02, 0.02, 0.1}, 0.005));
    f_with.tool_values.push_back({0, 0, 0.002});
  } else if (state.range(1) == 2) {
    with.tools.push_back(Tool::plate({{-1, 0.0499, 0.03}, {1, 1, 0.07}}, false));
    f_with.tool_values.push_back({0, -0.001, 0});
  } else {
    with.loads.push_back(Load::body_force());
    f_with.values.push_back({0, 0, -9.81});
  }
  std::unique_ptr<Model> models[2] = {info.create(), info.create()};
  models[0]->setup(Problem{&mesh, Material{}, base, parameters, Points()});
  models[1]->setup(Problem{&mesh, Material{}, with, parameters, Points()});
  const FrameLoads* frames[2] = {&f_base, &f_with};
  for (int f = 0; f < 200; ++f)
    for (int k = 0; k < 2; ++k) models[k]->step(*frames[k]);
  using Clock = std::chrono::steady_clock;
  double seconds[2] = {0, 0};
  for (auto _ : state)
    for (int k = 0; k < 2; ++k) {
      const auto a = Clock::now();
      models[k]->step(*frames[k]);
      const double s = std::chrono::duration<double>(Clock::now() - a).count();
      seconds[k] += s;
      if (k == 1) state.SetIterationTime(s);
    }
  state.counters["point_force_ms"] = benchmark::Counter(1e3 * seconds[0], benchmark::Counter::kAvgIterations);
  state.counters["with_ms"] = benchmark::Counter(1e3 * seconds[1], benchmark::Counter::kAvgIterations);
  state.counters["ratio"] = seconds[0] > 0 ? seconds[1] / seconds[0] : 0;
  state.SetLabel(model + (state.range(1) == 1 ? " grasp" : state.range(1) == 2 ? " plate" : " gravity"));
}

/// The condensed model's precomputation (a back-solve per loadable surface dof) and
/// the memory of its response matrix. range(0): 0 cube, 1 liver (needs a fine volume).
void BM_CondensedSetup(benchmark::State& state) {
  const bool liver = state.range(0) == 1;
  const HybridMesh& mesh = liver ? liver_mesh() : cube_mesh(1);
  nlohmann::json report;
  for (auto _ : state) {
    const PointForce& load = liver ? kLiverLoad : kCubeLoad;
    auto m = make_model("condensed", mesh, liver ? kLiverBottom : kCubeBottom, load.loads(), 10);
    m->step(load.frame());
    report = m->report();
  }
  state.counters["response_MiB"] = report.value("response_memory_mib", 0.0);
  state.counters["surface_vertices"] = static_cast<double>(mesh.fine_surface.V.rows());
}

/// One PBD frame (10 iterations) with the projection on range(0) = 0 SSE2, 1 AVX,
/// 2 AVX-512, in range(1) = 0 double, 1 single precision, on range(2) = 0 the
/// paper's cube, else a cube of that many divisions per side: what the run-time
/// choice and the precision are worth.
void BM_PbdFrameInstructionSet(benchmark::State& state) {
  const auto isa = static_cast<pbd::InstructionSet>(state.range(0));
  if (!pbd::cpu_supports(isa)) {
    state.SkipWithError((std::string("this CPU has no ") + pbd::name(isa)).c_str());
    return;
  }
  const HybridMesh& mesh = state.range(2) == 0 ? cube_mesh(1) : surface_only_cube(static_cast<int>(state.range(2)));
  const SurfaceMesh& s = mesh.fine_surface;
  pbd::Settings settings;
  settings.precision = state.range(1) == 1 ? pbd::Precision::Single : pbd::Precision::Double;
  pbd::Solver solver(s, pbd::inverse_masses(s, Material{}.density, kCubeBottom.select(s.V)), settings);
  solver.use_instruction_set(isa);
  solver.set_loads({nearest_vertex(s.V, kCubeLoad.point)});
  const std::vector<Eigen::Vector3d> force = {scaled_cube_load(mesh).force};
  const Points no_pins;
  for (int f = 0; f < 200; ++f) solver.step(force, {}, no_pins);
  for (auto _ : state) solver.step(force, {}, no_pins);
  state.counters["surface_vertices"] = static_cast<double>(s.V.rows());
  state.SetLabel(std::string(pbd::name(isa)) + " " + pbd::name(settings.precision));
}

/// The coarse FEM inside the hybrid alone: back-substitution on the coarse mesh.
void BM_HybridCoarseSolve(benchmark::State& state) {
  const HybridMesh& h = cube_mesh(1);
  const ElasticBody body(h.coarse_volume, Material{}, kCubeBottom.select(h.coarse_volume.V));
  auto coarse = make_direct_solve(body);
  const BodyLoads loads(body, {containing_tet(h.coarse_volume, kCubeLoad.point, "coarse volume")});
  const std::vector<Eigen::Vector3d> values = {kCubeLoad.force};
  Eigen::VectorXd u;
  for (auto _ : state) coarse->solve(loads, values, u);
  state.counters["dofs"] = static_cast<double>(3 * h.coarse_volume.V.rows());
}

/// PBD cost against surface size: range(0) divisions per cube side, range(1)
/// threads sweeping each colour, range(2) 1 for a single-precision sweep, range(3)
/// the sweep's spatial domains (pbd parameter domains).
void BM_PbdFrameScaling(benchmark::State& state) {
  const HybridMesh& mesh = surface_only_cube(static_cast<int>(state.range(0)));
  const PointForce load = scaled_cube_load(mesh);
  auto m = make_model(
      "pbd", mesh, kCubeBottom, load.loads(), 10,
      {{"threads", state.range(1)}, {"precision", state.range(2) ? "single" : "double"}, {"domains", state.range(3)}});
  const FrameLoads frame = load.frame();
  for (int f = 0; f < 20; ++f) m->step(frame);
  for (auto _ : state) m->step(frame);
  state.counters["surface_vertices"] = static_cast<double>(mesh.fine_surface.V.rows());
  state.counters["ns_per_vertex"] =
      benchmark::Counter(static_cast<double>(mesh.fine_surface.V.rows()),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
  state.SetLabel(m->report()["instruction_set"].get<std::string>() + " " + m->report()["precision"].get<std::string>());
}

/// The hybrid end to end at scale: range(0) divisions per cube side (40: 9602
/// surface vertices, 129: 99 848), range(1) the coarse selection's target (150,
/// 1500 nodes), range(2) threads, range(3) 1 for a single-precision sweep, range(4)
/// the sweep's spatial domains. Counters: the mean time of each named phase of a
/// frame (Model::last_phase_times), ms.
void BM_HybridFrameScaling(benchmark::State& state) {
  const HybridMesh& mesh = scaled_cube(static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  const PointForce load = scaled_cube_load(mesh);
  auto m = make_model(
      "hybrid", mesh, kCubeBottom, load.loads(), 10,
      {{"threads", state.range(2)}, {"precision", state.range(3) ? "single" : "double"}, {"domains", state.range(4)}});
  const FrameLoads frame = load.frame();
  for (int f = 0; f < 20; ++f) m->step(frame);
  std::vector<double> phase_ms(m->last_phase_times().size(), 0.0);
  for (auto _ : state) {
    m->step(frame);
    for (size_t k = 0; k < phase_ms.size(); ++k) phase_ms[k] += m->last_phase_times()[k].ms;
  }
  for (size_t k = 0; k < phase_ms.size(); ++k)
    state.counters[std::string(m->last_phase_times()[k].name) + "_ms"] =
        benchmark::Counter(phase_ms[k], benchmark::Counter::kAvgIterations);
  state.counters["surface_vertices"] = static_cast<double>(mesh.fine_surface.V.rows());
  state.counters["coarse_nodes"] = static_cast<double>(mesh.coarse_volume.V.rows());
  state.SetLabel(m->report()["instruction_set"].get<std::string>() + " " + m->report()["precision"].get<std::string>());
}

/// The SIMD kernels against the scalar reference (reference_projections.h) on the
/// same frames: each iteration steps a reference solver and a SIMD solver once
/// (same state, same order), timed in pairs, so the VM's drift hits both alike.
/// range(0): divisions per cube side. Counters: each one's ms per frame and the
/// speed-up; the iteration time is the SIMD frame's.
void BM_PbdKernelSpeedup(benchmark::State& state) {
  const HybridMesh& mesh = surface_only_cube(static_cast<int>(state.range(0)));
  const SurfaceMesh& s = mesh.fine_surface;
  const Eigen::VectorXd w = pbd::inverse_masses(s, Material{}.density, kCubeBottom.select(s.V));
  pbd::Settings reference_settings;
  reference_settings.kernels = pbd::Kernels::Reference;
  pbd::Solver simd(s, w, pbd::Settings{}), reference(s, w, reference_settings);
  for (pbd::Solver* solver : {&simd, &reference}) solver->set_loads({nearest_vertex(s.V, kCubeLoad.point)});
  const std::vector<Eigen::Vector3d> force = {scaled_cube_load(mesh).force};
  const Points no_pins;
  using Clock = std::chrono::steady_clock;
  double simd_s = 0, reference_s = 0;
  for (auto _ : state) {
    const auto a = Clock::now();
    reference.step(force, {}, no_pins);
    const auto b = Clock::now();
    simd.step(force, {}, no_pins);
    const auto c = Clock::now();
    reference_s += std::chrono::duration<double>(b - a).count();
    simd_s += std::chrono::duration<double>(c - b).count();
    state.SetIterationTime(std::chrono::duration<double>(c - b).count());
  }
  state.counters["reference_ms"] = benchmark::Counter(1e3 * reference_s, benchmark::Counter::kAvgIterations);
  state.counters["simd_ms"] = benchmark::Counter(1e3 * simd_s, benchmark::Counter::kAvgIterations);
  state.counters["speedup"] = simd_s > 0 ? reference_s / simd_s : 0;
  state.counters["surface_vertices"] = static_cast<double>(s.V.rows());
  state.SetLabel(pbd::name(simd.instruction_set()));
}

/// XPBD against PBD on the paper's cube, 10 iterations, 200 frames
/// in: each benchmark iteration steps three models of one kind (range(0): 0 pbd,
/// 1 hybrid) once each, PBD with the SIMD kernels, PBD with the scalar reference
/// kernels and XPBD (reference kernels, the only ones it has), timed in triples so
/// the VM's drift hits all alike. Counters: each one's ms per frame; the iteration
/// time is XPBD's.
void BM_XpbdFrame(benchmark::State& state) {
  const std::string kind = state.range(0) == 0 ? "pbd" : "hybrid";
  const HybridMesh& mesh = cube_mesh(1);
  const std::vector<Load> loads = kCubeLoad.loads();
  std::unique_ptr<Model> models[3] = {
      make_model(kind, mesh, kCubeBottom, loads, 10),
      make_model(kind, mesh, kCubeBottom, loads, 10, {{"kernels", "reference"}}),
      make_model(kind, mesh, kCubeBottom, loads, 10,
                 {{"kernels", "reference"}, {"constraint_solve", "xpbd"}, {"bending_angle", "signed"}})};
  const FrameLoads frame = kCubeLoad.frame();
  for (int f = 0; f < 200; ++f)
    for (auto& m : models) m->step(frame);
  using Clock = std::chrono::steady_clock;
  double seconds[3] = {0, 0, 0};
  for (auto _ : state) {
    for (int k = 0; k < 3; ++k) {
      const auto a = Clock::now();
      models[k]->step(frame);
      seconds[k] += std::chrono::duration<double>(Clock::now() - a).count();
      if (k == 2) state.SetIterationTime(std::chrono::duration<double>(Clock::now() - a).count());
    }
  }
  const char* names[3] = {"pbd_simd_ms", "pbd_reference_ms", "xpbd_ms"};
  for (int k = 0; k < 3; ++k)
    state.counters[names[k]] = benchmark::Counter(1e3 * seconds[k], benchmark::Counter::kAvgIterations);
  state.SetLabel(kind);
}

/// What a barrier of the PBD sweep's thread team costs: range(0) members meeting
/// 1000 times per iteration, with no work between. Time per barrier = iteration
/// time / 1000.
void BM_ThreadTeamBarrier(benchmark::State& state) {
  pbd::ThreadTeam team(static_cast<int>(state.range(0)));
  auto task = [&team](int) {
    for (int i = 0; i < 1000; ++i) team.barrier();
  };
  for (auto _ : state) team.run(task);
  state.counters["ns_per_barrier"] =
      benchmark::Counter(1000, benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
}

/// The cube_mesh(refinement) fine volume as TetGen numbers it (its Steiner points in
/// insertion order), before the hybrid builder stores it along a Z curve
/// (volume_ordering.h): what the builder's order is measured against. Cached.
const TetMesh& cube_volume_in_tetgen_order(int refinement) {
  static std::map<int, std::unique_ptr<TetMesh>> cache;
  auto& m = cache[refinement];
  if (!m) {
    MeshRecipe r = scenario_recipe("cube-pull");
    r.build.fine_tetgen.max_volume /= refinement;
    m = std::make_unique<TetMesh>(tetrahedralize_surface(cube_mesh(refinement).fine_surface, r.build.fine_tetgen, "cube"));
  }
  return *m;
}

/// A frame of a real-time nonlinear stepper on the paper cube's fine volume
/// (refinement range(1): 1 the paper's ~17 800 tets, 6 about 100 000), the 1 N pull
/// at the top centre: range(0) 0 VBD (neo_hookean), 1 XPBD (xpbd_neo_hookean), 2 PD
/// quasi_newton (neo_hookean), 3 PD local_global (arap_volume) or 4 VBD with its scalar
/// kernels (one tet at a time: 0 takes four at a time in vector lanes), on range(2)
/// threads, range(3) sweeps (VBD), sub-steps (XPBD) or iterations (PD, all run) a frame; time_step
/// 0.01 s (XPBD with one sub-step: 0.001 s, the configuration whose settled error
/// docs/realtime_nonlinear.md tables); range(4) zorder: 1 the volume as the hybrid
/// builder stores it (along a Z curve), 0 in TetGen's own order. Frames continue the
/// same run (the transient). Wall time: the second thread works.
void BM_NonlinearStepperFrame(benchmark::State& state) {
  const HybridMesh& h = cube_mesh(static_cast<int>(state.range(1)));
  const TetMesh& volume = state.range(4) ? h.fine_volume : cube_volume_in_tetgen_order(static_cast<int>(state.range(1)));
  const ElasticBody body(volume, Material{}, kCubeBottom.select(volume.V));
  const BodyLoads loads(body, {containing_tet(volume, kCubeLoad.point, "fine volume")});
  std::unique_ptr<ElasticSolve> solve;
  const int threads = static_cast<int>(state.range(2));
  const int work = static_cast<int>(state.range(3));
  if (state.range(0) == 0 || state.range(0) == 4) {
    VbdSettings o;
    o.stepping.threads = threads;
    o.iterations = work;
    if (state.range(0) == 4) o.kernels = VbdKernels::Scalar;
    solve = make_vbd_solve(body, o);
  } else if (state.range(0) >= 2) {  // pd: 2 quasi_newton (neo_hookean), 3 local_global (arap_volume)
    PdSettings o;
    o.stepping.threads = threads;
    o.iterations = work;
    o.tolerance = 0;  // every iteration runs: the cost of `work` of them
    if (state.range(0) == 3) {
      o.mode = PdMode::LocalGlobal;
      o.law = "arap_volume";
    }
    solve = make_pd_solve(body, o);
  } else {
    XpbdTetSettings o;
    o.stepping.threads = threads;
    o.substeps = work;
    if (work == 1) o.stepping.time_step = 0.001;
    solve = make_xpbd_tet_solve(body, o);
  }
  ElasticFrame frame(body, loads, *solve);
  const std::vector<Eigen::Vector3d> values = {kCubeLoad.force};
  Eigen::VectorXd u;
  frame.step(values, {}, u);
  // Each frame's wall time too: the median and p95 frame (counters p50_ms, p95_ms)
  // are what the runner reports, and on a VM whose other tenants steal the CPU in
  // bursts the median frame moves less between runs than the mean of the loop.
  std::vector<double> frame_ms;
  frame_ms.reserve(100000);
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    frame.step(values, {}, u);
    if (frame_ms.size() < frame_ms.capacity())
      frame_ms.push_back(std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start).count());
  }
  std::sort(frame_ms.begin(), frame_ms.end());
  state.counters["p50_ms"] = frame_ms[frame_ms.size() / 2];
  state.counters["p95_ms"] = frame_ms[frame_ms.size() * 95 / 100];
  state.counters["tets"] = static_cast<double>(h.fine_volume.T.rows());
  state.counters["nodes"] = static_cast<double>(h.fine_volume.V.rows());
}

BENCHMARK(BM_FemSetup)
    ->ArgNames({"refine", "solver"})
    ->ArgsProduct({{1, 4, 16}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(3);
BENCHMARK(BM_FemFrame)
    ->ArgNames({"refine", "solver"})
    ->ArgsProduct({{1, 4, 16}, {0, 1, 2}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PbdFrame)
    ->ArgNames({"liver", "iterations"})
    ->ArgsProduct({{0, 1}, {5, 10, 20}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HybridFrame)
    ->ArgNames({"liver", "iterations"})
    ->ArgsProduct({{0, 1}, {5, 10, 20}})
    ->Unit(benchmark::kMillisecond);
// The benchmarks' liver has no fine volume (the condensed model needs one): cube only.
BENCHMARK(BM_CondensedFrame)->ArgNames({"liver", "iterations"})->Args({0, 10});
BENCHMARK(BM_EmbeddedFrame)->ArgNames({"liver", "iterations"})->ArgsProduct({{0, 1}, {10}});
BENCHMARK(BM_FrameWithToolOrLoad)
    ->ArgNames({"model", "with"})
    ->ArgsProduct({{0, 1, 2, 3, 4}, {1, 2, 3}})
    ->UseManualTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_CondensedSetup)->ArgName("liver")->Arg(0)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PbdFrameInstructionSet)
    ->ArgNames({"isa", "single", "divisions"})
    ->ArgsProduct({{0, 1, 2, 3}, {0, 1}, {0, 40}})
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HybridCoarseSolve)->Unit(benchmark::kMillisecond);
// 10 divisions: 602 vertices; 20: 2402; 40: 9602; 82: 40 346; 129: 99 848.
// Wall time (UseRealTime) wherever a second thread may work.
BENCHMARK(BM_PbdFrameScaling)
    ->ArgNames({"divisions", "threads", "single", "domains"})
    ->ArgsProduct({{10, 20, 40, 82, 129}, {1, 2}, {0, 1}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HybridFrameScaling)
    ->ArgNames({"divisions", "coarse", "threads", "single", "domains"})
    ->ArgsProduct({{40, 82, 129}, {150, 1500}, {1, 2}, {0, 1}, {1, 2}})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PbdKernelSpeedup)->ArgName("divisions")->Arg(10)->Arg(40)->UseManualTime()->Unit(benchmark::kMillisecond);
BENCHMARK(BM_XpbdFrame)->ArgName("hybrid")->Arg(0)->Arg(1)->UseManualTime()->Unit(benchmark::kMillisecond);
// The real-time question: a frame of one sweep (VBD) or one 1 ms sub-step
// (XPBD) against the tet count (refine 1, 2, 4, 6: the slope of cost in tets) and
// the threads; and the default 20, which the study's error table pairs with.
BENCHMARK(BM_NonlinearStepperFrame)
    // zorder 0: the same frames on TetGen's node order, against the builder's (1).
    ->ArgNames({"xpbd", "refine", "threads", "work", "zorder"})
    ->ArgsProduct({{0, 1}, {1, 2, 4, 6}, {1, 2}, {1}, {1}})
    ->ArgsProduct({{0, 1}, {1, 6}, {1, 2}, {1, 20}, {0}})
    ->ArgsProduct({{0, 1}, {1, 6}, {1, 2}, {20}, {1}})
    ->ArgsProduct({{2, 3}, {1}, {1, 2}, {1, 10}, {1}})
    ->ArgsProduct({{4}, {1, 6}, {1, 2}, {1, 20}, {1}})  // VBD's scalar kernels beside its lanes (0)
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ThreadTeamBarrier)->ArgName("members")->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);

}  // namespace
}  // namespace tb

int main(int argc, char** argv) {
  tb::pin_blas_kernels(argv);  // the runner's BLAS kernels (blas_kernels.h)
  tb::use_one_thread();  // single-threaded figures, as the runner's
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  // The machine and build of tissuebench's code, as in every run.json (the
  // context's library_build_type is Google Benchmark's own library).
  const nlohmann::json build = tb::build_and_machine_info();
  for (const char* key : {"cpu_model", "build_type", "compiler", "git_commit", "blas_core"})
    benchmark::AddCustomContext(std::string("tissuebench_") + key, build.value(key, std::string("?")));
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
