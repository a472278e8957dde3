// `tissuebench calibrate`: this machine's figure for the benchmark's kind of work, so
// that times measured on different machines can be shown side by side
// (docs/benchmark_format.md "Submissions and scoring"). The workload is fixed: sweeps
// of a P1 tet loop, the neo-Hookean internal forces of every tet of a structured
// cube mesh (models/numerics/materials/tet_element.h, neo_hookean.h) gathered from
// and scattered to its nodes, as every model's frame does; one thread, no input,
// nothing allocated while timed.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace tb {

struct Calibration {
  double figure_ms = 0;          ///< the fastest repeat's time (calibration.cc says why)
  std::vector<double> times_ms;  ///< each repeat's time, in order
  double checksum = 0;           ///< of the forces: the same on every run of one build
  nlohmann::json machine;        ///< cpu, cores, build, load average (build_info.h)
  /// {"figure_ms", "repeats", "times_ms", "workload", "checksum", "machine"}.
  nlohmann::json to_json() const;
};

/// What one repeat does, in words (calibrate's JSON "workload").
std::string calibration_workload();

/// Runs the workload `repeats` times (after one untimed warm-up) and times each.
Calibration run_calibration(int repeats = 15);

/// The figure `--calibration VALUE` gives: VALUE a positive number of ms, or a file
/// holding calibrate's JSON (its figure_ms). Throws one line naming VALUE otherwise.
double calibration_figure(const std::string& value);

}  // namespace tb
