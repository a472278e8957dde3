// The parts of the Python module tissuebench (module.cc), one function per area,
// and the JSON <-> Python conversion they share.
#pragma once

#include <pybind11/pybind11.h>

#include <nlohmann/json.hpp>

namespace tb::python {
namespace py = pybind11;

/// tissuebench.models() (registry_binding.cc).
void bind_registry(py::module_& m);
/// tissuebench.load(), Experiment and Scenario (scenario_binding.cc).
void bind_scenarios(py::module_& m);
/// tissuebench.Run (run_binding.cc).
void bind_run(py::module_& m);

/// `value` as Python's json.loads reads its text: dict, list, str, int, float, bool, None.
py::object to_python(const nlohmann::json& value);
/// A Python value of those types as JSON (through json.dumps). Throws tissuebench.Error
/// naming `what` when Python's json module cannot write it.
nlohmann::json from_python(const py::handle& value, const std::string& what);

}  // namespace tb::python
