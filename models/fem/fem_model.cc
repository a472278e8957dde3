#include "fem_model.h"

#include "elastic_solve.h"
#include "fine_fem.h"

namespace tb {

ModelInfo fem_model_info() {
  ModelInfo m;
  m.name = "fem";
  m.description = "Linear FEM on the fine tet volume (P1, deal.II assembly); the accuracy reference";
  m.parameters = elastic_solve_parameters("", "direct", "two_level");
  m.create = [] {
    return make_fine_fem("fem", [](const ElasticBody& body, const Problem& p) {
      check_elastic_solve_takes_tools("fem", p.parameters, "", p.load_case);
      // The two-level preconditioner's coarse space is the scenario's coarse (hybrid) mesh.
      const TetMesh& coarse = p.mesh->coarse_volume;
      return make_elastic_solve(body, p.parameters, "", {coarse.T.rows() ? &coarse : nullptr});
    });
  };
  describe_fine_fem(m);
  m.check_case = [](const Parameters& p, const LoadCase& load_case) {
    check_elastic_solve_takes_tools("fem", p, "", load_case);
  };
  return m;
}

}  // namespace tb
