// The fuzz target of the benchmark's submission reader and scorer
// (experiments/submission.h, submission_score.h). The package and its converged
// answers are fixed (tests/submission_fixture.h, written into the workspace); the
// input is the submission: submission.json, then each CSV after a separator line
// (kSubmissionSeparator), a file left out where its separator is. The seeds
// (make_seeds.py) are the fixture's valid submission and variants of it.
#include <filesystem>

#include "../submission_fixture.h"
#include "fuzz_targets.h"
#include "submission.h"
#include "submission_score.h"

namespace tb::fuzz {
namespace fs = std::filesystem;

namespace {

/// The input cut at `separator`s: {submission.json, displacements.csv, forces.csv}
/// present or not.
std::map<std::string, std::string> submission_files_of(const std::string& bytes) {
  const std::vector<std::string> names{"submission.json", "displacements.csv", "forces.csv"};
  std::map<std::string, std::string> files;
  size_t start = 0;
  for (size_t k = 0; k < names.size(); ++k) {
    const std::string next = k + 1 < names.size() ? std::string(kSubmissionSeparator) + names[k + 1] + "\n" : "";
    const size_t end = next.empty() ? std::string::npos : bytes.find(next, start);
    files[names[k]] = bytes.substr(start, end == std::string::npos ? std::string::npos : end - start);
    if (end == std::string::npos) break;
    start = end + next.size();
  }
  return files;
}

}  // namespace

Target submission_target() {
  return {
      "submission",
      "benchmark submission (read_submission against a fixed package, then score_submission): submission.json, "
      "displacements.csv, forces.csv",
      [](const std::string& bytes, const Workspace& w) {
        // The workspace outlives one input: the submission's folder is made anew.
        const std::string package = w.path("package"), answers = w.path("answers"), dir = w.path("submission");
        if (!fs::exists(package)) {
          fs::create_directories(package);
          fs::create_directories(answers);
          testing::write_tiny_package(package);
          testing::write_tiny_answers(answers);
        }
        fs::remove_all(dir);
        fs::create_directories(dir);
        for (const auto& [name, text] : submission_files_of(bytes)) w.write("submission/" + name, text);
        const ProblemPackage p = read_problem_package(package);
        const Submission s = read_submission(dir, p);
        (void)score_submission(s, p, {answers, DataDir{w.path("data"), "the fuzz workspace"}, 100.0, nullptr}).dump();
      },
      {"submission.json", "displacements.csv", "forces.csv"},
      {"\"format\"",
       "\"tissuebench-submission/1\"",
       "\"units\"",
       "\"length\": \"m\"",
       "\"time\": \"ms\"",
       "\"memory\": \"MiB\"",
       "\"force\": \"N\"",
       "\"calibration\"",
       "\"figure_ms\"",
       "\"timing\"",
       "\"threads\"",
       "\"resolution\"",
       "\"tets\"",
       "null",
       "1e400",
       "-0",
       "nan",
       "inf",
       "\n",
       "\r\n",
       ",",
       "s0",
       "s1",
       "s2",
       "p0",
       "grasp",
       "frame,id,ux,uy,uz\n",
       "frame,tool,fx,fy,fz\n",
       "0,",
       "1,",
       "2,",
       "3,",
       "-1,",
       std::string(kSubmissionSeparator) + "displacements.csv\n",
       std::string(kSubmissionSeparator) + "forces.csv\n"}};
}

}  // namespace tb::fuzz
