// The tissuebench command line: `run`, `mesh`, `models`, `export` (the problem
// package), `score`. Any failure prints one line naming the file and the problem
// and exits non-zero. Under `mpirun -np N`
// the ranks run the distributed FEM's cases together and share out the others,
// each case run and written by one rank (runner.h, RunOptions::processes); rank 0
// prints the summary of all.
#include <CLI/CLI.hpp>
#include <algorithm>
#include <filesystem>
#include <iostream>

#include "atomic_file.h"
#include "blas_kernels.h"
#include "build_info.h"
#include "calibration.h"
#include "elastic_body.h"
#include "mesh_recipe.h"
#include "model.h"
#include "mpi_session.h"
#include "observation_points.h"
#include "problem_package.h"
#include "runner.h"
#include "strict_json.h"
#include "submission_score.h"

namespace {

int command_models() {
  for (const auto& m : tb::registered_models()) {
    std::cout << m.name << (m.dynamic ? " (dynamic)" : " (static)") << ": " << m.description << "\n";
    std::cout << "  loads:";
    for (tb::LoadKind k : m.loads) std::cout << " " << tb::name(k);
    std::cout << "\n  tools:";
    for (tb::ToolKind k : m.tools) std::cout << " " << tb::name(k);
    if (m.tools.empty()) std::cout << " none";
    std::cout << (m.tools_how.empty() ? "" : " (" + m.tools_how + ")") << "\n";
    std::cout << "  reaction forces: " << (m.reactions.empty() ? "not measured" : m.reactions) << "\n";
    std::cout << "  interior probes: " << (m.probes.empty() ? "none (no volume)" : m.probes) << "\n";
    for (const auto& p : m.parameters) {
      std::cout << "  " << p.name << " = ";
      if (!p.is_choice())
        std::cout << p.default_number << " in [" << p.min << ", " << p.max << "]";
      else {
        std::cout << p.default_choice << " (one of";
        for (const auto& c : p.choices) std::cout << " " << c;
        std::cout << ")";
      }
      std::cout << ": " << p.description << "\n";
    }
  }
  return 0;
}

/// `--set KEY=VALUE` arguments as [[key, value], ...]: VALUE parsed as JSON (a
/// number, an array, true), else taken as a string.
nlohmann::json overrides_of(const std::vector<std::string>& settings) {
  nlohmann::json out = nlohmann::json::array();
  for (const std::string& s : settings) {
    const size_t eq = s.find('=');
    if (eq == std::string::npos || eq == 0)
      throw tb::ScenarioError("--set " + s + ": expected KEY=VALUE (e.g. frames.max=200)");
    const std::string text = s.substr(eq + 1);
    nlohmann::json value = nlohmann::json::parse(text, nullptr, false);
    if (value.is_discarded()) value = text;
    out.push_back({s.substr(0, eq), value});
  }
  return out;
}

/// Every rank's outcomes on rank 0, in the experiment's order (empty on the others).
std::vector<tb::CaseOutcome> all_outcomes(const tb::Experiment& e, std::vector<tb::CaseOutcome> mine) {
  if (tb::MpiSession::size() == 1) return mine;
  nlohmann::json list = nlohmann::json::array();
  for (const tb::CaseOutcome& o : mine)
    list.push_back({o.scenario, o.case_name, o.ok, o.error, o.frames, o.steady_frame});
  std::vector<tb::CaseOutcome> all;
  for (const std::string& rank : tb::MpiSession::gather_to_root(list.dump()))
    for (const nlohmann::json& j : nlohmann::json::parse(rank)) {
      tb::CaseOutcome o;
      o.scenario = j[0], o.case_name = j[1], o.ok = j[2], o.error = j[3], o.frames = j[4], o.steady_frame = j[5];
      all.push_back(o);
    }
  auto order = [&](const tb::CaseOutcome& o) {
    size_t index = 0;
    for (const tb::Scenario& s : e.scenarios)
      for (const tb::ModelRun& run : s.models) {
        if (s.name == o.scenario && run.case_name == o.case_name) return index;
        ++index;
      }
    return index;
  };
  std::stable_sort(all.begin(), all.end(), [&](const auto& a, const auto& b) { return order(a) < order(b); });
  return all;
}

}  // namespace

