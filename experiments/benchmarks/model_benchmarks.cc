// Google Benchmark of setup and per-frame cost (issues 4 and 5). Named arguments,
// counters (dofs, tets, vertices, constraints, solver iterations), milliseconds.
// Run: build/experiments/benchmarks/tissuebench_benchmarks --benchmark_out=FILE
//      --benchmark_out_format=json (scripts/benchmark does this).
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "cube_generator.h"
#include "elastic_body.h"
#include "elastic_solve.h"
#include "hybrid_builder.h"
#include "load_mapping.h"
#include "mesh_recipe.h"
#include "model.h"
#include "pbd_solver.h"
#include "scenario.h"

namespace tb {
namespace {

// Support and load as in experiments/scenarios/{cube,liver}-pull.json.
const SupportBox kCubeBottom{{-1, -1, -1e-9}, {1, 1, 1e-9}};
const SupportBox kLiverBottom{{-1, -1, -1}, {1, 1, -0.0101}};
const PointLoad kCubeLoad{{0, 0, 0.1}, {0, 0, 1}};
const PointLoad kLiverLoad{{-0.01731, 0.02453, 0.0253}, {0, 0, 0.1}};

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
  ElasticSolveOptions o;
  o.preconditioner = solver == 2 ? "two_level" : "ic";
  o.coarse_space = &h.coarse_volume;
  f.solve = make_elastic_solve(solver == 0 ? "direct" : "iterative", *f.body, o);
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
  const LoadStencil s = containing_tet(h.fine_volume, kCubeLoad.point, "fine volume");
  Eigen::VectorXd u;
  solver.solve(s, kCubeLoad.force, u);
  // The load changes every frame (a ramp), so a warm-started CG has work to do.
  int frame = 0;
  double iterations = 0;
  for (auto _ : state) {
    const double scale = 1.0 + 0.01 * (++frame % 50);
    solver.solve(s, scale * kCubeLoad.force, u);
    iterations += solver.last_iterations();
  }
  state.counters["dofs"] = static_cast<double>(3 * h.fine_volume.V.rows());
  state.counters["cg_iterations"] = benchmark::Counter(iterations, benchmark::Counter::kAvgIterations);
}

std::unique_ptr<Model> make_model(const std::string& name, const HybridMesh& mesh, const SupportBox& support,
                                  int iterations) {
  const ModelInfo& info = find_model(name);
  Problem p{&mesh, Material{}, support, resolve_parameters(info.parameters, {{"iterations", iterations}}, name)};
  auto m = info.create();
  m->setup(p);
  return m;
}

/// One frame of a dynamic model. range(0): 0 cube, 1 liver; range(1): iterations.
void dynamic_frame(benchmark::State& state, const std::string& model) {
  const bool liver = state.range(0) == 1;
  const HybridMesh& mesh = liver ? liver_mesh() : cube_mesh(1);
  auto m = make_model(model, mesh, liver ? kLiverBottom : kCubeBottom, static_cast<int>(state.range(1)));
  const PointLoad load = liver ? kLiverLoad : kCubeLoad;
  for (int f = 0; f < 200; ++f) m->step(load);  // measure near the steady state
  for (auto _ : state) m->step(load);
  state.counters["surface_vertices"] = static_cast<double>(mesh.fine_surface.V.rows());
  state.SetLabel(pbd::name(pbd::best_instruction_set()));  // the projection's vector instructions
}
void BM_PbdFrame(benchmark::State& state) { dynamic_frame(state, "pbd"); }
void BM_HybridFrame(benchmark::State& state) { dynamic_frame(state, "hybrid"); }

/// One PBD frame on the cube (10 iterations) with the projection on SSE2
/// (range(0) = 0) or AVX (1): what the run-time choice is worth.
void BM_PbdFrameInstructionSet(benchmark::State& state) {
  const pbd::InstructionSet isa = state.range(0) == 1 ? pbd::InstructionSet::Avx : pbd::InstructionSet::Sse2;
  if (isa == pbd::InstructionSet::Avx && pbd::best_instruction_set() != isa) {
    state.SkipWithError("this CPU has no AVX");
    return;
  }
  const SurfaceMesh& s = cube_mesh(1).fine_surface;
  pbd::Solver solver(s, pbd::inverse_masses(s, Material{}.density, kCubeBottom.select(s.V)), pbd::Settings{});
  solver.use_instruction_set(isa);
  const int load_vertex = nearest_vertex(s.V, kCubeLoad.point).nodes(0);
  const Points no_pins;
  for (int f = 0; f < 200; ++f) solver.step(load_vertex, kCubeLoad.force, {}, no_pins);
  for (auto _ : state) solver.step(load_vertex, kCubeLoad.force, {}, no_pins);
  state.SetLabel(pbd::name(isa));
}

/// The coarse FEM inside the hybrid alone: back-substitution on the coarse mesh.
void BM_HybridCoarseSolve(benchmark::State& state) {
  const HybridMesh& h = cube_mesh(1);
  const ElasticBody body(h.coarse_volume, Material{}, kCubeBottom.select(h.coarse_volume.V));
  auto coarse = make_elastic_solve("direct", body, {});
  const LoadStencil s = containing_tet(h.coarse_volume, kCubeLoad.point, "coarse volume");
  Eigen::VectorXd u;
  for (auto _ : state) coarse->solve(s, kCubeLoad.force, u);
  state.counters["dofs"] = static_cast<double>(3 * h.coarse_volume.V.rows());
}

/// PBD cost against surface size: range(0) divisions per cube side.
void BM_PbdFrameScaling(benchmark::State& state) {
  const HybridMesh& mesh = surface_only_cube(static_cast<int>(state.range(0)));
  auto m = make_model("pbd", mesh, kCubeBottom, 10);
  for (auto _ : state) m->step(kCubeLoad);
  state.counters["surface_vertices"] = static_cast<double>(mesh.fine_surface.V.rows());
  state.counters["ns_per_vertex"] =
      benchmark::Counter(static_cast<double>(mesh.fine_surface.V.rows()),
                         benchmark::Counter::kIsIterationInvariantRate | benchmark::Counter::kInvert);
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
BENCHMARK(BM_PbdFrameInstructionSet)->ArgName("avx")->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_HybridCoarseSolve)->Unit(benchmark::kMillisecond);
// 40 divisions: 9602 vertices; 129: 99 848 vertices.
BENCHMARK(BM_PbdFrameScaling)->ArgName("divisions")->Arg(10)->Arg(40)->Arg(129)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace tb

int main(int argc, char** argv) {
  tb::use_one_thread();  // single-threaded figures, as the runner's
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
