// The runner loop, narrated:
//  1. Meshes: each scenario's mesh recipe is built once per process and shared by
//     every scenario with the same recipe (cube pull and push share one), and
//     kept in a disk cache keyed by its content hash, so a rerun does not re-mesh.
//  2. Setup: the model is created from the registry and set up; timed on its own.
//     Steps 2 and 3's frame itself are case_run.h's CaseRun, which the Python module
//     steps too (python/run_binding.cc); this file records and writes around it.
//  3. Frames: the load of the frame (ramped, then constant) is applied by step();
//     only step() is inside the timed region. After each frame the surface
//     displacement is checked for divergence (NaN/Inf, or beyond a bound).
//     Dynamic models stop at the steady state: max per-vertex change in a frame
//     <= steady_tolerance x max displacement. Static models run `static` frames,
//     which are the timing samples of the per-frame solve.
//  4. Output: written into a temporary folder, run.json last, then renamed into
//     place (staged_folder.h), so a killed or failed run leaves the previous result
//     intact: a case folder is complete or absent (docs/robustness.md).
#include "runner.h"

#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <map>
#include <memory>
#include <sstream>

#include "atomic_file.h"
#include "build_info.h"
#include "case_run.h"
#include "mesh_io.h"
#include "progress_notice.h"
#include "resource_limits.h"
#include "sphere_guard.h"
#include "staged_folder.h"

namespace tb {
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

TimingStats timing_stats(std::vector<double> s) {
  TimingStats t;
  t.count = static_cast<int>(s.size());
  if (s.empty()) return t;
  std::sort(s.begin(), s.end());
  auto quantile = [&](double q) {  // linear interpolation between order statistics
    const double pos = q * static_cast<double>(s.size() - 1);
    const size_t lo = static_cast<size_t>(std::floor(pos));
    const size_t hi = std::min(lo + 1, s.size() - 1);
    return s[lo] + (pos - static_cast<double>(lo)) * (s[hi] - s[lo]);
  };
  t.median = quantile(0.5);
  t.p95 = quantile(0.95);
  double sum = 0;
  for (double x : s) sum += x;
  t.mean = sum / static_cast<double>(s.size());
  t.min = s.front();
  t.max = s.back();
  return t;
}

std::vector<int> observed_vertices(const Scenario& s, const Points& V) {
  std::vector<int> out;
  const double top = V.col(2).maxCoeff();
  for (Eigen::Index v = 0; v < V.rows(); ++v)
    if (s.observed == "all" || std::abs(V(v, 2) - top) <= s.top_tolerance) out.push_back(static_cast<int>(v));
  return out;
}

namespace {

nlohmann::json to_json(const TimingStats& t) {
  return {{"median_ms", t.median}, {"p95_ms", t.p95}, {"mean_ms", t.mean},
          {"min_ms", t.min},       {"max_ms", t.max}, {"count", t.count}};
}

/// Progress on stderr: one updating line on a terminal, plain lines otherwise.
class Progress {
 public:
  /// `prefix` starts every line ("rank 1: " under mpirun, whose ranks share a
  /// terminal: plain lines then, not one updating line).
  Progress(bool enabled, std::string prefix)
      : enabled_(enabled), tty_(prefix.empty() && isatty(STDERR_FILENO)), prefix_(std::move(prefix)) {}
  void update(const std::string& label, int frame, int budget, double elapsed_s, bool force = false) {
    if (!enabled_) return;
    const auto now = Clock::now();
    if (!force && now - last_ < std::chrono::milliseconds(tty_ ? 200 : 2000)) return;
    last_ = now;
    const double rate = elapsed_s > 0 ? frame / elapsed_s : 0;
    std::ostringstream os;
    os << prefix_ << label << ": frame " << frame << "/" << budget << std::fixed << std::setprecision(0) << ", " << rate
       << " frames/s";
    if (rate > 0 && frame < budget) os << ", at most " << std::setprecision(1) << (budget - frame) / rate << " s left";
    if (tty_)
      std::cerr << "\r\033[K" << os.str() << std::flush;
    else
      std::cerr << os.str() << "\n";
  }
  void line(const std::string& text) {
    if (!enabled_) return;
    if (tty_) std::cerr << "\r\033[K";
    std::cerr << prefix_ << text << "\n";
  }

