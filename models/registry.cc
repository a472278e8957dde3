// Every model, listed explicitly in one place (STYLE.md 7). Adding a variant: one
// folder under models/, one line here, one scenario entry.
#include <sstream>
#include <stdexcept>

#include "condensed/condensed_model.h"
#include "embedded/embedded_model.h"
#include "fem/fem_model.h"
#include "fem_distributed/fem_distributed_model.h"
#include "hybrid/hybrid_model.h"
#include "model.h"
#include "pbd/pbd_model.h"

namespace tb {

const std::vector<ModelInfo>& registered_models() {
  static const std::vector<ModelInfo> models = {
      fem_model_info(),       pbd_model_info(),      hybrid_model_info(),
      condensed_model_info(), embedded_model_info(), fem_distributed_model_info(),
  };
  return models;
}

const ModelInfo& find_model(const std::string& name) {
  std::ostringstream known;
  for (const auto& m : registered_models()) {
    if (m.name == name) return m;
    known << (known.tellp() > 0 ? ", " : "") << m.name;
  }
  throw std::invalid_argument("unknown model '" + name + "' (registered: " + known.str() + ")");
}

void require_point_load(const PointLoad& load, const char* model) {
  if (load.disc_radius == 0) return;
  std::ostringstream msg;
  msg << model << ": load.disc_radius " << load.disc_radius
      << " asks for a disc load, which this model does not support; use disc_radius 0 (the paper's point load)";
  throw std::invalid_argument(msg.str());
}

}  // namespace tb
