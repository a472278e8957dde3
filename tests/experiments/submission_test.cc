// The submission reader and scorer (experiments/submission.h, submission_score.h):
// a hand-made package (tests/submission_fixture.h) scored to hand-computed values,
// the converged answers themselves scoring 0, and every kind of malformed
// submission refused with one line naming the file (and the line or key).
#include "submission.h"

#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <iomanip>
#include <set>
#include <sstream>

#include "calibration.h"
#include "cli_run.h"
#include "submission_fixture.h"
#include "submission_score.h"
#include "test_support.h"

namespace tb {
namespace {

namespace fs = std::filesystem;
using testing::in_dir;
using testing::write_text;

/// A package, its answers and a submission folder in a temporary folder.
struct Tiny {
  testing::TempFolder root{"submission"};
  std::string package = root / "package", answers = root / "answers", submission = root / "submission";
  explicit Tiny(bool with_tool = true) {
    for (const std::string& d : {package, answers, submission}) fs::create_directories(d);
    testing::write_tiny_package(package, with_tool);
    testing::write_tiny_answers(answers);
    for (const auto& [name, text] : testing::tiny_submission(with_tool)) write_text(in_dir(submission, name), text);
  }
  ScoreOptions options() const { return {answers, DataDir{root / "data", "the test"}, 100.0, nullptr}; }
  nlohmann::json score() const {
    const ProblemPackage p = read_problem_package(package);
    return score_submission(read_submission(submission, p), p, options());
  }
  std::string read(const std::string& name) const {
    std::ifstream in(in_dir(submission, name), std::ios::binary);
    return {std::istreambuf_iterator<char>(in), {}};
  }
  void write(const std::string& name, const std::string& text) const { write_text(in_dir(submission, name), text); }
  /// Replaces the first `from` in the submission's `name` by `to`.
  void replace(const std::string& name, const std::string& from, const std::string& to) const {
    std::string text = read(name);
    const size_t at = text.find(from);
    ASSERT_NE(at, std::string::npos) << from << " not in " << name;
    write(name, text.replace(at, from.size(), to));
  }
};

TEST(Submission, ReadsThePackageAndTheSubmission) {
  const Tiny t;
  const ProblemPackage p = read_problem_package(t.package);
  EXPECT_EQ(p.scenario, "tiny");
  EXPECT_EQ(p.role, "tiny_role");
  EXPECT_EQ(p.frames, 3);
  EXPECT_EQ(p.observation_frames, (std::vector<int>{1, 2}));
  EXPECT_EQ(p.point_ids(), (std::vector<std::string>{"s0", "s1", "s2", "p0"}));
  EXPECT_EQ(p.tools, std::vector<std::string>{"grasp"});
  const Submission s = read_submission(t.submission, p);
  EXPECT_EQ(s.frames, (std::vector<int>{1, 2}));
  ASSERT_EQ(s.displacements.size(), 2u);
  EXPECT_EQ(s.displacements[1](2, 2), 0.0026);
  EXPECT_EQ(s.displacements[1](3, 2), 0.0024);
  ASSERT_EQ(s.forces.size(), 2u);
  EXPECT_EQ(s.forces[1](0, 2), 1.0);
}

TEST(Submission, ScoresToTheHandComputedValues) {
  const nlohmann::json score = Tiny().score();
  EXPECT_EQ(score["frame"], 2);
  EXPECT_NEAR(score["rel_l2_converged"].get<double>(), 0.2, 1e-12);  // tests/submission_fixture.h
  EXPECT_NEAR(score["probe_error_mm"].get<double>(), 0.4, 1e-12);
  EXPECT_TRUE(std::isnan(score["bead_rms_mm"].get<double>()));
  EXPECT_EQ(score["converged_run"], "P2 L1");
  const nlohmann::json& timing = score["timing"];
  EXPECT_EQ(timing["self_reported"], true);
  EXPECT_DOUBLE_EQ(timing["factor"].get<double>(), 0.5);  // 100 ms here, 200 ms theirs
  EXPECT_DOUBLE_EQ(timing["frame_median_ms"]["normalised"].get<double>(), 5.0);
  EXPECT_DOUBLE_EQ(timing["setup_s"]["normalised"].get<double>(), 0.75);
  EXPECT_EQ(score["tool_forces_n"]["at_frame"]["grasp"], nlohmann::json({0.0, 0.0, 1.0}));
  const std::string summary = score_summary(score);
  EXPECT_NE(summary.find("rel L2 vs converged  0.2"), std::string::npos) << summary;
}

TEST(Submission, TheConvergedValuesScoreZero) {
  const Tiny t;
  t.replace("displacements.csv", "2,s2,0,0,0.0026", "2,s2,0,0,0.002");
  t.replace("displacements.csv", "2,p0,0.001,0.002,0.0024", "2,p0,0.001,0.002,0.002");
  const nlohmann::json score = t.score();
  EXPECT_EQ(score["rel_l2_converged"].get<double>(), 0.0);
  EXPECT_EQ(score["probe_error_mm"].get<double>(), 0.0);
}

TEST(Submission, RowsInAnyOrderWithinAFrameAndBlanksAroundCells) {
  const Tiny t;
  t.write("displacements.csv",
          "frame,id,ux,uy,uz\r\n1,p0,0.0005,0.001,0.0012\r\n1,s2,0,0,0.0013\n1,s1,0,0.001,0\n1,s0,0.0005,0,0\n\n"
          "2, s1, 0, 0.002, 0\n2,s0,0.001,0,0\n2,p0,0.001,0.002,0.0024\n2,s2,0,0,0.0026\n");
  EXPECT_NEAR(t.score()["rel_l2_converged"].get<double>(), 0.2, 1e-12);
}

TEST(Submission, NoRoleScoresNothingWithANote) {
  const Tiny t;
  const std::string problem = in_dir(t.package, "problem.json");
  std::ifstream in(problem);
  std::string text{std::istreambuf_iterator<char>(in), {}};
  const std::string role = "\"role\": \"tiny_role\"";
  text.replace(text.find(role), role.size(), "\"role\": \"\"");
  write_text(problem, text);
  t.replace("submission.json", "\"role\": \"tiny_role\"", "\"role\": \"\"");
  const nlohmann::json score = t.score();
  EXPECT_TRUE(std::isnan(score["rel_l2_converged"].get<double>()));
  EXPECT_NE(score["note"].get<std::string>().find("no suite role"), std::string::npos);
}

// The Truth Cube's beads: a bead table of two beads in a temporary data directory,
// the frame the identity (mm to m): bead 0 measured 1 mm lower at 5% strain, bead 1
// 2 mm lower; the submission moves bead 0 by exactly that and bead 1 not at all, so
// the RMS is sqrt((0 + 2^2) / 2) mm.
TEST(Submission, BeadRmsAgainstTheMeasuredBeads) {
  const Tiny t;
  fs::create_directories(t.root / "data/data/truthcube");
  write_text(t.root / "data/data/truthcube/uniaxial_positions.csv",
             "a bead table written by tests/experiments/submission_test.cc,,,,,,\n,,,,,,\n,,,,,,\n,,,,,,\n,,,,,,\n"
             "bead nominal location,,,no strain,,,5% strain,,\ni,j,k,x0,y0,z0,x1,y1,z1\n"
             "1,1,1,0,0,10,0,0,9\n2,1,1,0,0,20,0,0,18\n");
  write_text(in_dir(t.answers, "tiny_role_interior.csv"), "id,patch,table_row,ux,uy,uz\np0,interior,1,0,0,-0.002\n");
  write_text(in_dir(t.answers, "tiny_role.json"),
             R"({"converged": null, "note": "", "compare_at_strain": 0.05,
                 "frame": {"origin_mm": [0, 0, 0], "centre_m": [0, 0, 0], "axes": [1, 1, 1]}})");
  // One bead (the package's one interior point, p0, at table row 1), moved by -1 mm
  // where it was measured 2 mm lower: 1 mm off.
  t.replace("displacements.csv", "2,p0,0.001,0.002,0.0024", "2,p0,0,0,-0.001");
  const nlohmann::json score = t.score();
  EXPECT_NEAR(score["bead_rms_mm"].get<double>(), 1.0, 1e-9);
  EXPECT_NEAR(score["probe_error_mm"].get<double>(), 1.0, 1e-9);  // against the answers' -2 mm
  // The table-free formula, on two beads: sqrt((0 + 2^2) / 2).
  const TruthCubeTable table = read_truth_cube_table(t.root / "data/data/truthcube/uniaxial_positions.csv");
  Points u(2, 3);
  u << 0, 0, -0.001, 0, 0, 0;
  EXPECT_NEAR(bead_rms_mm(table, nlohmann::json::parse(R"({"compare_at_strain": 0.05, "frame":
      {"origin_mm": [0, 0, 0], "centre_m": [0, 0, 0], "axes": [1, 1, 1]}})"),
                          {0, 1}, u),
              std::sqrt(2.0), 1e-9);
}