int main(int argc, char** argv) {
  tb::pin_blas_kernels(argv);      // the same FEM bits on every AVX2 CPU (blas_kernels.h)
  tb::MpiSession mpi(argc, argv);  // once per program; a singleton without mpirun
  const bool root = tb::MpiSession::rank() == 0;
  CLI::App app{"tissuebench: soft-tissue deformation models (fine FEM, PBD, hybrid) on shared scenarios"};
  app.require_subcommand(1);

  // Third-party data files ("data:..." in scenario files) are read from the data
  // directory (data_dir.h, README "Data").
  const std::string data_help =
      "data directory for the scenarios' data: files (default $TISSUEBENCH_DATA, else ../shared beside the "
      "repository; now " +
      tb::data_dir().path + ")";
  std::string data_dir_flag;

  auto* run = app.add_subcommand("run", "Run a scenario or an experiment file and write results");
  std::string scenario_file, out_dir = tb::RunOptions{}.out_dir, only;
  bool quiet = false, index_only = false;
  run->add_option("file", scenario_file, "scenario or experiment JSON")->required();
  run->add_option("--out", out_dir,
                  "results folder (default: " + out_dir +
                      "/ in the working folder; the committed results are regenerated with --out results)");
  run->add_option("--data-dir", data_dir_flag, data_help);
  run->add_flag("--index-only", index_only,
                "write <out>/<experiment>/experiment.json (cases, their order, roles, reference) and nothing else");
  run->add_option("--model", only, "run only this case or model name");
  std::string only_scenario;
  run->add_option("--scenario", only_scenario, "run only the scenario of this name");
  std::vector<std::string> skipped_scenarios;
  run->add_option("--skip-scenario", skipped_scenarios, "leave out the scenario of this name (repeatable)")
      ->allow_extra_args(false);
  std::vector<std::string> settings;
  run->add_option("--set", settings,
                  "KEY=VALUE: set a scenario key in every scenario (a dotted path, as a sweep factor's key, e.g. "
                  "frames.max=200 or models.vbd.parameters.iterations=5; VALUE read as JSON, else as a string); "
                  "repeatable; experiment.json records them")
      ->allow_extra_args(false);
  bool no_mesh_output = false;
  run->add_flag("--no-mesh-output", no_mesh_output, "do not write the built meshes beside the results");
  run->add_flag("--quiet", quiet, "no progress on stderr");
  std::string mesh_cache = tb::default_mesh_cache_dir();
  bool no_cache = false;
  run->add_option("--mesh-cache", mesh_cache,
                  "folder of the mesh cache (default $TISSUEBENCH_MESH_CACHE or ~/.cache/tissuebench/meshes)");
  run->add_flag("--no-mesh-cache", no_cache, "always build the meshes");
  double max_memory_gib = 0;
  run->add_option("--max-memory", max_memory_gib,
                  "GiB every case must fit, estimated before anything is built (default: the available memory; "
                  "-1: no check; docs/robustness.md)");

  auto* mesh = app.add_subcommand("mesh", "Build a hybrid mesh (paper section 1.2) and write it for ParaView");
  // Options left out keep the mesh recipe's defaults (parse_mesh_recipe), so
  // `mesh --cube` builds the cube of the paper scenarios.
  std::string surface, coarse, mesh_out, shape;
  bool cube = false, repair = false;
  double unit_scale = 1.0, max_volume = 0, quality = 0;
  int target = 0, resolution = 0;
  auto* surface_opt = mesh->add_option("--surface", surface, "closed triangle surface (.obj .off .stl .ply .vtu)");
  auto* cube_opt = mesh->add_flag("--cube", cube, "the paper's cube (10 x 10 x 12 divisions, side 0.1 m)");
  std::string shape_help = "a generated shape:";
  for (const auto& name : tb::shape_names()) shape_help += "\n  " + name + ": " + tb::shape_description(name);
  auto* shape_opt = mesh->add_option("--shape", shape, shape_help);
  auto* resolution_opt =
      mesh->add_option("--resolution", resolution,
                       "shape edge segments per 0.1 m (default " + std::to_string(tb::ShapeSpec{}.resolution) + ")");
  resolution_opt->needs(shape_opt);
  surface_opt->excludes(cube_opt);
  shape_opt->excludes(cube_opt)->excludes(surface_opt);
  mesh->add_option("--coarse", coarse, "given coarse tet volume (.msh .ele .vtu): embed the surface in it")
      ->needs(surface_opt);
  mesh->add_option("--unit-scale", unit_scale, "multiply file coordinates by this (0.01 for centimetres)")
      ->needs(surface_opt);
  mesh->add_flag("--repair-self-intersections", repair, "repair self-intersections with CGAL (reported)")
      ->needs(surface_opt);
  auto* max_volume_opt =
      mesh->add_option("--max-volume", max_volume, "fine TetGen volume bound, m^3 (0: none; default: the recipe's)");
  auto* quality_opt = mesh->add_option("--quality", quality, "fine TetGen radius-edge bound (-q)");
  auto* target_opt = mesh->add_option("--target-coarse-nodes", target, "coarse node count to aim for");
  int refine_levels = 0;
  mesh->add_option("--refine-levels", refine_levels, "split the surface's triangles in four this many times");
  mesh->add_option("--out", mesh_out, "output folder")->required();
  mesh->add_option("--data-dir", data_dir_flag, data_help + "; --surface and --coarse may be data:<path> references");

  auto* resolve = app.add_subcommand(
      "resolve",
      "Print a scenario or experiment file as the runner reads it: every scenario with every value resolved");
  std::string resolve_file;
  resolve->add_option("file", resolve_file, "scenario or experiment JSON")->required();
  resolve->add_option("--data-dir", data_dir_flag, data_help);

  // The problem package of the open benchmark (problem_package.h, docs/benchmark_format.md).
  auto* export_command = app.add_subcommand(
      "export",
      "Write each scenario's problem package (meshes, material, support, load and tool paths, observation "
      "points) for a simulator outside this tree: <out>/<scenario>/");
  std::string export_file, export_out, export_scenario;
  tb::ExportOptions export_options;
  bool export_quiet = false, export_no_cache = false;
  export_command->add_option("file", export_file, "scenario or experiment JSON (e.g. experiments/suite.json)")
      ->required();
  export_command->add_option("--out", export_out, "folder of the packages, one sub-folder per scenario")->required();
  export_command->add_option("--scenario", export_scenario, "only the scenario of this name or role");
  export_command->add_option("--data-dir", data_dir_flag, data_help);
  export_command->add_option(
      "--mesh-cache", mesh_cache,
      "folder of the mesh cache (default $TISSUEBENCH_MESH_CACHE or ~/.cache/tissuebench/meshes)");
  export_command->add_flag("--no-mesh-cache", export_no_cache, "always build the meshes");
  export_command->add_option("--observation-points", export_options.observation_points_dir,
                             "folder of the roles' observation points (default: the repository's " +
                                 export_options.observation_points_dir + ")");
  export_command->add_flag("--quiet", export_quiet, "no progress on stderr");

  // The open benchmark's scoring (submission.h, submission_score.h, calibration.h;
  // docs/benchmark_format.md "Submissions and scoring").
  auto* score_command = app.add_subcommand(
      "score", "Score a submission folder against its problem package: prints a summary, writes <submission>/score.json");
  std::string submission_dir, package_dir, answers_dir = tb::default_observation_points_dir(), calibration_value;
  score_command->add_option("submission", submission_dir, "the submission folder (submission.json, displacements.csv, "
                                                          "forces.csv if the scenario has tools)")->required();
  score_command->add_option("--package", package_dir, "the problem package folder (tissuebench export)")->required();
  score_command->add_option("--answers", answers_dir,
                            "folder of the converged answers, <role>.csv, <role>_interior.csv, <role>.json (default: "
                            "the repository's results/observation_points, now " + answers_dir + ")");
  score_command->add_option("--data-dir", data_dir_flag, data_help + "; the Truth Cube's bead table is read from it");
  score_command->add_option("--calibration", calibration_value,
                            "this machine's calibration figure: a number of ms, or a file holding calibrate's JSON "
                            "(default: run the calibration now, about 2 s)");
  auto* calibrate_command = app.add_subcommand(
      "calibrate", "Time a fixed tet-loop workload and print this machine's figure (ms) as JSON: what score "
                   "normalises self-reported times by");
  int calibration_repeats = 15;
  calibrate_command->add_option("--repeats", calibration_repeats, "timed repeats; the figure is their median")
      ->check(CLI::Range(1, 1000));

  app.add_subcommand("models", "List the registered models and their parameters");
  app.add_subcommand("build-info", "Print the build (commit, compiler, flags of each library) and machine as JSON");

  CLI11_PARSE(app, argc, argv);
  tb::use_one_thread();  // every reported time is single-threaded
  try {
    if (app.got_subcommand("models")) return root ? command_models() : 0;
    if (app.got_subcommand("build-info")) {
      if (!root) return 0;
      std::cout << tb::build_and_machine_info().dump(2) << "\n";
      return 0;
    }
    if (export_command->parsed()) {
      if (!root) return 0;  // one writer
      const tb::Experiment e = tb::load_experiment(export_file, tb::data_dir(data_dir_flag));
      export_options.out_dir = export_out;
      export_options.only_scenario = export_scenario;
      export_options.mesh_cache_dir = export_no_cache ? "" : mesh_cache;
      if (!export_quiet)
        export_options.progress = [](const std::string& line) { std::cerr << "tissuebench: " << line << "\n"; };
      const std::vector<std::string> written = tb::export_problem_packages(e, export_file, export_options);
      std::cerr << "tissuebench: " << written.size() << " problem package(s) written under " << export_out << "\n";
      return 0;
    }
    if (calibrate_command->parsed()) {
      if (!root) return 0;
      std::cout << tb::run_calibration(calibration_repeats).to_json().dump(2) << "\n";
      return 0;
    }
    if (score_command->parsed()) {
      if (!root) return 0;
      const tb::ProblemPackage package = tb::read_problem_package(package_dir);
      const tb::Submission submission = tb::read_submission(submission_dir, package);
      tb::ScoreOptions options{answers_dir, tb::data_dir(data_dir_flag), 0, nullptr};
      if (calibration_value.empty()) {
        const tb::Calibration calibration = tb::run_calibration();
        options.machine_figure_ms = calibration.figure_ms;
        options.machine = calibration.to_json();
      } else {
        options.machine_figure_ms = tb::calibration_figure(calibration_value);
        options.machine = {{"calibration", calibration_value}};
      }
      const nlohmann::json score = tb::score_submission(submission, package, options);
      const std::string written = (std::filesystem::path(submission_dir) / "score.json").string();
      tb::write_file_atomically(written, score.dump(2) + "\n");
      std::cout << tb::score_summary(score) << "  written: " << written << "\n";
      return 0;
    }
    if (resolve->parsed()) {
      if (!root) return 0;
      const tb::Experiment e = tb::load_experiment(resolve_file, tb::data_dir(data_dir_flag));
      nlohmann::json j = e.to_json();
      j["scenarios_resolved"] = nlohmann::json::array();
      for (const tb::Scenario& s : e.scenarios) j["scenarios_resolved"].push_back(s.to_json_with_models());
      std::cout << j.dump(2) << "\n";
      return 0;
    }
    if (run->parsed()) {
      tb::Experiment e = tb::load_experiment(scenario_file, tb::data_dir(data_dir_flag), overrides_of(settings));
      tb::leave_out_scenarios(e, skipped_scenarios);
      // A registered model the experiment does not run: scored on every scenario (docs/suite.md).
      if (!only.empty() && tb::add_model_everywhere(e, only) && root)
        std::cerr << "tissuebench: " << only << " is not a case of " << scenario_file
                  << ": running it, with its default parameters, on every scenario that takes it\n";
      tb::RunOptions opt;
      opt.out_dir = out_dir;
      opt.index_only = index_only;
      opt.only_case = only;
      opt.only_scenario = only_scenario;
      opt.write_meshes = !no_mesh_output;
      opt.progress = !quiet;  // every rank its own cases' lines
      opt.mesh_cache_dir = no_cache ? "" : mesh_cache;
      opt.max_memory_bytes = max_memory_gib < 0 ? -1 : max_memory_gib * (1ull << 30);
      opt.process = tb::MpiSession::rank();
      opt.processes = tb::MpiSession::size();
      if (opt.processes > 1) opt.barrier = [] { tb::MpiSession::barrier(); };
      opt.process_statistics = [] {  // every rank's peak memory in the case (build_info.h)
        const std::vector<double> peak = tb::MpiSession::all_gather(tb::peak_memory_since_reset_mib());
        double max = 0, sum = 0;
        for (double p : peak) max = std::max(max, p), sum += p;
        return nlohmann::json{{"ranks", peak.size()},
                              {"peak_rss_mib_per_rank", peak},
                              {"peak_rss_mib_max", max},
                              {"peak_rss_mib_sum", sum}};
      };
      const std::vector<tb::CaseOutcome> outcomes = all_outcomes(e, tb::run_experiment(e, opt));
      if (index_only) {
        if (root) std::cerr << "tissuebench: " << out_dir << "/" << e.name << "/experiment.json written\n";
        return 0;
      }
      if (!root) return 0;  // rank 0 reports every rank's cases
      int failed = 0;
      for (const auto& o : outcomes)
        if (!o.ok) {
          ++failed;
          std::cerr << "tissuebench: " << o.scenario << "/" << o.case_name << " failed: " << o.error << "\n";
        }
      if (outcomes.empty()) {
        std::cerr << "tissuebench: " << scenario_file << ": no case matches --model " << only << " --scenario "
                  << only_scenario << "\n";
        return 2;
      }
      std::cerr << "tissuebench: " << outcomes.size() - failed << " of " << outcomes.size() << " cases written under "
                << out_dir << "/" << e.name << "\n";
      return failed ? 1 : 0;
    }
    if (mesh->parsed()) {
      if (!root) return 0;  // one writer
      if (!cube && surface.empty() && shape.empty())
        throw std::invalid_argument("mesh: give --surface FILE, --cube or --shape NAME");
      nlohmann::json recipe;
      if (cube) {
        recipe = {{"type", "cube"}};
      } else if (!shape.empty()) {
        recipe = {{"type", "shape"}, {"shape", shape}};
        if (resolution_opt->count()) recipe["resolution"] = resolution;
      } else {
        auto file = [](const std::string& f) {
          return tb::is_data_reference(f) ? f : std::filesystem::absolute(f).string();
        };
        recipe = {{"type", "files"},
                  {"surface", file(surface)},
                  {"unit_scale", unit_scale},
                  {"repair_self_intersections", repair}};
        if (!coarse.empty()) recipe["coarse"] = file(coarse);
      }
      recipe["fine_tetgen"] = nlohmann::json::object();
      if (quality_opt->count()) recipe["fine_tetgen"]["radius_edge_ratio"] = quality;
      if (max_volume_opt->count()) recipe["fine_tetgen"]["max_volume"] = max_volume;
      if (target_opt->count()) recipe["coarse_selection"] = {{"target_nodes", target}};
      recipe["refine_levels"] = refine_levels;
      const tb::MeshRecipe r = tb::parse_mesh_recipe(recipe, ".", "mesh options", tb::data_dir(data_dir_flag));
      tb::MeshReport report;
      const tb::HybridMesh h = tb::build_mesh(r, report);
      tb::write_mesh_folder(mesh_out, h, report);
      std::cout << report.to_json(h).dump(2) << "\n";
      return 0;
    }
  } catch (const std::exception& e) {
    if (root) std::cerr << "tissuebench: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
