// A tiny problem package, its converged answers and a valid submission, written by
// hand in the layout of docs/benchmark_format.md ("The problem package",
// "Submissions and scoring"): what tests/experiments/submission_test.cc and the
// submission fuzz target (tests/fuzz/submission_target.cc) read. Header-only, so the
// fuzz driver uses it without the test support library.
//
// Three surface points and one probe; scenario frames 0..2, observed at 1 and 2; one
// tool. The converged field u_ref (m) at frame 2, and the submission's:
//   s0 (0.001, 0, 0)      submitted exactly
//   s1 (0, 0.002, 0)      submitted exactly
//   s2 (0, 0, 0.002)      submitted (0, 0, 0.0026)
//   p0 (0.001, 0.002, 0.002)  submitted (0.001, 0.002, 0.0024)
// so rel L2 = |(0, 0, 0.0006)| / sqrt(1 + 4 + 4) mm = 0.6 / 3 = 0.2 and the probe RMS
// error 0.4 mm. The submission's calibration figure is 200 ms; its frame median 10 ms.
#pragma once

#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>
#include <string>

namespace tb::testing {

inline void write_text(const std::string& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
  if (!out) throw std::logic_error("cannot write " + path);
}

inline std::string in_dir(const std::string& dir, const std::string& name) {
  return (std::filesystem::path(dir) / name).string();
}

/// problem.json, observation_points.csv and observation_interior.csv in `dir` (which
/// exists); with_tool false: a scenario without tools (no forces.csv).
inline void write_tiny_package(const std::string& dir, bool with_tool = true) {
  write_text(in_dir(dir, "problem.json"),
             std::string(R"({"format": "tissuebench-problem/1", "scenario": "tiny", "role": "tiny_role",
 "description": "three points and a probe, written by hand",
 "time": {"dt": 0.01, "frames": 3, "ramp_frames": 1},
 "observation": {"surface_points": "observation_points.csv", "interior_points": "observation_interior.csv",
                 "frames": [1, 2]},
 "tools": )") + (with_tool ? R"([{"name": "grasp", "type": "grasp", "path": "tool_0.csv"}])" : "[]") +
                 "}\n");
  write_text(in_dir(dir, "observation_points.csv"),
             "id,patch,x,y,z\ns0,top_face,0,0,0.1\ns1,top_face,0.01,0,0.1\ns2,top_face,0,0.01,0.1\n");
  write_text(in_dir(dir, "observation_interior.csv"), "id,x,y,z\np0,0,0,0.05\n");
}

/// tiny_role.csv (its rows in another order than the package's), tiny_role_interior.csv
/// and tiny_role.json in `dir` (which exists): the converged answers.
inline void write_tiny_answers(const std::string& dir) {
  write_text(in_dir(dir, "tiny_role.csv"),
             "id,patch,x,y,z,ux,uy,uz\ns2,top_face,0,0.01,0.1,0,0,0.002\ns0,top_face,0,0,0.1,0.001,0,0\n"
             "s1,top_face,0.01,0,0.1,0,0.002,0\n");
  write_text(in_dir(dir, "tiny_role_interior.csv"),
             "id,patch,x,y,z,ux,uy,uz\np0,interior,0,0,0.05,0.001,0.002,0.002\n");
  write_text(in_dir(dir, "tiny_role.json"),
             R"({"role": "tiny_role", "converged": {"run": "P2 L1", "estimated_error": 0.01}, "note": ""})"
             "\n");
}

/// The valid submission's files, name -> content (forces.csv only with_tool).
inline std::map<std::string, std::string> tiny_submission(bool with_tool = true) {
  std::map<std::string, std::string> files;
  files["submission.json"] = R"({
  "format": "tissuebench-submission/1",
  "scenario": "tiny",
  "role": "tiny_role",
  "method": "hand-written",
  "resolution": {"description": "the observation points themselves", "surface_vertices": 3, "tets": 0},
  "units": {"length": "m", "force": "N", "time": "ms", "memory": "MiB"},
  "timing": {"frame_median_ms": 10, "frame_p95_ms": 12, "setup_s": 1.5},
  "peak_memory_mib": 64,
  "threads": 1,
  "machine": {"cpu": "a test machine", "cores": 2},
  "calibration": {"figure_ms": 200, "command": "tissuebench calibrate"},
  "provenance": "tests/submission_fixture.h"
}
)";
  files["displacements.csv"] =
      "frame,id,ux,uy,uz\n"
      "1,s0,0.0005,0,0\n1,s1,0,0.001,0\n1,s2,0,0,0.0013\n1,p0,0.0005,0.001,0.0012\n"
      "2,s0,0.001,0,0\n2,s1,0,0.002,0\n2,s2,0,0,0.0026\n2,p0,0.001,0.002,0.0024\n";
  if (with_tool) files["forces.csv"] = "frame,tool,fx,fy,fz\n1,grasp,0,0,0.5\n2,grasp,0,0,1\n";
  return files;
}

}  // namespace tb::testing
