// The fuzz targets: one entry point per reader of user input (docs/robustness.md).
// Each takes bytes, writes them where its reader looks (a file in a workspace
// folder), reads them, and runs what the runner runs next on what was read (the
// surface checks, the tet checks). The contract every reader keeps: it returns a
// result, or throws a std::exception whose message is one non-empty line naming the
// file. Anything else is a finding: another exception, a message of several lines,
// without the file's name or empty; and, seen by the drivers, a crash, a sanitizer
// report, a hang or an allocation beyond the bound.
//
// Two drivers run the same entry points: libFuzzer (libfuzzer_main.cc, built with
// -DTB_LIBFUZZER=ON and clang) and the deterministic mutator over the committed seed
// corpus that CTest runs (fuzz_driver.cc, mutator.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace tb::fuzz {

/// A fresh folder for the inputs' files, removed at destruction. The scenario
/// target's fixed companion files (a base scenario to extend, a probes file, a
/// surface, a data directory) are copied in from `aux_dir` when it is given.
class Workspace {
 public:
  explicit Workspace(const std::string& aux_dir = "");
  ~Workspace();
  Workspace(const Workspace&) = delete;
  Workspace& operator=(const Workspace&) = delete;
  /// The path of `name` inside the workspace.
  std::string path(const std::string& name) const;
  /// Writes `bytes` to `name` (replacing it); returns its path.
  std::string write(const std::string& name, const std::string& bytes) const;
  const std::string& dir() const { return dir_; }

 private:
  std::string dir_;
};

struct Target {
  std::string name;         ///< e.g. "obj": the corpus folder tests/fuzz/corpus/<name>/
  std::string description;  ///< which reader, for --list and the robustness table
  /// Reads `bytes` as its format; throws what the reader throws.
  std::function<void(const std::string& bytes, const Workspace& workspace)> run;
  /// The file names one of which every error message must contain.
  std::vector<std::string> files;
  /// The format's keywords, spliced in by the mutator (and written as a libFuzzer
  /// dictionary by `tb_fuzz --write-dictionaries`).
  std::vector<std::string> dictionary;
  /// The workspace holds the scenario companions (tests/fuzz/corpus/scenario_aux/).
  bool companions = false;
};

/// Every target, in the order of the robustness table (all_targets.cc; the
/// libFuzzer binaries of the mesh readers link mesh_targets_only.cc instead).
const std::vector<Target>& targets();
/// The mesh readers' targets (fuzz_targets.cc).
std::vector<Target> mesh_targets();
/// The scenario loader's target, and its probe-point CSV reader's (scenario_target.cc).
Target scenario_target();
Target probes_target();
/// The Truth Cube bead table's target (scenario_target.cc).
Target truth_cube_target();
/// The benchmark submission's target (submission_target.cc).
Target submission_target();
/// The target called `name`; throws std::invalid_argument listing the names.
const Target& find_target(const std::string& name);

struct Outcome {
  enum class Kind { Accepted, Rejected, Finding };
  Kind kind = Kind::Accepted;
  /// Rejected: the reader's message; Finding: what broke the contract.
  std::string message;
};

/// Runs one input through `target` and judges the result against the contract.
Outcome run_input(const Target& target, const std::string& bytes, const Workspace& workspace);

/// A rejection's message with its variable parts taken out, to count distinct kinds
/// of error (both drivers): the workspace folder, quoted text (as '...') and numbers
/// (as #).
std::string message_kind(std::string message, const std::string& workspace);

/// The TetGen target's input holds the .node file, this line, then the .ele file.
inline constexpr const char* kTetgenSeparator = "\n#--ele--\n";
/// The submission target's input: submission.json, then this and "displacements.csv\n",
/// the CSV, then this and "forces.csv\n", the CSV.
inline constexpr const char* kSubmissionSeparator = "\n#--";

}  // namespace tb::fuzz
