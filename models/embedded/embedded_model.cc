#include "embedded_model.h"

#include "coarse_embedded.h"

namespace tb {

ModelInfo embedded_model_info() {
  std::vector<ParameterSpec> specs;
  for (ParameterSpec& s : elastic_solve_parameters("coarse_", "direct", "ic")) {
    s.description = "coarse mesh: " + s.description;
    specs.push_back(std::move(s));
  }
  ModelInfo m;
  m.name = "embedded";
  m.description =
      "Coarse linear FEM; every fine-surface vertex follows it by barycentric weights, no PBD (SOFA's barycentric "
      "mapping)";
  m.parameters = specs;
  m.create = [] { return make_coarse_embedded("embedded"); };
  m.loads = {LoadKind::PointForce, LoadKind::SurfaceTraction, LoadKind::BodyForce};
  describe_coarse_fem(m);
  return m;
}

}  // namespace tb
