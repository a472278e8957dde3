#include "test_support.h"

#include <map>
#include <memory>
#include <tuple>

#include "mesh_recipe.h"
#include "scenario.h"

namespace tb::testing {

const HybridMesh& scenario_mesh(const std::string& name, bool with_fine_volume, bool symmetric_fine_volume) {
  static std::map<std::tuple<std::string, bool, bool>, std::unique_ptr<HybridMesh>> cache;
  auto& m = cache[{name, with_fine_volume, symmetric_fine_volume}];
  if (!m) {
    const Experiment e = load_experiment(std::string(TB_SOURCE_DIR) + "/experiments/scenarios/" + name + ".json");
    MeshRecipe r = e.scenarios.at(0).mesh;
    r.build_fine_volume = with_fine_volume;
    if (symmetric_fine_volume) r.symmetric_fine_volume = true;
    MeshReport report;
    m = std::make_unique<HybridMesh>(build_mesh(r, report));
  }
  return *m;
}

double mirror_asymmetry(const Points& V, const Eigen::VectorXd& values, int axis, double parity) {
  double worst = 0;
  for (Eigen::Index v = 0; v < V.rows(); ++v) {
    Eigen::RowVector3d m = V.row(v);
    m(axis) = -m(axis);
    Eigen::Index w;
    (V.rowwise() - m).rowwise().norm().minCoeff(&w);
    worst = std::max(worst, std::abs(values(v) - parity * values(w)));
  }
  return worst;
}

}  // namespace tb::testing
