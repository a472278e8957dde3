// Scoring a submission (submission.h) against the converged answers of its role
// (results/observation_points/, docs/benchmark_format.md): the C++ twin of
// analysis/observation_points.py score_observations, whose definitions it keeps:
// the relative L2 of the surface displacements against the converged field
// (analysis/metrics.py compare's rel_l2), the probes' RMS error (mm) against the
// converged run's, and on the Truth Cube the beads' RMS distance (mm) from the
// CT-measured beads (experiments/truth_cube.h). Self-reported times are shown
// normalised by the two machines' calibration figures (calibration.h).
#pragma once

#include <cmath>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "data_dir.h"
#include "mesh_types.h"
#include "submission.h"
#include "truth_cube.h"

namespace tb {

/// One file of converged answers: <role>.csv or <role>_interior.csv.
struct AnswerPoints {
  std::string file;
  std::vector<std::string> ids;
  Points u;                      ///< #ids by 3 converged displacements (m); 0 rows where the file has none
  std::vector<long> table_rows;  ///< the beads' rows of the bead table (Truth Cube); else empty
};

/// A role's converged answers (analysis/observation_points.py read_role).
struct ObservationAnswers {
  std::string meta_file;
  nlohmann::json meta;  ///< <role>.json: converged run, its estimated error, the beads' frame
  AnswerPoints surface;
  std::optional<AnswerPoints> interior;
};

/// Reads <answers_dir>/<role>.json, <role>.csv and, if there, <role>_interior.csv.
/// Throws one line naming the file on a missing or malformed one.
ObservationAnswers read_observation_answers(const std::string& answers_dir, const std::string& role);

/// ||u - u_ref|| / ||u_ref|| (Frobenius over every row; metrics.compare's rel_l2), NaN
/// if u_ref is zero. u, u_ref: #N by 3.
double relative_l2(const Points& u, const Points& u_ref);

/// The RMS over rows of |u - u_ref|, in mm (observation_points.py probe_rms_mm).
/// u, u_ref: #N by 3 (m).
double rms_error_mm(const Points& u, const Points& u_ref);

/// The RMS distance (mm) of the beads moved by u from their positions measured at
/// the strain nearest meta's compare_at_strain, both in the model's frame (meta's
/// frame, truth_cube.h): observation_points.py bead_rms_mm. rows: #I rows of the
/// table; u: #I by 3 (m).
double bead_rms_mm(const TruthCubeTable& table, const nlohmann::json& meta, const std::vector<long>& rows,
                   const Points& u);

struct ObservationScores {
  double rel_l2_converged = std::nan("");
  double probe_error_mm = std::nan("");
  double bead_rms_mm = std::nan("");
  nlohmann::json converged_run;    ///< e.g. "P2 L1"; null where there is no converged answer
  nlohmann::json converged_error;  ///< its estimated relative error; null where unknown
  std::string note;
};

/// score_observations: values #S by 3 (m) in answers.surface's order; probe_values #I
/// by 3 in answers.interior's order, or null. The bead table is read from `data`.
ObservationScores score_observations(const ObservationAnswers& answers, const Points& values,
                                     const Points* probe_values, const DataDir& data);

struct ScoreOptions {
  std::string answers_dir;       ///< default: the repository's results/observation_points
  DataDir data;                  ///< for the Truth Cube's bead table
  double machine_figure_ms = 0;  ///< this machine's calibration figure (calibration.h)
  nlohmann::json machine;        ///< what calibrate says of this machine, or null
};

/// score.json: the submission's scores at the package's last observation frame, its
/// self-reported times as reported and normalised (time * this machine's figure /
/// the submission's), marked self_reported.
nlohmann::json score_submission(const Submission& submission, const ProblemPackage& package,
                                const ScoreOptions& options);

/// The one-screen summary score prints.
std::string score_summary(const nlohmann::json& score);

}  // namespace tb
