// The build and machine a result was produced on, written into every run.json.
#pragma once

#include <nlohmann/json.hpp>

namespace tb {
nlohmann::json build_and_machine_info();
/// The process's peak resident memory (MiB, getrusage): since it started or since
/// the last reset_peak_memory(), which resets this high-water mark too.
double process_peak_memory_mib();
/// Starts a new peak of this process's resident memory: the memory malloc holds
/// freed is returned to the kernel (malloc_trim), then Linux resets VmHWM when "5"
/// is written to /proc/self/clear_refs (proc(5)). False where that is refused.
bool reset_peak_memory();
/// The machine's load average over the last minute (getloadavg(3)); NaN where unknown.
double load_average_1min();
/// This process's peak resident memory since the last reset_peak_memory() (VmHWM in
/// /proc/self/status), MiB; the peak since it started if never reset; NaN if unreadable.
double peak_memory_since_reset_mib();
}  // namespace tb
