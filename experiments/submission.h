// The open benchmark's files, as `tissuebench score` reads them
// (docs/benchmark_format.md "The problem package" and "Submissions and scoring";
// docs/schemas/submission.schema.json): what score needs of a problem package
// (`tissuebench export` writes it), and a submission read and checked against it.
// Every malformed file is one std::exception, what() one line naming the file and,
// where there is one, the line (CSV) or the key (JSON).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mesh_types.h"

namespace tb {

/// What score reads of a problem package (its problem.json, observation_points.csv
/// and observation_interior.csv); the rest of the package is the simulator's.
struct ProblemPackage {
  std::string dir;
  std::string scenario;
  std::string role;                       ///< the suite role; "" if none
  int frames = 0;                         ///< time.frames: frames 0..frames-1
  std::vector<int> observation_frames;    ///< increasing, each in 0..frames-1
  std::vector<std::string> surface_ids;   ///< observation_points.csv's ids, its order
  std::vector<std::string> interior_ids;  ///< observation_interior.csv's; empty if none
  std::vector<std::string> tools;         ///< tools[].name, in order; empty if none
  /// Every observation point: the surface ids, then the interior ones.
  std::vector<std::string> point_ids() const;
};

/// Reads the package in `dir`. Throws (one line naming the file) if problem.json is not
/// a tissuebench-problem/1 (kProblemFormat, problem_package.h) or lacks what score
/// reads, or its point files are malformed (no id column, an id repeated).
ProblemPackage read_problem_package(const std::string& dir);

/// One submission's values, in the package's order.
struct Submission {
  std::string dir;
  nlohmann::json meta;      ///< submission.json as read (every key checked)
  std::vector<int> frames;  ///< reported frames, increasing
  /// displacements[f]: #points by 3 (m) at frames[f], rows in point_ids() order.
  std::vector<Points> displacements;
  /// forces[f]: #tools by 3 (N) at frames[f], rows in tools order; empty without tools.
  std::vector<Points> forces;
  /// The row of `frames` holding `frame`; -1 if not reported.
  int frame_index(int frame) const;
};

/// The files a submission holds: submission.json, displacements.csv and, when the
/// package's scenario has tools, forces.csv (score.json, which score writes, may be
/// there too; nothing else).
std::vector<std::string> submission_files(const ProblemPackage& package);

/// The most bytes `file` (one of submission_files) may hold for this package: a row
/// per point (tool) per frame of the scenario at 256 bytes each, more than a row of
/// 17-digit numbers needs, and 64 KiB; submission.json 1 MiB. A larger file is
/// refused before it is read.
size_t submission_file_bound(const ProblemPackage& package, const std::string& file);

/// Reads and checks the submission in `dir` against `package`: the folder's files,
/// submission.json's keys, values and units (the contract's, exactly), the
/// displacements' and forces' headers, ids, frames (increasing, within the scenario,
/// every observation frame), numbers (finite). Throws on the first problem.
Submission read_submission(const std::string& dir, const ProblemPackage& package);

}  // namespace tb