/// The committed converged field of a role against itself: 0; twice it: 1; against a
/// zero field: NaN (metrics.compare's rel_l2).
TEST(Submission, CommittedConvergedFieldScoresZero) {
  const std::string answers = (fs::path(TB_SOURCE_DIR) / "results" / "observation_points").string();
  const ObservationAnswers a = read_observation_answers(answers, "cube_pull_disc");
  ASSERT_EQ(a.surface.u.rows(), static_cast<Eigen::Index>(a.surface.ids.size()));
  EXPECT_EQ(relative_l2(a.surface.u, a.surface.u), 0.0);
  EXPECT_NEAR(relative_l2(2 * a.surface.u, a.surface.u), 1.0, 1e-12);
  EXPECT_TRUE(std::isnan(relative_l2(a.surface.u, Points::Zero(a.surface.u.rows(), 3))));
}

// ---- malformed submissions ----

/// The reader's message for the tiny submission after `change`; "" if it was accepted.
std::string refusal(const std::function<void(const Tiny&)>& change, bool with_tool = true) {
  const Tiny t(with_tool);
  change(t);
  try {
    read_submission(t.submission, read_problem_package(t.package));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

struct Bad {
  std::string what;
  std::function<void(const Tiny&)> change;
  std::string file;     ///< the file the message must name
  std::string line;     ///< "line <n>" it must name, or a key path; "" if none
  std::string problem;  ///< a part of the problem's wording
};

void expect_refused(const Bad& b, bool with_tool = true) {
  SCOPED_TRACE(b.what);
  const std::string m = refusal(b.change, with_tool);
  ASSERT_FALSE(m.empty()) << "accepted";
  EXPECT_EQ(m.find_first_of("\r\n"), std::string::npos) << m;
  EXPECT_NE(m.find(b.file), std::string::npos) << m;
  EXPECT_NE(m.find(b.line), std::string::npos) << m;
  EXPECT_NE(m.find(b.problem), std::string::npos) << m;
}

auto replace(const std::string& name, const std::string& from, const std::string& to) {
  return [=](const Tiny& t) { t.replace(name, from, to); };
}
auto rewrite(const std::string& name, const std::string& text) {
  return [=](const Tiny& t) { t.write(name, text); };
}

TEST(SubmissionErrors, Folder) {
  const std::vector<Bad> cases = {
      {"no submission.json", [](const Tiny& t) { fs::remove(in_dir(t.submission, "submission.json")); },
       "submission.json", "", "missing"},
      {"no displacements.csv", [](const Tiny& t) { fs::remove(in_dir(t.submission, "displacements.csv")); },
       "displacements.csv", "", "missing"},
      {"no forces.csv", [](const Tiny& t) { fs::remove(in_dir(t.submission, "forces.csv")); }, "forces.csv", "",
       "missing"},
      {"an extra file", rewrite("notes.txt", "hello\n"), "notes.txt", "", "unexpected file"},
      {"a folder", [](const Tiny& t) { fs::remove_all(t.submission), write_text(t.submission, "x"); }, "submission", "",
       "not a folder"},
  };
  for (const Bad& b : cases) expect_refused(b);
  expect_refused({"forces.csv without tools", rewrite("forces.csv", "frame,tool,fx,fy,fz\n"), "forces.csv", "",
                  "the scenario has no tools"},
                 false);
  // score.json, which score writes, may stay: scoring twice reads the same folder.
  EXPECT_EQ(refusal(rewrite("score.json", "{}")), "");
}

TEST(SubmissionErrors, SubmissionJson) {
  const std::string f = "submission.json";
  const std::vector<Bad> cases = {
      {"malformed JSON", replace(f, "\"method\": \"hand-written\",", "\"method\": hand-written,"), f, "line 5",
       "malformed JSON"},
      {"not an object", rewrite(f, "[]"), f, "", "must be a JSON object"},
      {"a missing key", replace(f, "\"method\": \"hand-written\",", ""), f, "method", "missing"},
      {"an unknown key", replace(f, "\"threads\": 1,", "\"threads\": 1, \"gpu\": true,"), f, "gpu", "unknown key"},
      {"no units",
       replace(f, "\"units\": {\"length\": \"m\", \"force\": \"N\", \"time\": \"ms\", \"memory\": \"MiB\"},", ""), f,
       "units", "missing"},
      {"a unit missing", replace(f, ", \"time\": \"ms\"", ""), f, "units.time", "missing"},
      {"a unit not the contract's", replace(f, "\"length\": \"m\"", "\"length\": \"mm\""), f, "units.length",
       "'mm' is not one of m"},
      {"time in seconds", replace(f, "\"time\": \"ms\"", "\"time\": \"s\""), f, "units.time", "not one of ms"},
      {"an unknown unit", replace(f, "\"memory\": \"MiB\"", "\"memory\": \"MiB\", \"angle\": \"rad\""), f, "angle",
       "unknown key"},
      {"another format", replace(f, "tissuebench-submission/1", "tissuebench-submission/2"), f, "format", "not one of"},
      {"another scenario", replace(f, "\"scenario\": \"tiny\"", "\"scenario\": \"huge\""), f, "scenario",
       "the package is scenario 'tiny'"},
      {"another role", replace(f, "\"role\": \"tiny_role\"", "\"role\": \"cube\""), f, "role", "package's role"},
      {"a string for a number", replace(f, "\"frame_median_ms\": 10", "\"frame_median_ms\": \"10\""), f,
       "timing.frame_median_ms", "must be a number"},
      {"p95 below the median", replace(f, "\"frame_p95_ms\": 12", "\"frame_p95_ms\": 8"), f, "timing.frame_p95_ms",
       "below"},
      {"a fractional count", replace(f, "\"tets\": 0", "\"tets\": 0.5"), f, "resolution.tets", "integer"},
      {"no threads", replace(f, "\"threads\": 1", "\"threads\": 0"), f, "threads", "out of range"},
      {"a zero calibration", replace(f, "\"figure_ms\": 200", "\"figure_ms\": 0"), f, "calibration.figure_ms",
       "out of range"},
      {"another calibration command", replace(f, "tissuebench calibrate", "my stopwatch"), f, "calibration.command",
       "not one of"},
      {"too large", [f](const Tiny& t) { t.write(f, t.read(f) + std::string(size_t{1} << 20, ' ')); }, f, "",
       "bytes, more than"},
  };
  for (const Bad& b : cases) expect_refused(b);
}

TEST(SubmissionErrors, DisplacementsCsv) {
  const std::string f = "displacements.csv";
  const std::vector<Bad> cases = {
      {"empty", rewrite(f, ""), f, "", "truncated file"},
      {"another header", replace(f, "frame,id,ux,uy,uz", "frame,id,x,y,z"), f, "line 1", "expected the header"},
      {"a missing column", replace(f, "1,s1,0,0.001,0", "1,s1,0,0.001"), f, "line 3", "4 cells, the header has 5"},
      {"an extra column", replace(f, "1,s1,0,0.001,0", "1,s1,0,0.001,0,7"), f, "line 3", "6 cells"},
      {"a non-numeric value", replace(f, "1,s1,0,0.001,0", "1,s1,0,abc,0"), f, "line 3", "uy: expected a number"},
      {"NaN", replace(f, "1,s1,0,0.001,0", "1,s1,0,0.001,nan"), f, "line 3", "uz is NaN or Inf"},
      {"inf", replace(f, "1,s1,0,0.001,0", "1,s1,-inf,0.001,0"), f, "line 3", "ux is NaN or Inf"},
      {"beyond double", replace(f, "1,s1,0,0.001,0", "1,s1,1e400,0.001,0"), f, "line 3", "ux: expected a number"},
      {"a fractional frame", replace(f, "1,s1,0,0.001,0", "1.5,s1,0,0.001,0"), f, "line 3",
       "frame: expected an integer"},
      {"an unknown id", replace(f, "1,s1,0,0.001,0", "1,s9,0,0.001,0"), f, "line 3",
       "'s9' is not one of the package's observation points"},
      {"an id twice in a frame", replace(f, "1,s1,0,0.001,0", "1,s0,0,0.001,0"), f, "line 3", "'s0' twice in frame 1"},
      {"an id missing in a frame", replace(f, "1,s1,0,0.001,0\n", ""), f, "line 5",
       "frame 1 has no row for observation point 's1'"},
      {"an id missing in the last frame", replace(f, "2,p0,0.001,0.002,0.0024\n", ""), f, "line 8",
       "frame 2 has no row for observation point 'p0'"},
      {"frames decreasing",
       rewrite(f, "frame,id,ux,uy,uz\n2,s0,0,0,0\n2,s1,0,0,0\n2,s2,0,0,0\n2,p0,0,0,0\n1,s0,0,0,0\n"), f, "line 6",
       "frame 1 after frame 2: frames must increase"},
      {"a frame's rows apart", replace(f, "1,p0,0.0005,0.001,0.0012\n2,s0,0.001,0,0\n", "2,s0,0.001,0,0\n1,p0,0,0,0\n"),
       f, "line 5", "frame 1 has no row for observation point 'p0'"},
      {"a frame beyond the scenario", replace(f, "2,s0", "3,s0"), f, "line 6",
       "frame 3 is not a frame of the scenario"},
      {"a negative frame", replace(f, "1,s0", "-1,s0"), f, "line 2", "frame -1 is not a frame"},
      {"an observation frame missing",
       rewrite(f, "frame,id,ux,uy,uz\n1,s0,0,0,0\n1,s1,0,0,0\n1,s2,0,0,0\n1,p0,0,0,0\n"), f, "",
       "no rows for frame 2, an observation frame"},
      {"header only", rewrite(f, "frame,id,ux,uy,uz\n"), f, "", "no rows for frame 1"},
      {"too large", [f](const Tiny& t) { t.write(f, t.read(f) + std::string(size_t{1} << 20, '\n')); }, f, "",
       "bytes, more than"},
  };
  for (const Bad& b : cases) expect_refused(b);
}

TEST(SubmissionErrors, ForcesCsv) {
  const std::string f = "forces.csv";
  const std::vector<Bad> cases = {
      {"another header", replace(f, "frame,tool,fx,fy,fz", "frame,tool,fx,fy"), f, "line 1", "expected the header"},
      {"an unknown tool", replace(f, "2,grasp", "2,plate"), f, "line 3", "'plate' is not one of the package's tools"},
      {"a tool twice", replace(f, "2,grasp,0,0,1\n", "2,grasp,0,0,1\n2,grasp,0,0,1\n"), f, "line 4",
       "'grasp' twice in frame 2"},
      {"NaN", replace(f, "2,grasp,0,0,1", "2,grasp,0,nan,1"), f, "line 3", "fy is NaN or Inf"},
      {"non-numeric", replace(f, "2,grasp,0,0,1", "2,grasp,0,0,one"), f, "line 3", "fz: expected a number"},
      {"a frame missing", replace(f, "2,grasp,0,0,1\n", ""), f, "", "but displacements.csv reports 1, 2"},
      {"frames decreasing", rewrite(f, "frame,tool,fx,fy,fz\n2,grasp,0,0,1\n1,grasp,0,0,1\n"), f, "line 3",
       "frames must increase"},
  };
  for (const Bad& b : cases) expect_refused(b);
}

/// The package `tissuebench export` writes for the suite's pulled cube, and a submission
/// of the committed converged field at its observation frame: 0; and of 0.9 times it: 0.1.
/// The export's problem.json and point files are read as score reads them (the contract
/// between the two, docs/benchmark_format.md).
TEST(SubmissionCommand, AnExportedPackageScoresTheConvergedFieldToZero) {
  const testing::TempFolder root("submission-export");
  std::string out;
  ASSERT_EQ(
      testing::run_tissuebench("export " + std::string(TB_SOURCE_DIR) +
                                   "/experiments/suite.json --scenario cube_pull_disc --quiet --out " + (root / "pk"),
                               out),
      0)
      << out;
  const std::string package = root / "pk/suite-cube-pull-disc";
  const ProblemPackage p = read_problem_package(package);
  EXPECT_EQ(p.role, "cube_pull_disc");
  EXPECT_TRUE(p.tools.empty());
  const ObservationAnswers a =
      read_observation_answers((fs::path(TB_SOURCE_DIR) / "results" / "observation_points").string(), p.role);
  for (const double scale : {1.0, 0.9}) {
    const std::string dir = root / ("scaled-" + std::to_string(scale));
    fs::create_directories(dir);
    std::string json = testing::tiny_submission()["submission.json"];
    for (const auto& [from, to] : {std::pair<std::string, std::string>{"\"tiny\"", "\"" + p.scenario + "\""},
                                   {"\"tiny_role\"", "\"" + p.role + "\""}})
      json.replace(json.find(from), from.size(), to);
    write_text(in_dir(dir, "submission.json"), json);
    std::ostringstream csv;
    csv << std::setprecision(17) << "frame,id,ux,uy,uz\n";
    for (size_t k = 0; k < a.surface.ids.size(); ++k) {
      const auto u = (scale * a.surface.u.row(static_cast<Eigen::Index>(k))).eval();
      csv << p.observation_frames.back() << "," << a.surface.ids[k] << "," << u(0) << "," << u(1) << "," << u(2)
          << "\n";
    }
    write_text(in_dir(dir, "displacements.csv"), csv.str());
    ASSERT_EQ(testing::run_tissuebench("score " + dir + " --package " + package + " --calibration 100", out), 0) << out;
    std::ifstream written(in_dir(dir, "score.json"));
    EXPECT_NEAR(nlohmann::json::parse(written)["rel_l2_converged"].get<double>(), 1 - scale, 1e-12) << out;
  }
}

/// submission.schema.json and the reader agree: the schema's keys are the fixture's,
/// key for key, and each key it requires the reader requires too.
TEST(SubmissionSchema, TheSchemasKeysAreTheReadersKeys) {
  std::ifstream in(fs::path(TB_SOURCE_DIR) / "docs/schemas/submission.schema.json");
  const nlohmann::json schema = nlohmann::json::parse(in);
  const nlohmann::json valid = nlohmann::json::parse(testing::tiny_submission()["submission.json"]);
  std::function<void(const nlohmann::json&, const nlohmann::json&, const std::vector<std::string>&)> walk =
      [&](const nlohmann::json& s, const nlohmann::json& value, const std::vector<std::string>& path) {
        std::string where;
        for (const std::string& k : path) where += "." + k;
        SCOPED_TRACE(where);
        if (s.contains("const")) {
          EXPECT_EQ(s["const"], value);
        }
        if (!s.contains("properties")) return;
        EXPECT_EQ(s["additionalProperties"], false);
        std::set<std::string> keys, properties;
        for (const auto& [k, v] : value.items()) keys.insert(k);
        for (const auto& [k, v] : s["properties"].items()) properties.insert(k);
        EXPECT_EQ(keys, properties);
        for (const std::string key : s["required"]) {
          nlohmann::json without = valid;
          nlohmann::json* parent = &without;
          for (const std::string& k : path) parent = &(*parent)[k];
          parent->erase(key);
          const std::string m = refusal([&](const Tiny& t) { t.write("submission.json", without.dump()); });
          EXPECT_NE(m.find("submission.json" + where + "." + key + ": missing"), std::string::npos) << m;
        }
        for (const auto& [k, v] : s["properties"].items())
          if (value.contains(k)) {
            std::vector<std::string> inner = path;
            inner.push_back(k);
            walk(v, value[k], inner);
          }
      };
  walk(schema, valid, {});
}

// The command line: a bad submission is one line "tissuebench: <file>: line <n>:
// <problem>" and exit status 1; a good one prints the summary and writes score.json.
TEST(SubmissionCommand, ScoreAndCalibrate) {
  const Tiny t;
  const std::string args = t.submission + " --package " + t.package + " --answers " + t.answers + " --calibration 100";
  std::string out;
  ASSERT_EQ(testing::run_tissuebench("score " + args, out), 0) << out;
  EXPECT_NE(out.find("rel L2 vs converged  0.2"), std::string::npos) << out;
  std::ifstream written(in_dir(t.submission, "score.json"));
  ASSERT_TRUE(written) << out;
  EXPECT_NEAR(nlohmann::json::parse(written)["rel_l2_converged"].get<double>(), 0.2, 1e-12);

  t.replace("displacements.csv", "2,s1,0,0.002,0", "2,s1,0,0.002,zero");
  ASSERT_EQ(testing::run_tissuebench("score " + args, out), 1) << out;
  EXPECT_EQ(out.find('\n'), out.size() - 1) << out;
  EXPECT_EQ(out.rfind("tissuebench: ", 0), 0u) << out;
  EXPECT_NE(out.find("displacements.csv: line 7: uz: expected a number"), std::string::npos) << out;

  ASSERT_EQ(testing::run_tissuebench("calibrate --repeats 1", out), 0) << out;
  const nlohmann::json c = nlohmann::json::parse(out);
  EXPECT_GT(c["figure_ms"].get<double>(), 0);
  EXPECT_EQ(c["repeats"], 1);
  EXPECT_TRUE(c["machine"].contains("cpu"));
}

TEST(Calibration, FigureFromANumberOrCalibratesJson) {
  const testing::TempFolder dir("calibration");
  EXPECT_EQ(calibration_figure("123.5"), 123.5);
  write_text(dir / "c.json", R"({"figure_ms": 80, "repeats": 3})");
  EXPECT_EQ(calibration_figure(dir / "c.json"), 80);
  for (const std::string& bad : {std::string("0"), std::string("-3"), dir / "missing.json"}) {
    try {
      calibration_figure(bad);
      ADD_FAILURE() << bad << " accepted";
    } catch (const std::exception& e) {
      EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace tb
