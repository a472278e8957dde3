#include "pd_model.h"

#include "fine_fem.h"
#include "pd_solve.h"

namespace tb {

ModelInfo pd_model_info() {
  ModelInfo m;
  m.name = "pd";
  m.description =
      "Projective Dynamics on the fine tet volume: each frame one implicit-Euler step, the global matrix M/h^2 + "
      "sum w V G^T G factorised once; local/global iterations on the arap_volume law (Bouaziz et al. 2014) or L-BFGS "
      "with a line search on any law (Liu, Bouaziz and Kavan 2017; default neo_hookean)";
  m.dynamic = true;
  m.parameters = pd_parameters();
  m.create = [] {
    return make_fine_fem("pd", [](const ElasticBody& body, const Problem& p) {
      return make_pd_solve(body, pd_settings(p.parameters));
    });
  };
  describe_fine_fem(m);
  m.tools = {ToolKind::Grasp, ToolKind::BondedPlate, ToolKind::SlidingPlate, ToolKind::Sphere};
  m.tools_how = "the fine-volume nodes of the held surface vertices: their held components are set to the tool's "
                "position each frame (Dirichlet rows of the global matrix); a sliding plate holds the normal "
                "component only; a sphere: the linearised gaps of the surface nodes in it as constraints of the global "
                "step (multipliers by a Schur complement on A's factor; L-BFGS history dropped while any is in contact)";
  m.reactions = "f - f_int(x) - m (x - x_n - h v_n) / h^2 at the held dofs, summed per tool and over the support (the "
                "implicit-Euler balance of the held nodes); a sphere: the normal part of that balance at its contact "
                "nodes";
  return m;
}

}  // namespace tb
