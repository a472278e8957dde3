// The build and machine a result was produced on, written into every run.json.
#pragma once

#include <nlohmann/json.hpp>

namespace tb {
nlohmann::json build_and_machine_info();
}
