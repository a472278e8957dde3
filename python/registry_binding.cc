// tissuebench.models(): the registry (models/registry.cc) as data, what
// `tissuebench models` prints (experiments/tissuebench_main.cc, command_models).
#include <pybind11/stl.h>

#include "load_case.h"
#include "model.h"
#include "python_bindings.h"

namespace tb::python {
namespace {

py::object text_or_none(const std::string& text) {
  if (text.empty()) return py::none();
  return py::str(text);
}

py::dict parameter_of(const ParameterSpec& p) {
  py::dict d;
  d["name"] = p.name;
  d["description"] = p.description;
  if (p.is_choice()) {
    d["type"] = "choice";
    d["default"] = p.default_choice;
    d["choices"] = p.choices;
  } else if (p.integer) {
    d["type"] = "integer";
    d["default"] = static_cast<long long>(p.default_number);
    d["min"] = static_cast<long long>(p.min);
    d["max"] = static_cast<long long>(p.max);
  } else {
    d["type"] = "number";
    d["default"] = p.default_number;
    d["min"] = p.min;
    d["max"] = p.max;
  }
  return d;
}

py::dict model_of(const ModelInfo& m) {
  py::dict d;
  d["name"] = m.name;
  d["dynamic"] = m.dynamic;
  d["description"] = m.description;
  d["spans_ranks"] = m.spans_ranks;
  py::list loads, tools, parameters;
  for (LoadKind k : m.loads) loads.append(name(k));
  for (ToolKind k : m.tools) tools.append(name(k));
  for (const ParameterSpec& p : m.parameters) parameters.append(parameter_of(p));
  d["loads"] = loads;
  d["tools"] = tools;
  d["tools_how"] = m.tools_how;
  // None where the model does not measure them / has no volume (`tissuebench models`:
  // "not measured", "none (no volume)").
  d["reactions"] = text_or_none(m.reactions);
  d["probes"] = text_or_none(m.probes);
  d["parameters"] = parameters;
  return d;
}

}  // namespace

void bind_registry(py::module_& m) {
  m.def(
      "models",
      [] {
        py::list out;
        for (const ModelInfo& info : registered_models()) out.append(model_of(info));
        return out;
      },
      R"(The registered models, in the registry's order (models/registry.cc): a list of dicts with
name, dynamic (runs until steady, else one solve a frame), description, spans_ranks, loads
and tools (the kinds it takes), tools_how, reactions and probes (how it measures them, or
None), and parameters: each a dict of name, description, type ("number", "integer" or
"choice"), default, and min and max (numbers) or choices. What `tissuebench models` prints.)");
}

}  // namespace tb::python
