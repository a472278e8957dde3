// Every key of scenario and experiment files, per object. The loader reads no
// other key: StrictObject checks each key it reads against this table (a key read
// but not declared here is a programming error), and finish() rejects the keys a
// file gives that were not read. docs/scenario_schema.md documents every key of
// this table, with its type, default, range and meaning; a test compares the two.
#pragma once

#include <map>
#include <string>
#include <vector>

namespace tb {

/// {object: keys}. Objects are named by their path from the file's root:
/// "scenario", "scenario.mesh", "scenario.models[]" (an element of the array),
/// "experiment", "experiment.sweep.factors[]" ...
const std::map<std::string, std::vector<std::string>>& file_schema();

}  // namespace tb