 private:
  bool enabled_, tty_;
  std::string prefix_;
  Clock::time_point last_{};
};

/// The vertex of `observed` (not empty) nearest `p`, the first of equals.
int nearest_observed(const std::vector<int>& observed, const Points& V, const Eigen::Vector3d& p) {
  int best = observed.front();
  for (int v : observed)
    if ((V.row(v).transpose() - p).squaredNorm() < (V.row(best).transpose() - p).squaredNorm()) best = v;
  return best;
}

/// Geometry read from a third-party file (a scenario's data: mesh, README "Data") is
/// not copied into the case's CSVs: they give the displacement by surface vertex
/// index alone, and run.json names the observed vertex nearest the load point (what
/// the analysis would otherwise find from the coordinates). surface.vtu, the field a
/// researcher opens in ParaView, still holds the deformed surface; result trees
/// commit it only for the project's own geometry (.gitignore, tests/analysis/
/// test_third_party_geometry.py).
bool geometry_from_data(const Scenario& s) {
  return !s.mesh.surface_reference.empty() || !s.mesh.coarse_reference.empty();
}

/// The surface vertices whose every frame a dynamic case records (trajectory.csv):
/// the observed vertex nearest each point where a load or a grasp or sphere acts,
/// then at most kTrackedSpread observed vertices evenly spread through their list.
constexpr int kTrackedSpread = 8;
std::vector<int> tracked_vertices(const Scenario& s, const Points& V) {
  const std::vector<int> observed = observed_vertices(s, V);
  std::vector<int> out;
  if (observed.empty()) return out;
  auto add = [&](int v) {
    if (std::find(out.begin(), out.end(), v) == out.end()) out.push_back(v);
  };
  auto nearest = [&](const Eigen::Vector3d& p) { return nearest_observed(observed, V, p); };
  const LoadCase load_case = s.load_case();
  for (const Load& load : load_case.loads)
    if (load.kind != LoadKind::BodyForce) add(nearest(load.point));
  for (const Tool& tool : load_case.tools)
    if (tool.holds_a_disc() || tool.kind == ToolKind::Sphere) add(nearest(tool.point));
  const size_t n = observed.size(), spread = std::min<size_t>(n, kTrackedSpread);
  for (size_t k = 0; k < spread; ++k) add(observed[k * n / spread]);
  return out;
}

/// A dynamic case's first frames are recorded at its tracked vertices: the window in
/// which its transient is compared with the implicit-Euler reference's (docs/suite.md).
constexpr int kTrajectoryFrames = 200;

/// The displacement CSV of `vertices`: with their rest coordinates, or (geometry
/// from a third-party file) without.
std::string csv_of(const Points& rest, const Displacements& u, const std::vector<int>& vertices, bool coordinates) {
  std::ostringstream os;
  os << std::setprecision(17) << (coordinates ? "vertex,x,y,z,ux,uy,uz\n" : "vertex,ux,uy,uz\n");
  for (int v : vertices) {
    os << v << ',';
    if (coordinates) os << rest(v, 0) << ',' << rest(v, 1) << ',' << rest(v, 2) << ',';
    os << u(v, 0) << ',' << u(v, 1) << ',' << u(v, 2) << '\n';
  }
  return os.str();
}

/// One case. `writes`: this process writes its files (under mpirun, one process
/// per case); `shared`: every process runs it together (ModelInfo::spans_ranks).
CaseOutcome run_case(const Scenario& s, const ModelRun& run, const HybridMesh& mesh, const nlohmann::json& mesh_summary,
                     const std::string& experiment, const RunOptions& opt, bool writes, bool shared,
                     Progress& progress) {
  CaseOutcome out;
  out.scenario = s.name;
  out.case_name = run.case_name;
  const std::string label = s.name + "/" + run.case_name;
  // A model's own progress lines (a Newton solve of minutes) among the runner's.
  const ScopedProgressNotices notices([&](const std::string& text) { progress.line(label + ": " + text); });
  CaseRun case_run(s, run, mesh);  // an unsupported load or tool stops here, before setup
  const ModelInfo& info = case_run.info();
  const Model* const model = &case_run.model();

  // The case's own peak memory: from here (the mesh already resident) to its last frame.
  const bool peak_reset = reset_peak_memory();
  const double load_at_start = load_average_1min();
  case_run.setup();
  const double setup_ms = case_run.setup_ms();

  // Outputs are staged in a temporary folder and moved into place at the end (by
  // the writing process only).
  const fs::path dir = fs::path(opt.out_dir) / experiment / s.name / run.case_name;
  const fs::path staging = staging_folder(dir);
  if (writes) {
    remove_stale_staging(dir);
    fs::remove_all(staging);
    fs::create_directories(staging);
  }

  const Points& rest = mesh.fine_surface.V;
  // Optional ParaView time series of the surface (scenario "output": "series_every").
  std::ostringstream series;
  const bool write_series = writes && info.dynamic && s.series_every > 0;
  if (write_series) fs::create_directories(staging / "series");
  auto snapshot = [&](int frame, const Displacements& u) {
    char name[40];
    std::snprintf(name, sizeof name, "series/surface_%06d.vtu", frame);
    write_surface_vtu((staging / name).string(), SurfaceMesh{rest + u, mesh.fine_surface.F},
                      {{"displacement", u}, {"displacement_magnitude", u.rowwise().norm()}});
    series << "    <DataSet timestep=\"" << frame << "\" file=\"" << name << "\"/>\n";
  };
  const int changing = case_run.changing_frames();
  const int budget = case_run.budget();
  // A dynamic case's displacement at its tracked vertices, frame by frame (trajectory.csv).
  const std::vector<int> tracked = info.dynamic ? tracked_vertices(s, rest) : std::vector<int>();
  std::vector<double> trajectory;
  trajectory.reserve(tracked.size() * 3 * static_cast<size_t>(std::min(budget, kTrajectoryFrames)));
  std::vector<double> step_ms;
  step_ms.reserve(static_cast<size_t>(budget));
  std::vector<int> iterations;
  // Per-frame times of the model's named phases (Model::last_phase_times).
  std::vector<std::pair<std::string, std::vector<double>>> phase_ms;
  for (const PhaseTime& p : model->last_phase_times()) phase_ms.emplace_back(p.name, std::vector<double>());
  // The force on each tool and the support, per frame (Model::reaction_forces).
  std::vector<std::vector<Eigen::Vector3d>> reactions;
  // Each contact tool's state, per frame (Model::tool_contacts).
  std::vector<std::vector<ToolContact>> contacts;
  // Each sphere against the deformed surface after each frame (CaseRun::step): a
  // tunnelled sphere stops the case, and the faces' penetration is recorded
  // (sphere_guard.h); its cost per frame, outside the timed step, goes to timings.json.
  const SphereGuard& sphere_guard = case_run.sphere_guard();
  std::vector<double> sphere_guard_ms;
  if (sphere_guard.active()) sphere_guard_ms.reserve(static_cast<size_t>(budget));
  const auto loop_start = Clock::now();
  while (!case_run.finished()) {
    case_run.step();  // the frame's loads, the timed step, the divergence and sphere checks
    const int frame = case_run.frames() - 1;
    step_ms.push_back(case_run.last_step_ms());
    iterations.push_back(model->last_iterations());
    for (size_t k = 0; k < phase_ms.size(); ++k) phase_ms[k].second.push_back(model->last_phase_times()[k].ms);
    out.frames = frame + 1;
    if (const auto* r = model->reaction_forces()) reactions.push_back(*r);
    if (const auto* c = model->tool_contacts()) contacts.push_back(*c);

    const Displacements& u = model->surface_displacement();
    if (sphere_guard.active()) sphere_guard_ms.push_back(case_run.last_sphere_guard_ms());
    if (frame < kTrajectoryFrames)
      for (int v : tracked) trajectory.insert(trajectory.end(), {u(v, 0), u(v, 1), u(v, 2)});
    const bool steady = case_run.steady_frame() == frame;
    if (write_series && (frame % s.series_every == 0 || steady)) snapshot(frame, u);
    if (steady) break;
    progress.update(label, frame + 1, budget, std::chrono::duration<double>(Clock::now() - loop_start).count());
  }
  out.steady_frame = info.dynamic ? case_run.steady_frame() : std::max(0, changing - 1);
  const double last_change = case_run.last_change();
  const double peak_memory_mib = peak_memory_since_reset_mib();
  const double load_at_end = load_average_1min();
  nlohmann::json processes;
  if (shared && opt.process_statistics)
    processes = opt.process_statistics();
  else if (opt.processes > 1)
    processes = {{"ranks", 1}, {"dealt_to_process", opt.process}, {"processes", opt.processes}};
  if (!writes) {
    out.ok = true;
    return out;
  }

  // ---- output, staged then moved into place ----
  const Displacements& u = model->surface_displacement();
  if (write_series)
    write_file_atomically((staging / "surface_series.pvd").string(),
                          "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n  <Collection>\n" +
                              series.str() + "  </Collection>\n</VTKFile>\n");
  nlohmann::json j;
  j["experiment"] = experiment;
  j["scenario"] = s.name;
  j["scenario_file"] = s.file;
  j["scenario_resolved"] = s.to_json();
  // Where the data references of the scenario were read from on this machine.
  for (const auto& [reference, path] : {std::pair{s.mesh.surface_reference, s.mesh.surface_file},
                                        std::pair{s.mesh.coarse_reference, s.mesh.coarse_file}})
    if (!reference.empty()) j["data_files"][reference] = path;
  if (!s.sweep_base.empty()) j["sweep"] = {{"base", s.sweep_base}, {"values", s.sweep_values}, {"keys", s.sweep_keys}};
  j["case"] = run.case_name;
  j["model"] = run.model;
  j["dynamic"] = info.dynamic;
  j["model_description"] = info.description;
  j["parameters"] = run.parameters.to_json();  // every declared parameter, defaults included
  j["parameters_given"] = run.parameters_given;
  j["model_report"] = model->report();
  j["frames"] = out.frames;
  j["steady_frame"] = out.steady_frame;
  j["reached_steady_state"] = !info.dynamic || out.steady_frame >= 0;
  j["last_frame_change_m"] = last_change;
  j["max_displacement_m"] = u.rowwise().norm().maxCoeff();
  j["observed_vertices"] = s.observed;
  j["observed_coordinates"] = !geometry_from_data(s);
  if (s.has_load) j["observed_vertex_nearest_load"] = nearest_observed(observed_vertices(s, rest), rest, s.load.point);
  if (!tracked.empty())
    j["trajectory"] = {
        {"file", "trajectory.csv"},
        {"frames", std::min(out.frames, kTrajectoryFrames)},
        {"vertices", tracked},
        {"how", "the displacement of these surface vertices at each of the first " + std::to_string(kTrajectoryFrames) +
                    " frames: the observed vertex nearest each load, grasp and sphere, then " +
                    std::to_string(kTrackedSpread) + " observed vertices spread through their list"}};
  j["mesh"] = mesh_summary;
  // What the model measured beside the surface, and how (or why not).
  if (!s.tools.empty() || s.probes.rows() > 0) {
    nlohmann::json& obs = j["observables"];
    if (!s.tools.empty()) {
      obs["tools_how"] = info.tools_how;
      obs["reactions"] =
          model->reaction_forces()
              ? nlohmann::json{{"file", "reactions.csv"}, {"how", info.reactions}}
              : nlohmann::json{{"file", nullptr},
                               {"why_not", "model '" + info.name + "' does not measure reaction forces"}};
      if (model->tool_contacts()) obs["contact"] = {{"file", "contact.csv"}};
      if (sphere_guard.active()) obs["contact"]["faces"] = sphere_guard.to_json();
    }
    if (s.probes.rows() > 0)
      obs["probes"] = model->probe_displacements()
                          ? nlohmann::json{{"file", "probes.csv"}, {"how", info.probes}}
                          : nlohmann::json{{"file", nullptr},
                                           {"why_not", "model '" + info.name + "' has no volume to interpolate in"}};
  }
  j["build"] = build_and_machine_info();

  nlohmann::json t;
  t["setup_ms"] = setup_ms;
  t["peak_memory_mib"] = peak_memory_mib;
  t["peak_memory_how"] =
      peak_reset ? "this process's peak resident memory (VmHWM) from the model's setup to its last frame, the "
                   "mesh included (reset before setup: /proc/self/clear_refs)"
                 : "this process's peak resident memory since it started (VmHWM; the kernel refused a reset)";
  // The machine's other work inflates every time here: the analysis flags a case whose
  // load average exceeded the hardware threads (a busy machine).
  t["load_average_1min"] = {{"at_setup", load_at_start}, {"at_last_frame", load_at_end}};
  t["step"] = to_json(timing_stats(step_ms));
  // Frames after the load ramp, i.e. the frames of the steady load only.
  const size_t skip = std::min(step_ms.size(), static_cast<size_t>(changing));
  t["step_after_ramp"] =
      to_json(timing_stats(std::vector<double>(step_ms.begin() + static_cast<long>(skip), step_ms.end())));
  // Each named phase of a frame (docs/design.md: named timing phases), over the frames after the ramp.
  t["phases_after_ramp"] = nlohmann::json::object();
  for (const auto& [name, ms] : phase_ms)
    t["phases_after_ramp"][name] =
        to_json(timing_stats(std::vector<double>(ms.begin() + static_cast<long>(skip), ms.end())));
  t["step_ms_per_frame"] = step_ms;
  t["solver_iterations_per_frame"] = iterations;
  if (sphere_guard.active())
    t["sphere_guard"] = {{"how",
                          "the runner's check of each sphere against the deformed surface after each frame "
                          "(winding number, face penetration and, after a long move, the swept path: "
                          "sphere_guard.h), outside the timed step"},
                         {"per_frame", to_json(timing_stats(sphere_guard_ms))}};
  t["build"] = j["build"];
  if (!processes.is_null()) t["processes"] = processes;
  write_file_atomically((staging / "timings.json").string(), t.dump(1) + "\n");

  const bool coordinates = !geometry_from_data(s);
  write_file_atomically((staging / "top_surface.csv").string(),
                        csv_of(rest, u, observed_vertices(s, rest), coordinates));
  if (!tracked.empty()) {
    // Wide: a row per frame, three columns per tracked vertex (its index in the header).
    std::ostringstream csv;
    csv << std::setprecision(8) << "frame";
    for (int v : tracked) csv << ",v" << v << "_ux,v" << v << "_uy,v" << v << "_uz";
    csv << '\n';
    const size_t row = tracked.size() * 3;
    for (size_t f = 0; f * row < trajectory.size(); ++f) {
      csv << f;
      for (size_t k = 0; k < row; ++k) csv << ',' << trajectory[f * row + k];
      csv << '\n';
    }
    write_file_atomically((staging / "trajectory.csv").string(), csv.str());
  }
  std::vector<int> all(static_cast<size_t>(rest.rows()));
  for (size_t v = 0; v < all.size(); ++v) all[v] = static_cast<int>(v);
  write_file_atomically((staging / "surface.csv").string(), csv_of(rest, u, all, coordinates));
  if (!s.tools.empty() && !reactions.empty()) {
    // The force the tissue exerts on each tool and on the support, every frame (N).
    std::ostringstream csv;
    csv << std::setprecision(17) << "frame,constraint,kind,fx,fy,fz\n";
    for (size_t f = 0; f < reactions.size(); ++f)
      for (size_t k = 0; k < reactions[f].size(); ++k) {
        const bool support = k == s.tools.size();
        csv << f << ',' << (support ? "support" : s.tools[k].tool.key) << ','
            << (support ? "support" : name(s.tools[k].tool.kind)) << ',' << reactions[f][k].x() << ','
            << reactions[f][k].y() << ',' << reactions[f][k].z() << '\n';
      }
    write_file_atomically((staging / "reactions.csv").string(), csv.str());
  }
  if (!contacts.empty()) {
    // Each sphere's contact, every frame: points in contact, the area of the surface
    // triangles all of whose vertices are in contact (m^2), the deepest vertex inside (m).
    std::ostringstream csv;
    csv << std::setprecision(17) << "frame,constraint,kind,points_in_contact,contact_area_m2,max_penetration_m\n";
    for (size_t f = 0; f < contacts.size(); ++f)
      for (size_t k = 0; k < contacts[f].size() && k < s.tools.size(); ++k)
        if (s.tools[k].tool.kind == ToolKind::Sphere)
          csv << f << ',' << s.tools[k].tool.key << ',' << name(s.tools[k].tool.kind) << ',' << contacts[f][k].points
              << ',' << contacts[f][k].area << ',' << contacts[f][k].max_penetration << '\n';
    write_file_atomically((staging / "contact.csv").string(), csv.str());
  }
  if (const Points* probes = model->probe_displacements(); probes && s.probes.rows() > 0) {
    // Points from a third-party table (the Truth Cube's beads) are not copied out:
    // the file names them by their row in that table (run.json, "probes").
    const bool own_points = s.probes_source.empty();
    std::ostringstream csv;
    csv << std::setprecision(17) << (own_points ? "probe,x,y,z,ux,uy,uz\n" : "probe,ux,uy,uz\n");
    for (Eigen::Index p = 0; p < s.probes.rows(); ++p) {
      csv << p << ',';
      if (own_points) csv << s.probes(p, 0) << ',' << s.probes(p, 1) << ',' << s.probes(p, 2) << ',';
      csv << (*probes)(p, 0) << ',' << (*probes)(p, 1) << ',' << (*probes)(p, 2) << '\n';
    }
    write_file_atomically((staging / "probes.csv").string(), csv.str());
  }
  SurfaceMesh deformed{rest + u, mesh.fine_surface.F};
  write_surface_vtu((staging / "surface.vtu").string(), deformed,
                    {{"displacement", u}, {"displacement_magnitude", u.rowwise().norm()}});
  // run.json last: a folder holding it holds every file (what the analysis takes
  // for a case, analysis/results_index.py), even before the rename.
  write_file_atomically((staging / "run.json").string(), j.dump(2) + "\n");
  replace_folder(staging, dir);
  out.ok = true;
  return out;
}

}  // namespace

std::string default_mesh_cache_dir() {
  if (const char* env = std::getenv("TISSUEBENCH_MESH_CACHE"); env && *env) return env;
  if (const char* xdg = std::getenv("XDG_CACHE_HOME"); xdg && *xdg) return std::string(xdg) + "/tissuebench/meshes";
  if (const char* home = std::getenv("HOME"); home && *home) return std::string(home) + "/.cache/tissuebench/meshes";
  return "";
}

namespace {

/// A scenario's mesh built and its tools and probes placed on it, shared by its cases.
struct PreparedScenario {
  Scenario resolved;
  std::shared_ptr<HybridMesh> mesh;
  nlohmann::json summary;
  std::string error;  ///< why preparing failed (then every case of the scenario fails with it)
};

/// Who runs a case (RunOptions::processes): every process together, or one.
struct CaseAssignment {
  bool selected = false;  ///< passes --model / --scenario
  bool shared = false;    ///< its model spans ranks: every process runs it
  int writer = 0;         ///< the process that runs it alone (dealt), or writes it (shared: 0)
};

/// The deal: selected cases of models that span ranks to every process, the others
/// one each, the k-th to process k mod processes.
std::vector<std::vector<CaseAssignment>> assign_cases(const Experiment& e, const RunOptions& opt) {
  std::vector<std::vector<CaseAssignment>> plan(e.scenarios.size());
  int dealt = 0;
  for (size_t i = 0; i < e.scenarios.size(); ++i) {
    const Scenario& s = e.scenarios[i];
    for (const ModelRun& run : s.models) {
      CaseAssignment a;
      a.selected = (opt.only_scenario.empty() || opt.only_scenario == s.name) &&
                   (opt.only_case.empty() || opt.only_case == run.case_name || opt.only_case == run.model);
      if (a.selected) {
        a.shared = find_model(run.model).spans_ranks;
        a.writer = a.shared ? 0 : dealt++ % std::max(1, opt.processes);
      }
      plan[i].push_back(a);
    }
  }
  return plan;
}

void write_failure(const fs::path& file, const std::string& case_name, const std::string& error) {
  try {
    write_file_atomically(file.string(), nlohmann::json({{"case", case_name}, {"error", error}}).dump(2) + "\n");
  } catch (const std::exception&) {
    // the failure is reported on stderr and in the exit status already
  }
}

}  // namespace

std::vector<CaseOutcome> run_experiment(const Experiment& e, const RunOptions& opt) {
  const bool many = opt.processes > 1;
  Progress progress(opt.progress, many ? "rank " + std::to_string(opt.process) + ": " : "");
  Progress silent(false, "");
  struct BuiltMesh {
    std::shared_ptr<HybridMesh> mesh;
    MeshReport report;
    nlohmann::json summary;
  };
  std::map<std::string, BuiltMesh> meshes;
  std::vector<CaseOutcome> outcomes;
  if (!opt.index_only && opt.max_memory_bytes >= 0) {
    const bool given = opt.max_memory_bytes > 0;
    check_memory(e, opt.only_scenario, opt.only_case, given ? opt.max_memory_bytes : available_memory_bytes(),
                 given ? "--max-memory" : "available memory (MemAvailable, /proc/meminfo)");
  }
  // What the analysis reads to know the cases, their order and the reference.
  if (opt.process == 0) {
    fs::create_directories(fs::path(opt.out_dir) / e.name);
    write_file_atomically((fs::path(opt.out_dir) / e.name / "experiment.json").string(), e.to_json().dump(2) + "\n");
  }
  if (opt.index_only) return outcomes;
  // A case this build leaves out before setup (not_run) keeps nothing of an earlier
  // run beside it: its old results or failure would contradict the index just written.
  if (opt.process == 0)
    for (const Scenario& s : e.scenarios)
      for (const auto& not_run : s.not_run) {
        // Names are single folder names (scenario.cc refuses '.', '..', '/' and 'mesh').
        const fs::path scenario_dir = fs::path(opt.out_dir) / e.name / s.name;
        if (fs::path(not_run.first).filename() != fs::path(not_run.first)) continue;
        std::error_code ec;
        fs::remove(scenario_dir / (not_run.first + ".failed.json"), ec);
        fs::remove_all(scenario_dir / not_run.first, ec);
      }
  const std::vector<std::vector<CaseAssignment>> plan = assign_cases(e, opt);

  // Builds (or finds) the scenario's mesh and places its tools and probes. With
  // `collective`, every process calls it for the same scenarios in the same order.
  auto prepare = [&](const Scenario& s, bool collective, bool write_meshes) {
    PreparedScenario p;
    try {
      // The same resolved recipe (file paths absolute) builds the same mesh: build it once.
      const std::string key = s.mesh.to_json().dump();
      auto it = meshes.find(key);
      if (it == meshes.end()) {
        progress.line(s.name + ": preparing meshes");
        MeshReport report;
        bool cached = false;
        std::shared_ptr<HybridMesh> mesh;
        const auto build_start = Clock::now();
        if (collective && opt.barrier) {  // process 0 first, through the cache; then the others read it
          std::exception_ptr failed;
          if (opt.process == 0) try {
              mesh = std::make_shared<HybridMesh>(build_mesh_cached(s.mesh, report, opt.mesh_cache_dir, cached));
            } catch (...) {
              failed = std::current_exception();
            }
          opt.barrier();
          if (failed) std::rethrow_exception(failed);
        }
        if (!mesh) mesh = std::make_shared<HybridMesh>(build_mesh_cached(s.mesh, report, opt.mesh_cache_dir, cached));
        const double build_seconds = std::chrono::duration<double>(Clock::now() - build_start).count();
        if (cached) progress.line(s.name + ": meshes read from the cache " + opt.mesh_cache_dir);
        nlohmann::json summary = report.to_json(*mesh);
        // How long building took and the process's peak memory after it (an upper
        // bound of the build's own when it is the process's first and largest).
        summary["build_seconds"] = build_seconds;
        summary["read_from_cache"] = cached;
        summary["process_peak_memory_mib_after_build"] = process_peak_memory_mib();
        it = meshes.emplace(key, BuiltMesh{mesh, report, summary}).first;
        progress.line(s.name + ": " + std::to_string(mesh->fine_surface.V.rows()) + " surface vertices, " +
                      std::to_string(mesh->fine_volume.T.rows()) + " fine tets, " +
                      std::to_string(mesh->coarse_volume.T.rows()) + " coarse tets, " +
                      std::to_string(mesh->control_points.size()) + " control points");
      }
      p.mesh = it->second.mesh;
      p.summary = it->second.summary;
      // The meshes as built, for ParaView and figure 1.
      if (write_meshes)
        write_mesh_folder((fs::path(opt.out_dir) / e.name / s.name / "mesh").string(), *p.mesh, it->second.report);
      // What the scenario places relative to the mesh, and checks that every case
      // shares (tools that hold nothing, probes outside the body): before any case.
      p.resolved = placed_on_mesh(s, p.mesh->fine_surface);
    } catch (const std::exception& ex) {
      p.error = ex.what();
      progress.line(s.name + ": FAILED preparing the scenario: " + p.error);
    }
    return p;
  };

  // One process: every case in order. Several: the shared cases first, every
  // process together, then each process its own dealt cases.
  std::map<size_t, PreparedScenario> prepared;
  const int phases = many ? 2 : 1;
  for (int phase = 0; phase < phases; ++phase)
    for (size_t i = 0; i < e.scenarios.size(); ++i) {
      const Scenario& s = e.scenarios[i];
      auto takes_part = [&](const CaseAssignment& a) {
        if (!a.selected) return false;
        if (!many) return true;
        return phase == 0 ? a.shared : !a.shared && a.writer == opt.process;
      };
      std::vector<size_t> mine;
      for (size_t k = 0; k < s.models.size(); ++k)
        if (takes_part(plan[i][k])) mine.push_back(k);
      if (mine.empty()) continue;
      auto found = prepared.find(i);
      if (found == prepared.end()) {
        // The scenario's mesh folder is written by the process of its first case.
        int mesh_writer = -1;
        for (const CaseAssignment& a : plan[i])
          if (a.selected && (mesh_writer < 0 || a.shared)) mesh_writer = a.writer;
        found =
            prepared.emplace(i, prepare(s, many && phase == 0, opt.write_meshes && mesh_writer == opt.process)).first;
      }
      const PreparedScenario& p = found->second;
      for (size_t k : mine) {
        const ModelRun& run = s.models[k];
        const bool writes = plan[i][k].writer == opt.process;
        CaseOutcome o;
        o.scenario = s.name;
        o.case_name = run.case_name;
        // A failed case leaves its message beside its (absent or previous) results, for the analysis.
        const fs::path failure = fs::path(opt.out_dir) / e.name / s.name / (run.case_name + ".failed.json");
        if (!p.error.empty()) {
          o.error = p.error;
          if (writes) write_failure(failure, run.case_name, o.error), outcomes.push_back(o);
          continue;
        }
        Progress& report = writes ? progress : silent;
        try {
          o = run_case(p.resolved, run, *p.mesh, p.summary, e.name, opt, writes, plan[i][k].shared, report);
          std::error_code ec;
          if (writes) fs::remove(failure, ec);
          report.line(s.name + "/" + run.case_name + ": done, " + std::to_string(o.frames) + " frames" +
                      (o.steady_frame >= 0 ? "" : " (frame budget reached before steady state)"));
        } catch (const std::exception& ex) {
          o.ok = false;
          o.error = ex.what();
          report.line(s.name + "/" + run.case_name + ": FAILED: " + o.error);
          if (writes) {
            write_failure(failure, run.case_name, o.error);
            std::error_code ec;
            fs::remove_all(staging_folder(fs::path(opt.out_dir) / e.name / s.name / run.case_name), ec);
          }
        }
        if (writes) outcomes.push_back(o);
      }
    }
  return outcomes;
}

}  // namespace tb
