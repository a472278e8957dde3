// The scenario runner: for each scenario x model, build (or reuse) the meshes,
// set the model up, step it frame by frame, and write the raw results.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "scenario.h"

namespace tb {

struct RunOptions {
  /// <out_dir>/<experiment>/<scenario>/<case>/. Not results/: a trial run must not
  /// overwrite the committed results (scripts that regenerate them pass results).
  std::string out_dir = "runs";
  std::string only_case;      ///< run only this case (or model) name; empty: all
  std::string only_scenario;  ///< run only the scenario of this name; empty: all
  bool write_meshes = true;   ///< the built meshes into <scenario>/mesh/ (large for refined ones)
  /// Write <experiment>/experiment.json (the index the analysis reads: cases,
  /// their order, roles, the reference) and nothing else: no mesh, no case.
  bool index_only = false;
  bool progress = true;        ///< progress lines on stderr
  std::string mesh_cache_dir;  ///< built meshes cached here by content hash; empty: none
  /// The memory every selected case must fit, checked before anything is built or
  /// written (resource_limits.h): > 0 bytes (tissuebench run --max-memory); 0: the
  /// machine's available memory; < 0: no check.
  double max_memory_bytes = 0;
  /// Several processes (mpirun -np N; docs/usage.md, "Many cases over MPI ranks"):
  /// this one's index and their count. A case of a model that spans ranks
  /// (ModelInfo::spans_ranks) is run by every process together and written by
  /// process 0; every other selected case is dealt to one process, which runs and
  /// writes it alone: the k-th such case, in the experiment's order, to process
  /// k mod N. With N > 1 the shared cases come first, then each process's own.
  int process = 0, processes = 1;
  /// Set with processes > 1: for a scenario with a shared case, process 0 builds
  /// the mesh (through the cache) before the others, who read it from the cache.
  std::function<void()> barrier;
  /// If set, called by every process after a shared case's frames (it may be
  /// collective); its result goes into timings.json as "processes".
  std::function<nlohmann::json()> process_statistics;
};

struct CaseOutcome {
  std::string scenario, case_name;
  bool ok = false;
  std::string error;      ///< why it failed (diverged, setup error ...)
  int frames = 0;         ///< frames stepped
  int steady_frame = -1;  ///< first frame meeting the steady-state test (-1: never)
};

/// The default mesh cache: $TISSUEBENCH_MESH_CACHE, else $XDG_CACHE_HOME or
/// ~/.cache, + /tissuebench/meshes.
std::string default_mesh_cache_dir();

/// Runs this process's cases; a failing case is reported and writes nothing, the
/// others go on. Returns the outcomes of the cases this process writes.
std::vector<CaseOutcome> run_experiment(const Experiment& experiment, const RunOptions& options);

/// The surface vertices a case observes (scenario "observe.vertices": "top", those
/// within top_tolerance of the highest z of V; "all", every one), increasing. V #V by 3.
std::vector<int> observed_vertices(const Scenario& scenario, const Points& V);

/// Summary statistics of per-frame times (milliseconds).
struct TimingStats {
  double median = 0, p95 = 0, mean = 0, min = 0, max = 0;
  int count = 0;
};
TimingStats timing_stats(std::vector<double> samples_ms);

}  // namespace tb
