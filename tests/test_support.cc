#include "test_support.h"

#include <algorithm>
#include <array>
#include <map>
#include <memory>
#include <tuple>

#include "cube_generator.h"
#include "hybrid_builder.h"
#include "mesh_recipe.h"
#include "scenario.h"
#include "shapes.h"
#include "tetgen_driver.h"

namespace tb::testing {

void step_until_reactions_settle(Model& model, const FrameLoads& frame, int max_more) {
  model.step(frame);
  for (int k = 0; k < max_more; ++k) {
    const std::vector<Eigen::Vector3d> before = *model.reaction_forces();
    model.step(frame);
    double change = 0, size = 0;
    for (size_t t = 0; t < before.size(); ++t) {
      change += (before[t] - (*model.reaction_forces())[t]).norm();
      size += before[t].norm();
    }
    if (change <= 1e-12 * size) break;
  }
}

std::unique_ptr<Model> set_up_model(const std::string& name, const HybridMesh& mesh, const SupportBox& support,
                                    const nlohmann::json& parameters, const std::vector<Load>& loads) {
  const ModelInfo& info = find_model(name);
  Problem p{&mesh, Material{}, LoadCase{support, loads, {}}, resolve_parameters(info.parameters, parameters, name), Points()};
  auto m = info.create();
  m->setup(p);
  return m;
}

std::unique_ptr<ElasticSolve> make_solve(const ElasticBody& body, const nlohmann::json& given,
                                         const TetMesh* coarse_space) {
  return make_elastic_solve(body, resolve_parameters(elastic_solve_parameters("", "direct", "ic"), given, "test"), "",
                            {coarse_space});
}

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

const HybridMesh& shape_mesh(const std::string& shape) {
  static std::map<std::string, std::unique_ptr<HybridMesh>> cache;
  auto& m = cache[shape];
  if (!m) {
    HybridBuildOptions o;
    o.fine_tetgen.radius_edge_ratio = 1.414;
    o.target_coarse_nodes = 120;
    m = std::make_unique<HybridMesh>(build_hybrid_from_surface(make_shape_surface({shape, 12}), o, shape));
  }
  return *m;
}

TetMesh box_mesh(double lx, double ly, double lz, int nx, int ny, int nz, double max_volume) {
  SurfaceMesh s = make_cube_surface({1.0, 1.0, nx, ny, nz});
  s.V.col(0) = (s.V.col(0).array() + 0.5) * lx;  // [0, lx]
  s.V.col(1) = (s.V.col(1).array() + 0.5) * ly;
  s.V.col(2) *= lz;
  TetgenOptions o;
  o.max_volume = max_volume;
  return tetrahedralize_surface(s, o, "box");
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
