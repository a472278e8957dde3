// The scenario runner: for each scenario x model, build (or reuse) the meshes,
// set the model up, step it frame by frame, and write the raw results.
#pragma once

#include <string>
#include <vector>

#include "scenario.h"

namespace tb {

struct RunOptions {
  std::string out_dir = "results";  ///< results/<experiment>/<scenario>/<case>/
  std::string only_case;            ///< run only this case (or model) name; empty: all
  bool progress = true;             ///< progress lines on stderr
  std::string mesh_cache_dir;       ///< built meshes cached here by content hash; empty: none
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

/// Runs every case; a failing case is reported and writes nothing, the others go on.
std::vector<CaseOutcome> run_experiment(const Experiment& experiment, const RunOptions& options);

/// Summary statistics of per-frame times (milliseconds).
struct TimingStats {
  double median = 0, p95 = 0, mean = 0, min = 0, max = 0;
  int count = 0;
};
TimingStats timing_stats(std::vector<double> samples_ms);

}  // namespace tb
