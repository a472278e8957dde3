// The build and machine a result was produced on, written into every run.json.
#pragma once

#include <nlohmann/json.hpp>

namespace tb {
nlohmann::json build_and_machine_info();
/// The process's peak resident memory so far (MiB).
double process_peak_memory_mib();
}  // namespace tb
