// Every fuzz target (tb_fuzz, fuzz_scenario): the mesh readers', the scenario loader's and the
// submission reader's.
#include "fuzz_targets.h"

namespace tb::fuzz {

const std::vector<Target>& targets() {
  static const std::vector<Target> all = [] {
    std::vector<Target> t = mesh_targets();
    t.push_back(scenario_target());
    t.push_back(probes_target());
    t.push_back(truth_cube_target());
    t.push_back(submission_target());
    return t;
  }();
  return all;
}

}  // namespace tb::fuzz
