// tissuebench.load(): a scenario or experiment file read and resolved by the
// loader the tissuebench program uses (experiments/scenario.h, load_experiment),
// as an Experiment holding its Scenarios.
#include <pybind11/stl.h>

#include <memory>
#include <optional>
#include <stdexcept>
#include <string>

#include "python_bindings.h"
#include "scenario.h"

namespace tb::python {
namespace {

/// `overrides` as load_experiment takes them ([[key, value], ...], `tissuebench run
/// --set`): from a dict {key: value} or a list of [key, value] pairs; None: none.
nlohmann::json overrides_of(const py::object& overrides) {
  nlohmann::json out = nlohmann::json::array();
  if (overrides.is_none()) return out;
  const nlohmann::json given = from_python(overrides, "overrides");
  const char* expected = "overrides: expected a dict {key: value} or a list of [key, value] pairs (key a string)";
  if (given.is_object()) {
    for (const auto& [key, value] : given.items()) out.push_back({key, value});
    return out;
  }
  if (!given.is_array()) throw std::invalid_argument(expected);
  for (const nlohmann::json& pair : given) {
    if (!pair.is_array() || pair.size() != 2 || !pair[0].is_string()) throw std::invalid_argument(expected);
    out.push_back(pair);
  }
  return out;
}

py::list cases_of(const Scenario& s) {
  py::list out;
  for (const ModelRun& run : s.models) {
    py::dict d;
    d["name"] = run.case_name;
    d["model"] = run.model;
    d["parameters"] = to_python(run.parameters.to_json());
    d["parameters_given"] = to_python(run.parameters_given);
    d["max_frames"] = run.max_frames;
    out.append(d);
  }
  return out;
}

/// The experiment's scenarios, each keeping the experiment alive (aliasing pointers).
std::vector<std::shared_ptr<Scenario>> scenarios_of(const std::shared_ptr<Experiment>& e) {
  std::vector<std::shared_ptr<Scenario>> out;
  for (Scenario& s : e->scenarios) out.emplace_back(e, &s);
  return out;
}

}  // namespace

void bind_scenarios(py::module_& m) {
  py::class_<Scenario, std::shared_ptr<Scenario>>(
      m, "Scenario",
      "One scenario of a loaded file, every value resolved (its `extends` merged, the experiment's models and "
      "overrides applied). Run one of its cases with tissuebench.Run(scenario, case_name).")
      .def_property_readonly("name", [](const Scenario& s) { return s.name; })
      .def_property_readonly(
          "role", [](const Scenario& s) { return s.role; },
          "its role in the experiment (how the analysis finds it); '' when the experiment gives none")
      .def_property_readonly("description", [](const Scenario& s) { return s.description; })
      .def_property_readonly(
          "file", [](const Scenario& s) { return s.file; }, "the scenario file it was read from")
      .def_property_readonly("cases", &cases_of,
                             "its cases in run order: dicts of name, model, parameters (every declared one, "
                             "resolved), parameters_given (those the file set) and max_frames (0: the scenario's)")
      .def_property_readonly(
          "case_names",
          [](const Scenario& s) {
            std::vector<std::string> out;
            for (const ModelRun& run : s.models) out.push_back(run.case_name);
            return out;
          },
          "the cases' names, in run order")
      .def_property_readonly(
          "not_run",
          [](const Scenario& s) {
            py::list out;
            for (const auto& [name, reason] : s.not_run) {
              py::dict d;
              d["case"] = name;
              d["reason"] = reason;
              out.append(d);
            }
            return out;
          },
          "cases left out because their model does not take a load or tool of the scenario (an experiment "
          "with \"unsupported_cases\": \"skip\"): dicts of case and reason")
      .def(
          "to_json", [](const Scenario& s) { return to_python(s.to_json_with_models()); },
          "every value as resolved, defaults included, and its cases: a dict, what `tissuebench resolve` prints "
          "for the scenario")
      .def("__repr__", [](const Scenario& s) {
        return "<tissuebench.Scenario '" + s.name + "', " + std::to_string(s.models.size()) + " cases>";
      });

  py::class_<Experiment, std::shared_ptr<Experiment>>(
      m, "Experiment", "A loaded scenario or experiment file (a scenario file is an experiment of one scenario).")
      .def_property_readonly("name", [](const Experiment& e) { return e.name; })
      .def_property_readonly("description", [](const Experiment& e) { return e.description; })
      .def_property_readonly(
          "reference", [](const Experiment& e) { return e.reference; },
          "the case the analysis compares every other with; '' when none is declared")
      .def_property_readonly("scenarios", &scenarios_of, "its Scenarios, in file order")
      .def(
          "scenario",
          [](const std::shared_ptr<Experiment>& e, const std::string& name) {
            std::string known;
            for (Scenario& s : e->scenarios) {
              if (s.name == name || (!s.role.empty() && s.role == name)) return std::shared_ptr<Scenario>(e, &s);
              known += (known.empty() ? "" : ", ") + s.name;
            }
            throw std::invalid_argument("experiment '" + e->name + "' has no scenario named '" + name +
                                        "' (its scenarios: " + known + ")");
          },
          py::arg("name"), "the scenario of this name or role; tissuebench.Error if none")
      .def(
          "to_json", [](const Experiment& e) { return to_python(e.to_json()); },
          "the index the analysis reads (results/<name>/experiment.json): name, description, reference, and per "
          "scenario its name, file, role and cases in run order")
      .def("__repr__", [](const Experiment& e) {
        return "<tissuebench.Experiment '" + e.name + "', " + std::to_string(e.scenarios.size()) + " scenarios>";
      });

  m.def(
      "load",
      [](const py::object& path, const std::optional<std::string>& data_dir, const py::object& overrides) {
        const std::string file = py::str(py::module_::import("os").attr("fspath")(path));
        const nlohmann::json settings = overrides_of(overrides);
        return std::make_shared<Experiment>(load_experiment(file, tb::data_dir(data_dir.value_or("")), settings));
      },
      py::arg("path"), py::arg("data_dir") = py::none(), py::arg("overrides") = py::none(),
      R"(Reads a scenario or an experiment file as `tissuebench run` does: its "extends" followed,
an experiment's models combined with each scenario's, every value resolved and checked
strictly (docs/scenario_schema.md). Returns an Experiment.

path       the file (str or os.PathLike)
data_dir   where "data:" references are read from (default: $TISSUEBENCH_DATA, else
           ../shared beside the repository), as `--data-dir`
overrides  keys set in every scenario, as `tissuebench run --set KEY=VALUE`: a dict
           {"frames.static": 3} or a list of [key, value] pairs, applied in order

Raises tissuebench.Error, one line naming the file and the key, on any bad input.)");
}

}  // namespace tb::python
