// Every model, listed explicitly in one place (docs/extending.md: models are
// registered from one function, not by static initialisers). Adding a variant: one
// folder under models/, one line here, one scenario entry.
#include <sstream>
#include <stdexcept>

#include "condensed/condensed_model.h"
#include "embedded/embedded_model.h"
#include "fem/fem_model.h"
#include "fem_distributed/fem_distributed_model.h"
#include "fem_dynamic/fem_dynamic_model.h"
#include "hybrid/hybrid_model.h"
#include "model.h"
#include "pbd/pbd_model.h"
#include "pd/pd_model.h"
#include "vbd/vbd_model.h"
#include "xpbd_neo/xpbd_neo_model.h"

namespace tb {

const std::vector<ModelInfo>& registered_models() {
  static const std::vector<ModelInfo> models = [] {
    std::vector<ModelInfo> list = {
        fem_model_info(),       pbd_model_info(),      hybrid_model_info(),
        condensed_model_info(), embedded_model_info(), fem_distributed_model_info(), fem_dynamic_model_info(),
        vbd_model_info(),       xpbd_neo_model_info(),   pd_model_info(),
    };
    validate_registry(list);
    return list;
  }();
  return models;
}

void validate_registry(const std::vector<ModelInfo>& models) {
  for (size_t i = 0; i < models.size(); ++i) {
    const std::string& name = models[i].name;
    const bool valid = !name.empty() && name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") ==
                                            std::string::npos;
    if (!valid)
      throw std::logic_error("model name '" + name +
                             "' (models/registry.cc): use lower-case letters, digits and '_' only; it names result "
                             "folders and test cases");
    for (size_t j = 0; j < i; ++j)
      if (models[j].name == name) throw std::logic_error("model name '" + name + "' registered twice (models/registry.cc)");
  }
}

bool ModelInfo::takes(LoadKind kind) const {
  for (LoadKind k : loads)
    if (k == kind) return true;
  return false;
}

bool ModelInfo::takes(ToolKind kind) const {
  for (ToolKind k : tools)
    if (k == kind) return true;
  return false;
}

namespace {

template <class Kind>
[[noreturn]] void refuse(const ModelInfo& model, Kind kind, const std::string& key, const std::vector<Kind>& takes,
                         const char* what) {
  std::string list;
  for (Kind k : takes) list += (list.empty() ? "" : ", ") + std::string(name(k));
  throw std::invalid_argument("model '" + model.name + "' does not take " + name(kind) + " " + what + " (" + key +
                              "); it takes " + (list.empty() ? "none" : list));
}

}  // namespace

void check_supported(const ModelInfo& model, const LoadCase& load_case) {
  for (const Load& load : load_case.loads)
    if (!model.takes(load.kind)) refuse(model, load.kind, load.key, model.loads, "loads");
  for (const Tool& tool : load_case.tools)
    if (!model.takes(tool.kind)) refuse(model, tool.kind, tool.key, model.tools, "tools");
}

void check_supported(const ModelInfo& model, const Parameters& parameters, const LoadCase& load_case) {
  check_supported(model, load_case);
  if (model.check_case) model.check_case(parameters, load_case);
}

const ModelInfo& find_model(const std::string& name) {
  std::ostringstream known;
  for (const auto& m : registered_models()) {
    if (m.name == name) return m;
    known << (known.tellp() > 0 ? ", " : "") << m.name;
  }
  throw std::invalid_argument("unknown model '" + name + "' (registered: " + known.str() + ")");
}

}  // namespace tb
