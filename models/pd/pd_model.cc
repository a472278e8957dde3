#include "pd_model.h"

#include "pd_solve.h"
#include "realtime_volume.h"

namespace tb {

ModelInfo pd_model_info() {
  ModelInfo m;
  m.name = "pd";
  m.description =
      "Projective Dynamics on the fine tet volume (or the coarse one with the fine surface embedded: volume): each "
      "frame one implicit-Euler step, the global matrix M/h^2 + "
      "sum w V G^T G factorised once; local/global iterations on the arap_volume law (Bouaziz et al. 2014) or L-BFGS "
      "with a line search on any law (Liu, Bouaziz and Kavan 2017; default neo_hookean)";
  m.dynamic = true;
  m.parameters = pd_parameters();
  m.parameters.push_back(volume_parameter());
  m.create = [] {
    return make_on_volume(
        "pd", [](const ElasticBody& body, const Problem& p) { return make_pd_solve(body, pd_settings(p.parameters)); });
  };
  describe_on_volume(
      m,
      "their held components are set to the tool's "
      "position each frame (Dirichlet rows of the global matrix); a sliding plate holds the normal "
      "component only",
      "f - f_int(x) - m (x - x_n - h v_n) / h^2 at the held dofs, summed per tool and over the support (the "
      "implicit-Euler balance of the held nodes)",
      "the linearised gaps of the surface nodes in it as constraints of the global step (multipliers by a Schur "
      "complement on A's factor; L-BFGS history dropped while any is in contact)",
      "each pad's spring k_i on the global matrix's diagonal beside m / h^2 (prefactorised with it), its pull in "
      "the inertial target");
  return m;
}

}  // namespace tb
